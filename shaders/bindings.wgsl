// Layouts shared by the passes. Rust twins: engine/src/render/gpu_types.rs.

// Per-frame view data (uniform).
struct View {
    // Clip from world, reversed Z (near → 1, far → 0).
    clip_from_world: mat4x4<f32>,
    // World from clip, for position reconstruction from depth.
    world_from_clip: mat4x4<f32>,
    // Camera position in metres (xyz), exposure multiplier (w).
    position_exposure: vec4<f32>,
    // Target size in pixels (xy) and its reciprocal (zw).
    viewport: vec4<f32>,
    // Pre-exposed background luminance (rgb), unused (w).
    background: vec4<f32>,
    // Number of directional, point and spot lights; total.
    light_counts: vec4<u32>,
    // How many of each kind cast shadows; they come first within their kind.
    shadowed_counts: vec4<u32>,
    // Camera forward direction (xyz): view depth for cascade selection.
    forward: vec4<f32>,
    // Geometric specular anti-aliasing: screen scale c σ² (x), threshold κ (y); this
    // frame's camera jitter in pixels (zw).
    antialiasing: vec4<f32>,
}

// One drawn object (storage buffer, indexed by instance_index).
struct Instance {
    world_from_local: mat4x4<f32>,
    // Inverse-transpose of the upper 3×3, as three columns.
    normal_matrix_0: vec4<f32>,
    normal_matrix_1: vec4<f32>,
    normal_matrix_2: vec4<f32>,
    // Linear base colour (rgb) and alpha.
    base_color: vec4<f32>,
    // Pre-exposed emissive luminance (rgb), ambient occlusion (w).
    emissive_occlusion: vec4<f32>,
    // Metallic, perceptual roughness, specular level, receives shadows (1 or 0).
    params: vec4<f32>,
}

// One light (storage buffer): directional lights first, then point, then spot.
struct Light {
    // Position in metres (point and spot).
    position: vec4<f32>,
    // Unit vector towards the light (directional), or the spot's axis pointing away
    // from the light (spot).
    direction: vec4<f32>,
    // Colour × intensity × exposure: lux for directional, candela for point and spot
    // (rgb); 1/range² (w, 0 = unlimited).
    color_inv_range2: vec4<f32>,
    // Spot cone scale and offset (xy).
    spot: vec4<f32>,
    // Shadow: first shadow view (−1: none), view count, light size (directional: tan of
    // the angular radius; point and spot: radius in m), cascade blend fraction.
    shadow: vec4<f32>,
    // Directional: camera distance (m) where each of up to 4 cascades ends.
    cascade_far: vec4<f32>,
    // Shadow biases in texels: depth, slope, normal.
    shadow_bias: vec4<f32>,
}

// The part of a light its unshadowed loop reads (48 bytes): position (m, xyz) and
// 1/range² (w); colour × intensity × exposure (rgb) and spot cone scale (w); direction
// (xyz) and spot cone offset (w).
struct PunctualLight {
    position_inv_range2: vec4<f32>,
    color_spot_scale: vec4<f32>,
    direction_spot_offset: vec4<f32>,
}

fn punctual_of(light: Light) -> PunctualLight {
    return PunctualLight(
        vec4<f32>(light.position.xyz, light.color_inv_range2.w),
        vec4<f32>(light.color_inv_range2.rgb, light.spot.x),
        vec4<f32>(light.direction.xyz, light.spot.y),
    );
}

// One shadow view in the atlas.
struct ShadowView {
    clip_from_world: mat4x4<f32>,
    // Atlas rectangle in UV: offset (xy), scale (zw).
    rect: vec4<f32>,
    // Texel world size (ortho: m; perspective: m per m of distance), perspective (1/0),
    // near (perspective, m) or depth range (ortho, m), far (perspective, m).
    texel: vec4<f32>,
}

// The environment, pre-exposed (× intensity × exposure).
struct EnvironmentUniform {
    // Radiance spherical harmonics, bands 0–2 (rgb).
    sh: array<vec4<f32>, 9>,
    // Scale of cube samples, rotation about +Y (rad), highest prefiltered mip, background mip.
    params: vec4<f32>,
    // Uniform environments: radiance (rgb).
    uniform_radiance: vec4<f32>,
}

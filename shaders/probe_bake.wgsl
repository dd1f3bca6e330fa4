// Bakes the irradiance volume's probe records (probe_capture.wgsl) into the two atlases the
// lighting pass samples with bilinear filtering (volume_lookup.wgsl), after each capture
// pass: per probe, a 6² octahedral map of irradiance (pre-exposed) and an 8²
// map of the distance moments (E[d], E[d²]), each inside a one-texel border that repeats
// its edge (DDGI's layout, Majercik et al. 2019). One workgroup per probe.
#import common
#import encoding
#import irradiance_volume

struct BakeParams {
    // Probes, tiles per atlas row, vec4s per record, unused.
    probes_tiles_stride: vec4<u32>,
    // Exposure the irradiance is multiplied by, the largest stored distance (m), unused ×2.
    exposure_range: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: BakeParams;
@group(0) @binding(1) var<storage, read> probes: array<vec4<f32>>;
@group(0) @binding(2) var irradiance_atlas: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var moment_atlas: texture_storage_2d<rgba16float, write>;

const F16_MAX: f32 = 65504.0;

// The texel of a side² map that border texel `local` (0..side + 2) repeats.
fn inner_texel(local: vec2<u32>, side: u32) -> vec2<u32> {
    return vec2<u32>(clamp(vec2<i32>(local) - vec2<i32>(1), vec2<i32>(0), vec2<i32>(i32(side) - 1)));
}

@compute @workgroup_size(10, 10)
fn cs_bake(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let probe = group.x;
    let tiles = params.probes_tiles_stride.y;
    let tile = vec2<u32>(probe % tiles, probe / tiles);
    let base = probe * params.probes_tiles_stride.z;
    let range = params.exposure_range.y;

    let m_texel = inner_texel(local.xy, OCT_SIDE);
    let m = probes[base + IRRADIANCE_TEXELS + m_texel.y * OCT_SIDE + m_texel.x];
    // A direction no captured pixel reached counts as open as far as a moment reaches.
    var moments = vec2<f32>(range, range * range);
    if m.z > 0.0 {
        moments = m.xy / m.z;
    }
    textureStore(moment_atlas, tile * (OCT_SIDE + 2u) + local.xy, vec4<f32>(moments, 0.0, 1.0));

    if all(local.xy < vec2<u32>(IRRADIANCE_SIDE + 2u)) {
        let texel = inner_texel(local.xy, IRRADIANCE_SIDE);
        var e = probes[base + texel.y * IRRADIANCE_SIDE + texel.x].xyz * params.exposure_range.x;
        e = select(e, vec3<f32>(0.0), e != e);
        e = clamp(e, vec3<f32>(0.0), vec3<f32>(F16_MAX));
        textureStore(irradiance_atlas, tile * (IRRADIANCE_SIDE + 2u) + local.xy, vec4<f32>(e, 1.0));
    }
}

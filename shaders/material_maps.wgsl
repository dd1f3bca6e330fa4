// A textured material's maps (engine/src/render/material_maps.rs, `BINDINGS`): group 1 of
// the G-buffer's textured variants and of the shadow pass's alpha-masked casters, and
// the texture coordinates of each slot.

// Texture slots, in binding order.
const SLOT_BASE: u32 = 0u;
const SLOT_METALLIC_ROUGHNESS: u32 = 1u;
const SLOT_NORMAL: u32 = 2u;
const SLOT_OCCLUSION: u32 = 3u;
const SLOT_EMISSIVE: u32 = 4u;

struct Maps {
    // Per slot, the rows of its 2 × 3 texture-coordinate transform (xyz of two vec4s).
    transforms: array<vec4<f32>, 10>,
    // Per slot, the texture coordinate set (0 or 1); the emissive slot's is in `extra.x`.
    uv_sets: vec4<u32>,
    // x: emissive coordinate set; y: 1 when a normal map is bound.
    extra: vec4<u32>,
    // x: normal scale; y: occlusion strength; z: alpha cutoff (< 0: opaque).
    params: vec4<f32>,
}

@group(1) @binding(0) var<uniform> maps: Maps;
@group(1) @binding(1) var base_color_map: texture_2d<f32>;
@group(1) @binding(2) var metallic_roughness_map: texture_2d<f32>;
@group(1) @binding(3) var normal_map: texture_2d<f32>;
@group(1) @binding(4) var occlusion_map: texture_2d<f32>;
@group(1) @binding(5) var emissive_map: texture_2d<f32>;
@group(1) @binding(6) var base_color_sampler: sampler;
@group(1) @binding(7) var metallic_roughness_sampler: sampler;
@group(1) @binding(8) var normal_sampler: sampler;
@group(1) @binding(9) var occlusion_sampler: sampler;
@group(1) @binding(10) var emissive_sampler: sampler;

// The coordinates of `slot` after its set choice and KHR_texture_transform.
fn slot_uv(slot: u32, uv_set: u32, uv0: vec2<f32>, uv1: vec2<f32>) -> vec2<f32> {
    let uv = vec3<f32>(select(uv0, uv1, uv_set == 1u), 1.0);
    return vec2<f32>(dot(maps.transforms[slot * 2u].xyz, uv), dot(maps.transforms[slot * 2u + 1u].xyz, uv));
}

// The base colour map's texel at the base slot's coordinates.
fn base_color_texel(uv0: vec2<f32>, uv1: vec2<f32>) -> vec4<f32> {
    return textureSample(base_color_map, base_color_sampler, slot_uv(SLOT_BASE, maps.uv_sets.x, uv0, uv1));
}

// Whether a masked material's coverage `alpha` (base colour factor × vertex colour ×
// texel) falls below its cutoff (glTF `alphaMode: MASK`): the fragment is not drawn and
// casts no shadow.
fn masked_out(alpha: f32) -> bool {
    return maps.params.z >= 0.0 && alpha < maps.params.z;
}

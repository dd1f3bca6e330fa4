// A textured material's maps (engine/src/render/gpu_material_maps.rs, `BINDINGS`) and the
// texture coordinates of each slot. They are group MAPS_GROUP, a header constant
// (`material_maps::group_def`): group 1 of the G-buffer's textured variants and of the
// shadow pass's alpha-masked casters, group 4 of the transparent and layers passes.
// The extension units (bindings 11 to 18) and their sampling are in
// extension_units.wgsl, which the passes that read them import.
#import common
#import brdf

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
    // x: normal scale; y: occlusion strength; z: alpha cutoff (< 0: opaque); w: 1 where
    // blended (the transparent pass takes the base alpha as coverage).
    params: vec4<f32>,
    // Transmissive materials (transparent pass): x: transmission factor (0: none); y:
    // index of refraction; z: thickness (world m, 0: thin-walled); w: attenuation
    // distance (m, ∞: no absorption).
    transmission: vec4<f32>,
    // rgb: the attenuation colour; w: the dispersion (20 / Abbe number, 0: none).
    attenuation: vec4<f32>,
    // Clearcoated materials (layers pass): x: the coat's factor (0: none); y: its
    // perceptual roughness (clamped).
    clearcoat: vec4<f32>,
    // Materials with a sheen (layers pass): rgb: its colour; w: its perceptual roughness
    // (clamped).
    sheen: vec4<f32>,
    // Anisotropic materials (layers pass): x: the strength (0..1, 0: none); y, z: the
    // cosine and sine of the direction's angle from the tangent towards the bitangent.
    anisotropy: vec4<f32>,
    // Relit bases (layers pass): rgb: the dielectric F0's tint (1: untinted).
    specular_tint: vec4<f32>,
    // Relit bases: the iridescent film: x: factor (0: none); y: index of refraction; z:
    // thickness (nm).
    film: vec4<f32>,
    // Relit bases: the diffuse transmission: rgb: its colour; w: its factor (0: none).
    translucency: vec4<f32>,
    // The extension textures (engine/src/scene/extension_maps.rs): per unit, the rows of
    // its 2 × 3 texture-coordinate transform.
    extension_transforms: array<vec4<f32>, 8>,
    // Per unit, its texture coordinate set (0 or 1).
    extension_uv_sets: vec4<u32>,
    // Per property (PROPERTY_*), four to a vec4, its unit (EXTENSION_UNITS: none).
    extension_units: array<vec4<u32>, 4>,
    // x: the film's thickness (nm) where its thickness texture reads 0; y: how many
    // units are bound; z: the coat normal map's scale.
    extension_params: vec4<f32>,
}

@group(MAPS_GROUP) @binding(0) var<uniform> maps: Maps;
@group(MAPS_GROUP) @binding(1) var base_color_map: texture_2d<f32>;
@group(MAPS_GROUP) @binding(2) var metallic_roughness_map: texture_2d<f32>;
@group(MAPS_GROUP) @binding(3) var normal_map: texture_2d<f32>;
@group(MAPS_GROUP) @binding(4) var occlusion_map: texture_2d<f32>;
@group(MAPS_GROUP) @binding(5) var emissive_map: texture_2d<f32>;
@group(MAPS_GROUP) @binding(6) var base_color_sampler: sampler;
@group(MAPS_GROUP) @binding(7) var metallic_roughness_sampler: sampler;
@group(MAPS_GROUP) @binding(8) var normal_sampler: sampler;
@group(MAPS_GROUP) @binding(9) var occlusion_sampler: sampler;
@group(MAPS_GROUP) @binding(10) var emissive_sampler: sampler;
// The extension textures' properties (EXTENSION_TEXTURES in
// engine/src/scene/extension_maps.rs), each scaling its layer's factor by one channel.
const EXTENSION_UNITS: u32 = 4u;
const PROPERTY_TRANSMISSION: u32 = 0u;
const PROPERTY_THICKNESS: u32 = 1u;
const PROPERTY_CLEARCOAT: u32 = 2u;
const PROPERTY_CLEARCOAT_ROUGHNESS: u32 = 3u;
const PROPERTY_SHEEN_COLOR: u32 = 4u;
const PROPERTY_SHEEN_ROUGHNESS: u32 = 5u;
const PROPERTY_ANISOTROPY: u32 = 6u;
const PROPERTY_IRIDESCENCE: u32 = 7u;
const PROPERTY_IRIDESCENCE_THICKNESS: u32 = 8u;
const PROPERTY_DIFFUSE_TRANSMISSION: u32 = 9u;
const PROPERTY_DIFFUSE_TRANSMISSION_COLOR: u32 = 10u;
const PROPERTY_SPECULAR: u32 = 11u;
const PROPERTY_SPECULAR_COLOR: u32 = 12u;
const PROPERTY_CLEARCOAT_NORMAL: u32 = 13u;

// The extension units' texels at one fragment (`extension_texels`, extension_units.wgsl);
// the last entry is white (no texture).
struct ExtensionTexels {
    texels: array<vec4<f32>, 5>,
}

// The unit of `property` (EXTENSION_UNITS where it has no texture).
fn extension_unit(property: u32) -> u32 {
    return min(maps.extension_units[property / 4u][property % 4u], EXTENSION_UNITS);
}

// The texel that scales `property`'s factor (white where it has no texture).
fn extension_texel(t: ExtensionTexels, property: u32) -> vec4<f32> {
    var texels = t.texels;
    return texels[extension_unit(property)];
}

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

// A textured material at one fragment, after its maps (every slot but the base colour,
// which the caller samples first, for its alpha test or its coverage).
struct MappedMaterial {
    // Shading normal (world, unit): the geometric one bent by the normal map.
    n: vec3<f32>,
    // The filtered normal-map texel's own length, before the normal scale (1 without one).
    normal_length: f32,
    // Metallic (0..1) and perceptual roughness (clamped).
    metallic: f32,
    roughness: f32,
    // Occlusion of indirect light (0 occluded .. 1 open).
    occlusion: f32,
    // Pre-exposed emitted luminance (cd/m² × exposure): the factor × the texel.
    emissive: vec3<f32>,
}

// The material's maps at (uv0, uv1) for a fragment with geometric normal `ng` (flipped for
// back faces of double-sided materials) and world tangent `tangent` (w: the bitangent's
// sign); `params` and `emissive_occlusion` are the instance's factors (metallic,
// perceptual roughness, specular level, receives shadows; emissive and occlusion).
fn mapped_material(uv0: vec2<f32>, uv1: vec2<f32>, ng: vec3<f32>, tangent: vec4<f32>,
                   params: vec4<f32>, emissive_occlusion: vec4<f32>) -> MappedMaterial {
    let mr = textureSample(metallic_roughness_map, metallic_roughness_sampler,
                           slot_uv(SLOT_METALLIC_ROUGHNESS, maps.uv_sets.y, uv0, uv1));
    let occlusion_texel = textureSample(occlusion_map, occlusion_sampler,
                                        slot_uv(SLOT_OCCLUSION, maps.uv_sets.w, uv0, uv1)).r;
    let emissive_texel = textureSample(emissive_map, emissive_sampler,
                                       slot_uv(SLOT_EMISSIVE, maps.extra.x, uv0, uv1)).rgb;
    let normal_texel = textureSample(normal_map, normal_sampler,
                                     slot_uv(SLOT_NORMAL, maps.uv_sets.z, uv0, uv1)).xyz;

    var out: MappedMaterial;
    // glTF: bitangent = cross(normal, tangent) × w.
    out.n = ng;
    out.normal_length = 1.0;
    if maps.extra.y != 0u {
        out.n = normal_from_map(ng, tangent, normal_texel, maps.params.x);
        out.normal_length = length(normal_texel * 2.0 - 1.0);
    }
    out.metallic = clamp(params.x * mr.b, 0.0, 1.0);
    out.roughness = clamp_perceptual_roughness(params.y * mr.g);
    out.occlusion = emissive_occlusion.w * (1.0 + maps.params.y * (occlusion_texel - 1.0));
    out.emissive = emissive_occlusion.rgb * emissive_texel;
    return out;
}

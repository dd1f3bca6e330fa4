// The material maps' extension units (engine/src/scene/extension_maps.rs,
// `ExtensionMaps::units`): up to four textures, each with its sampler, coordinate set and
// transform, bound at MAPS_GROUP beside the maps (material_maps.wgsl). Imported by the
// passes that read the extension textures (layers, transparent); on adapters whose
// layout has no room for them, `extension_units_unbound.wgsl` replaces this module
// (`material_maps::unit_defs`).
#import material_maps

@group(MAPS_GROUP) @binding(11) var extension_map_0: texture_2d<f32>;
@group(MAPS_GROUP) @binding(12) var extension_map_1: texture_2d<f32>;
@group(MAPS_GROUP) @binding(13) var extension_map_2: texture_2d<f32>;
@group(MAPS_GROUP) @binding(14) var extension_map_3: texture_2d<f32>;
@group(MAPS_GROUP) @binding(15) var extension_sampler_0: sampler;
@group(MAPS_GROUP) @binding(16) var extension_sampler_1: sampler;
@group(MAPS_GROUP) @binding(17) var extension_sampler_2: sampler;
@group(MAPS_GROUP) @binding(18) var extension_sampler_3: sampler;

// The coordinates of extension unit `unit` after its set choice and transform.
fn extension_uv(unit: u32, uv0: vec2<f32>, uv1: vec2<f32>) -> vec2<f32> {
    let uv = vec3<f32>(select(uv0, uv1, maps.extension_uv_sets[unit] == 1u), 1.0);
    return vec2<f32>(dot(maps.extension_transforms[unit * 2u].xyz, uv),
                     dot(maps.extension_transforms[unit * 2u + 1u].xyz, uv));
}

// Every bound extension unit sampled at (uv0, uv1); unbound units read white. Call it in
// uniform control flow (before any discard); the unit count is uniform, so the branches
// are too.
fn extension_texels(uv0: vec2<f32>, uv1: vec2<f32>) -> ExtensionTexels {
    var out: ExtensionTexels;
    for (var k = 0u; k <= EXTENSION_UNITS; k++) {
        out.texels[k] = vec4<f32>(1.0);
    }
    let bound = maps.extension_params.y;
    if bound > 0.5 {
        out.texels[0] = textureSample(extension_map_0, extension_sampler_0, extension_uv(0u, uv0, uv1));
    }
    if bound > 1.5 {
        out.texels[1] = textureSample(extension_map_1, extension_sampler_1, extension_uv(1u, uv0, uv1));
    }
    if bound > 2.5 {
        out.texels[2] = textureSample(extension_map_2, extension_sampler_2, extension_uv(2u, uv0, uv1));
    }
    if bound > 3.5 {
        out.texels[3] = textureSample(extension_map_3, extension_sampler_3, extension_uv(3u, uv0, uv1));
    }
    return out;
}

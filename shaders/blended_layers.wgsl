// The layers over a blended or transmissive surface (engine/src/render/transparent/mod.rs,
// the variants of batches with a sheen or a clearcoat): its sheen, then its coat, over
// the base's light (a transmissive one's transmitted light included) in the same fragment (layer_light.wgsl, as the layers pass draws them over an opaque
// surface). The header declares SHEEN_LOBE and RELIT_BASE as private switches, not
// constants: the base is lit with the batch's own lobe, then each layer turns the
// switches to its own. Header constants BLENDED_SHEEN and BLENDED_COAT compile in only
// the layers the variant's batches have. Without layers the pass imports
// blended_layers_none.wgsl instead.
#import common
#import mesh_vertex
#import material_maps
#import extension_units
#import surface_light
#import layer_light

// The light leaving a blended or transmissive fragment `in` whose base, lit at `base`, leaves
// `base_light` (emission included): L_coat + w_coat · (L_sheen + w_sheen · base_light),
// the layers on the mesh's interpolated normal `layer_n`.
fn over_layers(ext: ExtensionTexels, in: TexturedOutput, base: ShadingPoint, layer_n: vec3<f32>,
               base_light: vec3<f32>) -> vec3<f32> {
    var p = base;
    p.n = layer_n;
    var light = base_light;
    RELIT_BASE = false;
    if BLENDED_SHEEN && any(maps.sheen.rgb > vec3<f32>(0.0)) {
        SHEEN_LOBE = true;
        let sheen = sheen_layer(ext, p);
        SHEEN_LOBE = false;
        light = sheen.light + sheen.through * light;
    }
    if BLENDED_COAT && maps.clearcoat.x > 0.0 {
        let coat = coat_layer(ext, p, in.world_tangent);
        light = coat.light + coat.through * light;
    }
    return light;
}

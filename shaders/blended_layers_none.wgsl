// blended_layers.wgsl for the transparent pass's variants without layers (no blended
// batch drawn by them has a sheen or a clearcoat): the base's light is the surface's.
#import mesh_vertex
#import material_maps
#import extension_units
#import surface_light

fn over_layers(ext: ExtensionTexels, in: TexturedOutput, base: ShadingPoint, layer_n: vec3<f32>,
               base_light: vec3<f32>) -> vec3<f32> {
    return base_light;
}

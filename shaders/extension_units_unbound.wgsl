// extension_units.wgsl for a maps layout without the units (`material_maps::CORE_BINDINGS`,
// adapters with too few textures per stage): every extension texel reads white, so
// every factor applies as it is.
#import material_maps

// White for every unit: no extension texture is sampled.
fn extension_texels(uv0: vec2<f32>, uv1: vec2<f32>) -> ExtensionTexels {
    var out: ExtensionTexels;
    for (var k = 0u; k <= EXTENSION_UNITS; k++) {
        out.texels[k] = vec4<f32>(1.0);
    }
    return out;
}

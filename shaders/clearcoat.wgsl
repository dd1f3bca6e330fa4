// The clearcoat layer (KHR_materials_clearcoat): the WGSL twins of engine/src/shading/clearcoat.rs,
// with the same names. L = factor · L_coat + (1 − factor · E_coat(n_c·v)) · L_base.
#import brdf

// The coat's specular level: F0 = 0.04, a dielectric of index 1.5.
const CLEARCOAT_SPECULAR_LEVEL: f32 = 0.5;

// The coat lobe's directional albedo: (F0·A + B) × compensation, from the split-sum table's
// (A, B) at (n_c·v, coat roughness).
fn clearcoat_albedo(dfg: vec2<f32>, compensation: f32) -> f32 {
    let f0 = dielectric_f0(CLEARCOAT_SPECULAR_LEVEL);
    return clamp((f0 * dfg.x + dfg.y) * compensation, 0.0, 1.0);
}

// The fraction of the base's light that leaves through the coat: 1 − factor · E_coat
// (NaN factor: no coat).
fn clearcoat_base_weight(factor: f32, coat_albedo: f32) -> f32 {
    var f = clamp(factor, 0.0, 1.0);
    if !(factor == factor) {
        f = 0.0;
    }
    return 1.0 - f * clamp(coat_albedo, 0.0, 1.0);
}

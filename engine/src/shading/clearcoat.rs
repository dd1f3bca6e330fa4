//! The clearcoat layer (glTF's `KHR_materials_clearcoat`): the CPU twins of
//! `shaders/clearcoat.wgsl`, with the same names (docs/src/materials.md#clearcoat).
//!
//! A clearcoat is a thin, colourless dielectric film (index of refraction 1.5, so
//! F0 = 0.04) over the base material, with its own roughness and its own normal: the
//! mesh's interpolated normal, without the base's normal map. Light leaving the coated
//! surface is the coat's specular lobe plus the base's light, dimmed by what the coat
//! reflects:
//!
//! `L = factor · L_coat + (1 − factor · E_coat(n_c·v)) · L_base`,
//!
//! the glTF specification's layering (`fresnel_coat` mixes base and layer by the layer's
//! Fresnel weight). Where the specification and the Khronos sample renderer weight the base
//! by the coat's Fresnel at the normal, `F(n_c·v)`, Lumen uses the coat lobe's
//! directional albedo E_coat, the fraction of light the rough coat actually reflects
//! (Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks", who layer
//! by albedo): a white base under a coat then returns exactly the light it receives in a
//! white furnace, at every roughness, where the Fresnel weight loses light at grazing view
//! on a rough coat. For a mirror-smooth coat the two weights are equal.

use glam::Vec2;

/// The coat's specular level (F0 = 0.08 × level = 0.04, a dielectric of index 1.5 against
/// air), as glTF fixes it.
pub const CLEARCOAT_SPECULAR_LEVEL: f32 = 0.5;

/// The directional albedo (0..1, dimensionless) of the coat's specular lobe seen at n_c·v:
/// the split-sum table's scale and bias `dfg` = (A, B) at (n_c·v, coat roughness) make
/// `E = F0·A + B` (Karis 2013), × the lobe's multiple-scattering `compensation`
/// (1 when off).
pub fn clearcoat_albedo(dfg: Vec2, compensation: f32) -> f32 {
    let f0 = crate::shading::brdf::dielectric_f0(CLEARCOAT_SPECULAR_LEVEL);
    ((f0 * dfg.x + dfg.y) * compensation).clamp(0.0, 1.0)
}

/// The fraction (0..1) of the base's light that leaves through a coat of strength
/// `factor` (0..1, clamped; NaN is no coat) whose albedo is `coat_albedo`:
/// `1 − factor · E_coat`.
pub fn clearcoat_base_weight(factor: f32, coat_albedo: f32) -> f32 {
    let factor = if factor.is_nan() {
        0.0
    } else {
        factor.clamp(0.0, 1.0)
    };
    1.0 - factor * coat_albedo.clamp(0.0, 1.0)
}

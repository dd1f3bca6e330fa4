//! Light through transmissive surfaces and their volumes (glTF's
//! `KHR_materials_transmission`, `_volume` and `_ior`): the CPU twins of
//! `shaders/transmission.wgsl`, with the same names (docs/src/materials.md#transmission).
//!
//! The transparent pass shades a transmissive fragment as the glTF specification mixes its
//! layers: the dielectric base's diffuse lobe is scaled by 1 − transmission, and the
//! transmitted part is the opaque frame behind, seen along the refracted ray, × the base
//! colour × (1 − F) × the volume's transmittance. The refracted ray is followed for the
//! length it takes to cross a slab of the material's thickness (Snell's law), and the
//! frame is sampled where that exit point projects: exact for a slab seen by a distant
//! camera, an approximation elsewhere, as in the Khronos sample renderer and Filament.

use glam::Vec3;

/// The smallest cosine of the refracted ray against the normal that
/// [`refraction_path_m`] divides by: the path through a slab is at most 20 × its
/// thickness.
pub const MIN_COS_REFRACTED: f32 = 0.05;

/// Attenuation distances (m) from this one up (and NaN) absorb nothing.
pub const INFINITE_DISTANCE_M: f32 = 1e30;

/// The interval the index of refraction is clamped into (dimensionless).
pub const IOR_RANGE: (f32, f32) = (1.0, 10.0);

/// The index of refraction clamped into [`IOR_RANGE`]; NaN gives 1.5, glTF's default.
pub fn clamp_ior(ior: f32) -> f32 {
    if ior.is_nan() {
        1.5
    } else {
        ior.clamp(IOR_RANGE.0, IOR_RANGE.1)
    }
}

/// The unit direction of the ray refracted into a surface of unit normal `n` (facing the
/// viewer) seen from the unit direction `v` (towards the viewer), for a relative index of
/// refraction `ior` ≥ 1 (Snell's law, n₁ sin θ₁ = n₂ sin θ₂, in the vector form of
/// Glassner's "An Introduction to Ray Tracing", 1989). Entering a denser medium never
/// reflects totally.
pub fn refracted_direction(n: Vec3, v: Vec3, ior: f32) -> Vec3 {
    let eta = 1.0 / clamp_ior(ior);
    let cos_i = n.dot(v).clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    (-v * eta + n * (eta * cos_i - cos_t)).normalize_or(-n)
}

/// The length (m) of the refracted ray's path across a slab of thickness `thickness_m`
/// (measured along `n`) entered from `v`: thickness / cos θₜ, with cos θₜ kept at least
/// [`MIN_COS_REFRACTED`]. 0 for a thin-walled surface (thickness 0) or a negative or NaN
/// thickness.
pub fn refraction_path_m(n: Vec3, v: Vec3, ior: f32, thickness_m: f32) -> f32 {
    if thickness_m.is_nan() || thickness_m <= 0.0 {
        return 0.0;
    }
    let cos_t = (-refracted_direction(n, v, ior).dot(n)).max(MIN_COS_REFRACTED);
    thickness_m.min(1e6) / cos_t
}

/// The fraction of light (per RGB channel) left after `path_m` metres through a volume
/// that gives white light `attenuation_color` after `attenuation_distance_m`:
/// Beer–Lambert's law T = exp(−σ·s) with σ = −ln(c)/d, that is c^(s/d) (the
/// `KHR_materials_volume` specification). An infinite distance absorbs nothing; a
/// distance of 0 is read as 1 µm; the colour is clamped to 10⁻⁶..1, so no input makes
/// NaN. Distances of [`INFINITE_DISTANCE_M`] and more absorb nothing.
pub fn volume_transmittance(
    attenuation_color: Vec3,
    attenuation_distance_m: f32,
    path_m: f32,
) -> Vec3 {
    if path_m.is_nan()
        || path_m <= 0.0
        || attenuation_distance_m.is_nan()
        || attenuation_distance_m >= INFINITE_DISTANCE_M
    {
        return Vec3::ONE;
    }
    let s = (path_m.min(INFINITE_DISTANCE_M) / attenuation_distance_m.max(1e-6))
        .min(INFINITE_DISTANCE_M);
    let c = Vec3::select(
        attenuation_color.cmpeq(attenuation_color),
        attenuation_color,
        Vec3::ONE,
    )
    .clamp(Vec3::splat(1e-6), Vec3::ONE);
    Vec3::new(
        (c.x.log2() * s).exp2(),
        (c.y.log2() * s).exp2(),
        (c.z.log2() * s).exp2(),
    )
}

/// The indices of refraction of red, green and blue light in a material of index `ior`
/// (the green one) and dispersion `dispersion` = 20 / V, V the Abbe number
/// (`KHR_materials_dispersion`). V = (n_d − 1)/(n_F − n_C) puts the blue (F, 486 nm) and
/// red (C, 656 nm) indices (n − 1)/V apart, so each lies half of that, (n − 1) · 0.025 ·
/// dispersion, from the green one (as the Khronos sample renderer spreads them). A
/// negative or NaN dispersion is none; each index stays in [`IOR_RANGE`].
pub fn dispersion_iors(ior: f32, dispersion: f32) -> Vec3 {
    let n = clamp_ior(ior);
    let d = if dispersion.is_nan() {
        0.0
    } else {
        dispersion.clamp(0.0, 1e3)
    };
    let half = (n - 1.0) * 0.025 * d;
    Vec3::new(clamp_ior(n - half), n, clamp_ior(n + half))
}

/// The perceptual roughness with which the frame behind a rough transmissive surface is
/// blurred: the surface's own, scaled by clamp(2·ior − 2, 0, 1), so that an IOR of 1
/// (no refraction) blurs nothing and from 1.5 up the full roughness applies (the
/// Khronos glTF sample renderer's `applyIorToRoughness`).
pub fn transmission_roughness(perceptual_roughness: f32, ior: f32) -> f32 {
    let r = crate::shading::brdf::clamp_perceptual_roughness(perceptual_roughness);
    r * (2.0 * clamp_ior(ior) - 2.0).clamp(0.0, 1.0)
}

/// The mip level of the frame copy that a surface of perceptual roughness
/// `perceptual_roughness` and index `ior` samples, for a copy `width` pixels wide:
/// log2(width) × [`transmission_roughness`], so roughness 1 reaches the 1-pixel level.
pub fn transmission_lod(perceptual_roughness: f32, ior: f32, width: f32) -> f32 {
    width.max(1.0).log2() * transmission_roughness(perceptual_roughness, ior)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snell_holds_for_the_refracted_direction() {
        let n = Vec3::Z;
        for (deg, ior) in [(0.0f32, 1.5f32), (30.0, 1.33), (45.0, 1.5), (80.0, 2.4)] {
            let t = deg.to_radians();
            let v = Vec3::new(t.sin(), 0.0, t.cos());
            let r = refracted_direction(n, v, ior);
            assert!((r.length() - 1.0).abs() < 1e-5);
            let sin_t = r.x.abs();
            assert!(
                (t.sin() - ior * sin_t).abs() < 1e-5,
                "{deg}° ior {ior}: sin θi {} vs n·sin θt {}",
                t.sin(),
                ior * sin_t
            );
            // Bent towards the normal, on the far side of it from v.
            assert!(r.z < 0.0 && r.x <= 0.0);
        }
    }

    #[test]
    fn a_slab_path_is_thickness_over_cos_theta_t() {
        let v = Vec3::new(45f32.to_radians().sin(), 0.0, 45f32.to_radians().cos());
        let s = refraction_path_m(Vec3::Z, v, 1.5, 0.2);
        let sin_t = 45f32.to_radians().sin() / 1.5;
        assert!((s - 0.2 / (1.0 - sin_t * sin_t).sqrt()).abs() < 1e-6);
        assert_eq!(refraction_path_m(Vec3::Z, v, 1.5, 0.0), 0.0);
        assert_eq!(refraction_path_m(Vec3::Z, v, 1.5, f32::NAN), 0.0);
        // Grazing at IOR 1 is bounded.
        let grazing = Vec3::new(1.0, 0.0, 0.0);
        assert!(refraction_path_m(Vec3::Z, grazing, 1.0, 1.0) <= 1.0 / MIN_COS_REFRACTED + 1e-3);
    }

    #[test]
    fn transmittance_follows_beer_lambert() {
        let c = Vec3::new(0.5, 0.8, 1.0);
        let t = volume_transmittance(c, 2.0, 3.0);
        for (got, colour) in [(t.x, c.x), (t.y, c.y), (t.z, c.z)] {
            let sigma = -colour.ln() / 2.0;
            assert!((got - (-sigma * 3.0).exp()).abs() < 1e-5);
        }
        assert_eq!(volume_transmittance(c, f32::INFINITY, 3.0), Vec3::ONE);
        assert_eq!(volume_transmittance(c, 2.0, 0.0), Vec3::ONE);
    }

    #[test]
    fn dispersion_spreads_by_the_abbe_number() {
        // Crown glass: n_d 1.5168, V 64.17: n_F − n_C = 0.00805.
        let iors = dispersion_iors(1.5168, 20.0 / 64.17);
        assert!((iors.z - iors.x - 0.5168 / 64.17).abs() < 1e-6);
        assert_eq!(iors.y, 1.5168);
        assert_eq!(dispersion_iors(1.5, 0.0), Vec3::splat(1.5));
    }

    #[test]
    fn extremes_stay_finite() {
        let v = Vec3::new(0.6, 0.0, 0.8);
        for ior in [0.0, 1.0, 10.0, 1e9, f32::NAN, f32::INFINITY] {
            let r = refracted_direction(Vec3::Z, v, ior);
            assert!(r.is_finite(), "ior {ior}: {r}");
            assert!(refraction_path_m(Vec3::Z, v, ior, 0.1).is_finite());
            assert!(transmission_lod(0.5, ior, 256.0).is_finite());
        }
        for d in [0.0, -1.0, f32::INFINITY, f32::NAN, 1e-30] {
            for c in [
                Vec3::ZERO,
                Vec3::ONE,
                Vec3::splat(f32::NAN),
                Vec3::splat(2.0),
            ] {
                for s in [0.0, 1.0, 1e6, f32::INFINITY] {
                    let t = volume_transmittance(c, d, s);
                    assert!(
                        t.is_finite() && t.min_element() >= 0.0 && t.max_element() <= 1.0,
                        "c {c} d {d} s {s}: {t}"
                    );
                }
            }
        }
        assert_eq!(transmission_roughness(0.8, 1.0), 0.0);
        for d in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e9] {
            let iors = dispersion_iors(1.5, d);
            assert!(iors.is_finite() && iors.min_element() >= 1.0 && iors.max_element() <= 10.0);
        }
        assert!((transmission_roughness(0.8, 1.5) - 0.8).abs() < 1e-6);
    }
}

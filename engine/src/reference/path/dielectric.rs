//! The path tracer's transmissive lobe (`KHR_materials_transmission`, `_volume`,
//! `_ior`): a rough dielectric interface that reflects or refracts (Walter et al. 2007,
//! "Microfacet Models for Refraction through Rough Surfaces"), with microfacet normals
//! drawn from GGX's visible normals (Heitz 2018) and the choice between reflection and
//! refraction made with the exact Fresnel reflectance of unpolarised light. Inside a
//! volume, light is absorbed by Beer–Lambert's law over the distance travelled
//! ([`crate::transmission::volume_transmittance`]). A thin-walled surface (thickness 0)
//! passes light through without bending it.

use super::microfacet::{basis, g1_ggx};
use super::rng::Rng;
use crate::scene::Transmission;
use glam::Vec3;

/// Fresnel reflectance of unpolarised light at a smooth interface, for the cosine
/// `cos_i` of the incident angle and the ratio `eta` = n_incident / n_transmitted
/// (Born & Wolf, "Principles of Optics", §1.5): the mean of the s and p reflectances. 1
/// under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let f = 0.5 * (rs * rs + rp * rp);
    if f.is_nan() { 1.0 } else { f.clamp(0.0, 1.0) }
}

/// A direction sampled from the interface at a hit, and its weight f·|cos|/pdf.
pub struct Scattered {
    /// Unit direction of the continuing ray.
    pub l: Vec3,
    /// Throughput multiplier.
    pub weight: Vec3,
    /// Whether the ray crosses the surface (leaves on the side opposite `v`).
    pub transmitted: bool,
}

/// Samples the interface of `transmission` at a hit with shading normal `n` (facing the
/// unit direction `v` towards where the ray came from), GGX width `alpha`, base colour
/// `base` (which tints transmitted light) and `entering` (whether `v` lies outside the
/// object, where its geometric normal points). Reflection and refraction are chosen by
/// their Fresnel reflectance about the sampled microfacet normal, so the weight is
/// Smith's masking of the outgoing direction (Heitz 2018, §5), × `base` when refracted.
/// `None` when the sampled direction falls on the wrong side of the surface.
pub fn sample(
    transmission: &Transmission,
    n: Vec3,
    v: Vec3,
    alpha: f32,
    base: Vec3,
    entering: bool,
    rng: &mut Rng,
) -> Option<Scattered> {
    let frame = basis(n);
    let local_v = frame.transpose() * v;
    if local_v.z <= 0.0 {
        return None;
    }
    let h = frame * crate::ibl::sample_ggx_vndf(local_v, alpha, rng.pair());
    let ior = crate::transmission::clamp_ior(transmission.ior);
    let thin = transmission.thickness_m.is_nan() || transmission.thickness_m <= 0.0;
    let eta = if thin || entering { 1.0 / ior } else { ior };
    let cos_i = v.dot(h);
    let reflectance = fresnel_dielectric(cos_i, eta);
    let reflected = 2.0 * cos_i * h - v;
    let (l, transmitted) = if rng.uniform() < reflectance {
        (reflected, false)
    } else if thin {
        // Through a thin wall: the reflection mirrored through the surface's plane.
        (reflected - 2.0 * reflected.dot(n) * n, true)
    } else {
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
        let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
        ((-v * eta + h * (eta * cos_i - cos_t)), true)
    };
    let l = l.normalize_or(-v);
    let n_dot_l = n.dot(l);
    if (transmitted && n_dot_l >= 0.0) || (!transmitted && n_dot_l <= 0.0) {
        return None;
    }
    let g1 = g1_ggx(n_dot_l.abs(), alpha);
    let weight = if transmitted {
        base * g1
    } else {
        Vec3::splat(g1)
    };
    weight.is_finite().then_some(Scattered {
        l,
        weight,
        transmitted,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_matches_normal_incidence_and_total_internal_reflection() {
        // ((n − 1)/(n + 1))² at normal incidence, from either side.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        // Beyond the critical angle asin(1/1.5) = 41.8° inside glass: total; below it not.
        assert_eq!(fresnel_dielectric(45f32.to_radians().cos(), 1.5), 1.0);
        assert!(fresnel_dielectric(40f32.to_radians().cos(), 1.5) < 0.5);
        assert!(fresnel_dielectric(45f32.to_radians().cos(), 1.0 / 1.5) < 0.06);
        assert_eq!(fresnel_dielectric(0.0, 1.0 / 1.5), 1.0);
        assert_eq!(fresnel_dielectric(0.7, 1.0), 0.0);
    }

    #[test]
    fn a_smooth_interface_refracts_by_snell_and_reflects_by_fresnel() {
        let glass = Transmission {
            thickness_m: 0.1,
            ..Transmission::default()
        };
        let t = 45f32.to_radians();
        let v = Vec3::new(t.sin(), 0.0, t.cos());
        let mut rng = Rng::new(7, 1, 2);
        let (mut reflected, mut total, mut off) = (0, 0, 0);
        for _ in 0..20000 {
            let Some(s) = sample(&glass, Vec3::Z, v, 1e-4, Vec3::ONE, true, &mut rng) else {
                continue;
            };
            total += 1;
            // GGX's long tail tilts a few microfacet normals of α = 10⁻⁴ by 10⁻³ rad or
            // more (P(θ > x) ≈ α²/x²): count them instead of failing on them.
            let error = if s.transmitted {
                assert!(s.l.z < 0.0 && s.l.x < 0.0, "{}", s.l);
                let sin_t = (s.l.x * s.l.x + s.l.y * s.l.y).sqrt();
                (t.sin() - 1.5 * sin_t).abs()
            } else {
                reflected += 1;
                (s.l - Vec3::new(-v.x, 0.0, v.z)).length()
            };
            off += usize::from(error > 1e-3);
        }
        assert!(
            off * 100 < total,
            "{off} of {total} off Snell's or the mirror direction"
        );
        let f = reflected as f32 / total as f32;
        let expected = fresnel_dielectric(t.cos(), 1.0 / 1.5);
        assert!(total > 19000);
        assert!(
            (f - expected).abs() < 0.01,
            "reflected {f}, Fresnel {expected}"
        );
    }

    #[test]
    fn a_thin_wall_passes_light_straight_through() {
        let t = 30f32.to_radians();
        let v = Vec3::new(t.sin(), 0.0, t.cos());
        let mut rng = Rng::new(3, 4, 5);
        let through = (0..200)
            .filter_map(|_| {
                sample(
                    &Transmission::default(),
                    Vec3::Z,
                    v,
                    1e-4,
                    Vec3::ONE,
                    true,
                    &mut rng,
                )
            })
            .find(|s| s.transmitted)
            .expect("most rays pass a thin wall");
        assert!((through.l + v).length() < 1e-3, "{}", through.l);
    }
}

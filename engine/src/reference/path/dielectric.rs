//! The path tracer's transmissive lobe (`KHR_materials_transmission`, `_volume`,
//! `_ior`): a rough dielectric interface that reflects or refracts (Walter et al. 2007,
//! "Microfacet Models for Refraction through Rough Surfaces"), with microfacet normals
//! drawn from GGX's visible normals (Heitz 2018) and the choice between reflection and
//! refraction made with the exact Fresnel reflectance of unpolarised light. Inside a
//! volume, light is absorbed by Beer–Lambert's law over the distance travelled
//! ([`crate::shading::transmission::volume_transmittance`]). A thin-walled surface (thickness 0)
//! passes light through without bending it.

use super::microfacet::g1_ggx_anisotropic;
use super::rng::Rng;
use crate::scene::Transmission;
use crate::shading::anisotropy::{RelitLobe, relit_fresnel};
use crate::shading::brdf::Surface;
use glam::{Mat3, Vec2, Vec3};

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

/// The interface a path meets at a transmissive surface, besides its transmission.
pub struct Interface {
    /// The microfacets' frame: its third column the shading normal, its first two the
    /// axes of `alphas` (an anisotropic interface's direction first).
    pub frame: Mat3,
    /// GGX widths along the frame's first two axes (α = perceptual roughness², stretched
    /// by an anisotropy: `crate::shading::anisotropy::anisotropic_alphas`).
    pub alphas: Vec2,
    /// Base colour, linear RGB 0..1: it tints the light the interface lets through.
    pub base: Vec3,
    /// Whether the path arrives from outside the object (where its geometric normal
    /// points).
    pub entering: bool,
    /// A tinted or iridescent interface (`KHR_materials_specular`, `_iridescence`): its
    /// dielectric surface and lobe, whose Fresnel ([`relit_fresnel`]) it reflects on its
    /// outside in place of the exact one, letting through 1 − its largest channel (glTF's
    /// `fresnel_mix`), as the rasterizer's transparent pass does. `None`: untinted.
    pub lobe: Option<(Surface, RelitLobe)>,
}

/// Samples the interface of `transmission` at a hit, seen from the unit direction `v`
/// towards where the ray came from (on the side of the frame's normal), its `interface`,
/// whose microfacet normals are drawn from the visible normals of GGX of its widths
/// (Heitz 2018, stretched along each axis for an anisotropic one). Reflection and
/// refraction are chosen by their Fresnel reflectance about the sampled microfacet
/// normal: the exact one for unpolarised light, or for a tinted or iridescent interface
/// entered from outside the largest channel of its relit Fresnel. So the weight is
/// Smith's masking of the outgoing direction (Heitz 2018, §5), × the base colour when
/// refracted, × the relit Fresnel ÷ its largest channel when a tinted interface reflects.
/// `None` when the sampled direction falls on the wrong side of the surface.
pub fn sample(
    transmission: &Transmission,
    v: Vec3,
    interface: &Interface,
    rng: &mut Rng,
) -> Option<Scattered> {
    let Interface {
        frame,
        alphas,
        base,
        entering,
        ..
    } = *interface;
    let n = frame.z_axis;
    let local_v = frame.transpose() * v;
    if local_v.z <= 0.0 {
        return None;
    }
    let h = frame * crate::shading::ibl::sample_ggx_vndf_anisotropic(local_v, alphas, rng.pair());
    let ior = crate::shading::transmission::clamp_ior(transmission.ior);
    let thin = transmission.thickness_m.is_nan() || transmission.thickness_m <= 0.0;
    let eta = if thin || entering { 1.0 / ior } else { ior };
    let cos_i = v.dot(h);
    let (reflectance, tint) = match interface.lobe.as_ref().filter(|_| entering) {
        Some((surface, lobe)) => {
            let f = relit_fresnel(surface, lobe, cos_i);
            let largest = f.max_element();
            (
                largest,
                if largest > 0.0 {
                    f / largest
                } else {
                    Vec3::ONE
                },
            )
        }
        None => (fresnel_dielectric(cos_i, eta), Vec3::ONE),
    };
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
    let g1 = g1_ggx_anisotropic(frame.transpose() * l, alphas);
    let weight = if transmitted { base * g1 } else { tint * g1 };
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

    /// A smooth (α 10⁻⁴), white interface facing +z, entered from outside, with `lobe`.
    fn smooth(lobe: Option<(Surface, RelitLobe)>) -> Interface {
        Interface {
            frame: Mat3::IDENTITY,
            alphas: Vec2::splat(1e-4),
            base: Vec3::ONE,
            entering: true,
            lobe,
        }
    }

    #[test]
    fn a_tinted_interface_reflects_its_fresnel_and_passes_the_rest_of_its_largest_channel() {
        // Specular level 1, tint (1, 0.5, 0.1), under a 400 nm film, seen at 60°: the
        // reflection's expected weight per channel is relit_fresnel, and 1 − its largest
        // channel passes through; from inside, the exact Fresnel of the IOR again.
        let surface = Surface {
            base_color: Vec3::ONE,
            metallic: 0.0,
            perceptual_roughness: 0.0,
            specular_level: 1.0,
        };
        let lobe = RelitLobe {
            strength: 0.0,
            tint: Vec3::new(1.0, 0.5, 0.1),
            film: Vec3::new(1.0, 1.33, 400.0),
        };
        let t = 60f32.to_radians();
        let v = Vec3::new(t.sin(), 0.0, t.cos());
        let f = relit_fresnel(&surface, &lobe, t.cos());
        let thin = Transmission::default();
        let mut rng = Rng::new(5, 6, 7);
        let n = 40000;
        let (mut reflected, mut through) = (Vec3::ZERO, 0);
        for _ in 0..n {
            let s = sample(&thin, v, &smooth(Some((surface, lobe))), &mut rng)
                .expect("a smooth interface samples every ray");
            if s.transmitted {
                through += 1;
            } else {
                reflected += s.weight;
            }
        }
        let reflected = reflected / n as f32;
        let through = through as f32 / n as f32;
        assert!(
            (reflected - f).abs().max_element() < 0.01,
            "reflected {reflected}, Fresnel {f}"
        );
        assert!(
            (through - (1.0 - f.max_element())).abs() < 0.01,
            "through {through}, 1 − max F {}",
            1.0 - f.max_element()
        );
        let inside = Interface {
            entering: false,
            ..smooth(Some((surface, lobe)))
        };
        let volume = Transmission {
            thickness_m: 0.1,
            ..Transmission::default()
        };
        let reflected_inside = (0..n)
            .filter_map(|_| sample(&volume, v, &inside, &mut rng))
            .filter(|s| !s.transmitted)
            .count() as f32
            / n as f32;
        // 60° inside glass is beyond the critical angle: every ray is reflected.
        assert_eq!(fresnel_dielectric(t.cos(), 1.5), 1.0);
        assert!(reflected_inside > 0.99, "{reflected_inside}");
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
            let Some(s) = sample(&glass, v, &smooth(None), &mut rng) else {
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
            .filter_map(|_| sample(&Transmission::default(), v, &smooth(None), &mut rng))
            .find(|s| s.transmitted)
            .expect("most rays pass a thin wall");
        assert!((through.l + v).length() < 1e-3, "{}", through.l);
    }
}

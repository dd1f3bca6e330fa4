//! Diffuse transmission (glTF's `KHR_materials_diffuse_transmission`): the CPU twin of
//! `shaders/diffuse_transmission.wgsl`, with the same names
//! (docs/src/materials.md#diffuse-transmission).
//!
//! Leaves, paper and lampshades scatter light so densely inside that what leaves their
//! far side has forgotten its direction: the light passes through diffusely. The
//! extension (Haeussler, Sdorra & Mackey, Khronos 2023) splits the base's diffuse lobe
//! by the factor `d ∈ [0, 1]` between a Lambertian reflection of the base colour and a
//! Lambertian transmission of the transmission colour `c_t`, both under the same
//! Fresnel weighting as the diffuse lobe; the specular lobe is untouched:
//!
//! `f_d = (1 − d) · k_d · base / π` for a light on the viewer's side,
//! `f_t = d · k_d′ · c_t / π` for a light on the other side,
//!
//! with `k_d = (1 − F(v·h))(1 − metallic)`. For a light behind the surface the half
//! vector of v and l is not defined; Lumen takes `k_d′` at the half vector of v and the
//! light mirrored through the surface, `l′ = l − 2 (n·l) n` (as the Khronos sample
//! renderer does), so a light behind at some angle is weighted as one in front at the
//! same angle. Both lobes are then reciprocal, and a white surface (`base = c_t = 1`)
//! in a uniform environment returns exactly that environment, whatever `d` is.

use crate::shading::anisotropy::RelitLobe;
use crate::shading::brdf::{Surface, fd_lambert, safe_normalize};
use glam::Vec3;

/// The diffuse transmission lobe (1/sr) of a relit base of `surface` and `lobe` (the
/// tinted, iridescent F0 of [`crate::shading::anisotropy::relit_brdf_lobes`]) with factor `factor`
/// (0..1, clamped; NaN: 0) and transmitted colour `color` (linear RGB 0..1, clamped),
/// for a light along the unit `l` below the horizon of the unit normal `n`, seen from
/// the unit `v` above it: `factor · (1 − F(v·h′))(1 − metallic) · color / π`, h′ the
/// half vector of v and l mirrored through the surface. Zero for a light above the
/// horizon (the reflected lobes' side).
pub fn diffuse_transmission_lobe(
    n: Vec3,
    v: Vec3,
    l: Vec3,
    surface: &Surface,
    lobe: &RelitLobe,
    factor: f32,
    color: Vec3,
) -> Vec3 {
    let n_dot_l = n.dot(l);
    if n_dot_l >= 0.0 || n_dot_l.is_nan() {
        return Vec3::ZERO;
    }
    let d = if factor.is_nan() {
        0.0
    } else {
        factor.clamp(0.0, 1.0)
    };
    let mirrored = l - 2.0 * n_dot_l * n;
    let h = safe_normalize(v + mirrored, n);
    let metallic = surface.metallic.clamp(0.0, 1.0);
    let f = crate::shading::anisotropy::relit_fresnel(surface, lobe, v.dot(h));
    let k_d = (Vec3::ONE - f) * (1.0 - metallic);
    k_d * color.clamp(Vec3::ZERO, Vec3::ONE) * (d * fd_lambert())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(metallic: f32) -> Surface {
        Surface {
            base_color: Vec3::new(0.8, 0.5, 0.2),
            metallic,
            perceptual_roughness: 0.5,
            specular_level: 0.5,
        }
    }

    #[test]
    fn mirrors_the_reflected_diffuse_lobe() {
        // A light behind at some angle is weighted as its mirror image in front: the
        // transmitted lobe is the reflected diffuse lobe with c_t for the base colour.
        let n = Vec3::Z;
        let v = Vec3::new(0.3, -0.2, 0.9).normalize();
        let l = Vec3::new(-0.5, 0.1, -0.6).normalize();
        let s = surface(0.3);
        let lobe = RelitLobe::default();
        let front = Vec3::new(l.x, l.y, -l.z);
        let reflected =
            crate::shading::anisotropy::relit_brdf_lobes(n, v, front, Vec3::X, &s, &lobe);
        let white = Surface {
            base_color: Vec3::ONE,
            ..s
        };
        let color = Vec3::new(0.9, 0.6, 0.1);
        let transmitted = diffuse_transmission_lobe(n, v, l, &s, &lobe, 0.7, color);
        let expected = reflected.diffuse / s.base_color * color * 0.7;
        assert!(
            (transmitted - expected).abs().max_element() < 1e-6,
            "{transmitted} vs {expected}"
        );
        // The base colour enters only through a metal's F0.
        let plain = diffuse_transmission_lobe(n, v, l, &white, &lobe, 0.7, color);
        assert!(plain.min_element() > 0.0);
    }

    #[test]
    fn zero_above_the_horizon_for_metals_and_without_a_factor() {
        let n = Vec3::Z;
        let v = Vec3::new(0.0, 0.6, 0.8);
        let lobe = RelitLobe::default();
        let (below, above) = (Vec3::new(0.0, 0.6, -0.8), Vec3::new(0.0, -0.6, 0.8));
        let s = surface(0.0);
        assert_eq!(
            diffuse_transmission_lobe(n, v, above, &s, &lobe, 1.0, Vec3::ONE),
            Vec3::ZERO
        );
        assert_eq!(
            diffuse_transmission_lobe(n, v, below, &surface(1.0), &lobe, 1.0, Vec3::ONE),
            Vec3::ZERO
        );
        assert_eq!(
            diffuse_transmission_lobe(n, v, below, &s, &lobe, 0.0, Vec3::ONE),
            Vec3::ZERO
        );
        assert_eq!(
            diffuse_transmission_lobe(n, v, below, &s, &lobe, f32::NAN, Vec3::ONE),
            Vec3::ZERO
        );
        let nan = diffuse_transmission_lobe(n, v, Vec3::NAN, &s, &lobe, 1.0, Vec3::ONE);
        assert_eq!(nan, Vec3::ZERO);
        // Clamped: a factor of 5 and a colour of 3 are 1 and 1.
        let one = diffuse_transmission_lobe(n, v, below, &s, &lobe, 1.0, Vec3::ONE);
        let big = diffuse_transmission_lobe(n, v, below, &s, &lobe, 5.0, Vec3::splat(3.0));
        assert_eq!(one, big);
        // (1 − 0.04) / π at normal incidence, within Schlick's 5th power.
        let straight = diffuse_transmission_lobe(n, Vec3::Z, -Vec3::Z, &s, &lobe, 1.0, Vec3::ONE);
        assert!(
            (straight.x - 0.96 / std::f32::consts::PI).abs() < 1e-6,
            "{straight}"
        );
    }
}

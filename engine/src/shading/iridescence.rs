//! Thin-film iridescence (glTF's `KHR_materials_iridescence`): the CPU twins of
//! `shaders/iridescence.wgsl`, with the same names (docs/src/materials.md#iridescence).
//!
//! A transparent film a few hundred nanometres thick over the base (soap bubbles, oil on
//! water, anodised or heat-tinted metal, beetle shells) reflects light from its top and
//! its bottom; the two reflections interfere, and which wavelengths add up depends on the
//! path difference, so the colour changes with the viewing angle. Belcour & Barla 2017
//! ("A Practical Extension to Microfacet Theory for the Modeling of Varying
//! Iridescence", ACM TOG 36(4)) sum the film's Airy series for the air–film–base stack
//! and integrate it against the colour-matching functions analytically, each fitted by
//! Gaussians, which gives the film's Fresnel reflectance in RGB. glTF specifies that
//! formula, with the first two orders of the series, and mixes it into the base's
//! Fresnel by the iridescence factor: `F = mix(F_Schlick, F_film, factor)`.
//!
//! Inputs: the cosine of the angle of incidence in air (h·v for a microfacet), the
//! film's index of refraction η (glTF's default 1.3), its thickness d in nanometres, and
//! the base's F0, from which the base's index is recovered per channel,
//! `n = (1 + √F0) / (1 − √F0)`.

use crate::shading::brdf::f_schlick;
use glam::{Mat3, Vec3};
use std::f32::consts::PI;

/// F0 of an interface between media of indices `a` and `b`: `((a − b)/(a + b))²`.
pub fn interface_f0(a: f32, b: f32) -> f32 {
    let r = (a - b) / (a + b);
    r * r
}

/// The sensitivity of the eye's XYZ responses, as linear Rec. 709 RGB, to the phase
/// difference of an optical path difference `opd_nm` (nm) with the phase shifts `shift`
/// (radians, per channel): Belcour & Barla's Gaussian fits of the colour-matching
/// functions in Fourier space, normalised so that a zero path difference gives 1.
pub fn film_sensitivity(opd_nm: f32, shift: Vec3) -> Vec3 {
    let phase = 2.0 * PI * opd_nm * 1e-9;
    let val = Vec3::new(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = Vec3::new(1.6810e6, 1.7953e6, 2.2084e6);
    let var = Vec3::new(4.3278e9, 9.3046e9, 6.6121e9);
    let gauss = |v: f32, p: f32, s: f32, shift: f32| {
        v * (2.0 * PI * s).sqrt() * (p * phase + shift).cos() * (-phase * phase * s).exp()
    };
    let mut xyz = Vec3::new(
        gauss(val.x, pos.x, var.x, shift.x),
        gauss(val.y, pos.y, var.y, shift.y),
        gauss(val.z, pos.z, var.z, shift.z),
    );
    xyz.x += gauss(9.7470e-14, 2.2399e6, 4.5282e9, shift.x);
    let xyz = xyz / 1.0685e-7;
    let xyz_to_rgb = Mat3::from_cols(
        Vec3::new(3.240_454_2, -0.969_266, 0.055_643_4),
        Vec3::new(-1.537_138_5, 1.876_010_8, -0.204_025_9),
        Vec3::new(-0.498_531_4, 0.041_556, 1.057_225_2),
    );
    xyz_to_rgb * xyz
}

/// The Fresnel reflectance (RGB, 0..1) of a thin film of index `film_ior` (clamped to
/// ≥ 1) and thickness `thickness_nm` (nm, ≥ 0) between air and a base of F0 `base_f0`,
/// for light arriving at cosine `cos_theta1` (clamped to 0..1): Belcour & Barla 2017 with
/// the Airy series to second order. As glTF specifies, the film's index tends to air's
/// as the thickness tends to 0 (over the first 0.03 nm, weight t = smoothstep); Lumen
/// also mixes the result into the base's Schlick Fresnel by that t, so that no film is
/// exactly the base (glTF's index fade alone leaves Schlick's grazing term of the vanished
/// interface: measured 0.36 too much at cos 0.3 before this fade was added).
pub fn iridescent_fresnel(
    cos_theta1: f32,
    film_ior: f32,
    thickness_nm: f32,
    base_f0: Vec3,
) -> Vec3 {
    let d = if thickness_nm.is_finite() {
        thickness_nm.max(0.0)
    } else {
        0.0
    };
    let ior = if film_ior.is_finite() {
        film_ior.max(1.0)
    } else {
        1.0
    };
    let t = (d / 0.03).clamp(0.0, 1.0);
    let fade = t * t * (3.0 - 2.0 * t);
    let eta = 1.0 + (ior - 1.0) * fade;
    let cos1 = if cos_theta1.is_nan() {
        1.0
    } else {
        cos_theta1.clamp(0.0, 1.0)
    };
    let bare = f_schlick(base_f0.clamp(Vec3::ZERO, Vec3::ONE), cos1);
    if fade == 0.0 {
        return bare;
    }
    // η ≥ 1: light entering the film from air always refracts.
    let cos2 = (1.0 - (1.0 - cos1 * cos1) / (eta * eta)).max(0.0).sqrt();
    // Air to film: the film is denser than air (η ≥ 1), so no phase shift on reflection
    // at its top, π at its bottom seen from inside.
    let r12 = f_schlick(Vec3::splat(interface_f0(eta, 1.0)), cos1).x;
    let t121 = 1.0 - r12;
    let phi21 = PI;
    // Film to base: the base's index per channel from its F0.
    let root = base_f0
        .clamp(Vec3::ZERO, Vec3::splat(0.9999))
        .map(f32::sqrt);
    let base_ior = (Vec3::ONE + root) / (Vec3::ONE - root);
    let r1 = base_ior.map(|n| interface_f0(n, eta));
    let r23 = f_schlick(r1, cos2);
    let phi23 = base_ior.map(|n| if n < eta { PI } else { 0.0 });
    let opd = 2.0 * eta * d * cos2;
    let phi = Vec3::splat(phi21) + phi23;
    let r123 = (r23 * r12).clamp(Vec3::splat(1e-5), Vec3::splat(0.9999));
    let r123_root = r123.map(f32::sqrt);
    let rs = t121 * t121 * r23 / (Vec3::ONE - r123);
    let mut reflectance = Vec3::splat(r12) + rs;
    let mut cm = rs - Vec3::splat(t121);
    for m in 1..=2 {
        cm *= r123_root;
        let order = m as f32;
        reflectance += cm * 2.0 * film_sensitivity(order * opd, order * phi);
    }
    bare.lerp(reflectance.clamp(Vec3::ZERO, Vec3::ONE), fade)
}

/// The base's Fresnel under an iridescent film `film` = (factor 0..1, clamped, NaN: 0;
/// index; thickness in nm): `mix(F_Schlick(f0, cos), iridescent_fresnel(cos, index,
/// thickness, f0), factor)`.
pub fn iridescent_mix(f0: Vec3, cos_theta: f32, film: Vec3) -> Vec3 {
    let k = if film.x.is_nan() {
        0.0
    } else {
        film.x.clamp(0.0, 1.0)
    };
    let schlick = f_schlick(f0, cos_theta.clamp(0.0, 1.0));
    if k == 0.0 {
        return schlick;
    }
    schlick.lerp(iridescent_fresnel(cos_theta, film.y, film.z, f0), k)
}

/// The F0 the split sum and the energy compensation use for a surface of F0 `f0` under
/// the film `film` (as in [`iridescent_mix`]) seen at cosine `cos_theta`:
/// `mix(f0, schlick_f0_of(iridescent_fresnel(cos, index, thickness, f0), cos), factor)`.
pub fn film_f0(f0: Vec3, cos_theta: f32, film: Vec3) -> Vec3 {
    let k = if film.x.is_nan() {
        0.0
    } else {
        film.x.clamp(0.0, 1.0)
    };
    if k == 0.0 {
        return f0;
    }
    let fresnel = iridescent_fresnel(cos_theta, film.y, film.z, f0);
    f0.lerp(schlick_f0_of(fresnel, cos_theta), k)
}

/// The F0 that makes Schlick's Fresnel at cosine `cos_theta` equal `fresnel`:
/// `(F − x)/(1 − x)`, x = (1 − cos)⁵, clamped to 0..1. The split sum reads the
/// environment's specular albedo with it for an iridescent surface, as the Khronos sample
/// renderer does.
pub fn schlick_f0_of(fresnel: Vec3, cos_theta: f32) -> Vec3 {
    let x = crate::shading::brdf::pow5_one_minus(cos_theta);
    ((fresnel - Vec3::splat(x)) / (1.0 - x).max(1e-4)).clamp(Vec3::ZERO, Vec3::ONE)
}

/// The film's thickness (nm) at a texel of glTF's `iridescenceThicknessTexture`: its
/// green channel `g` (0..1) mixes the minimum (0) and the maximum (1), the material's
/// `thickness_nm` (`KHR_materials_iridescence`).
pub fn film_thickness(min_nm: f32, max_nm: f32, g: f32) -> f32 {
    min_nm + (max_nm - min_nm) * g.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thickness_texel_mixes_the_minimum_and_the_maximum() {
        assert_eq!(film_thickness(100.0, 400.0, 0.0), 100.0);
        assert_eq!(film_thickness(100.0, 400.0, 1.0), 400.0);
        assert!((film_thickness(100.0, 400.0, 0.25) - 175.0).abs() < 1e-4);
        assert_eq!(film_thickness(100.0, 400.0, 3.0), 400.0);
    }

    #[test]
    fn a_film_of_no_thickness_is_the_base_alone() {
        // At 0 nm the result is Schlick's Fresnel of the base at every angle. With glTF's
        // fade of the film's index alone (measured with this function before the result
        // was faded too), Schlick's grazing term of the vanished air–film interface
        // (F0 0 but F > 0 away from the normal) was left in the series: 0.0073 above the
        // base at normal view, 0.0324 at cos 0.7 and 0.3598 at cos 0.3 (F0 (0.04, 0.5,
        // 0.9)).
        let f0 = Vec3::new(0.04, 0.5, 0.9);
        for cos in [1.0, 0.7, 0.3, 0.05] {
            let film = iridescent_fresnel(cos, 1.3, 0.0, f0);
            let bare = f_schlick(f0, cos);
            assert!(
                (film - bare).abs().max_element() < 1e-6,
                "cos {cos}: {film} vs {bare}"
            );
        }
    }

    #[test]
    fn the_colour_changes_with_angle_and_thickness() {
        // A 400 nm film of index 1.3 over a dielectric: its hue at normal view differs
        // from its hue at 60°, and a 250 nm film's from the 400 nm one's.
        let f0 = Vec3::splat(0.04);
        let hue = |c: Vec3| c / c.element_sum();
        let normal = iridescent_fresnel(1.0, 1.3, 400.0, f0);
        let oblique = iridescent_fresnel(0.5, 1.3, 400.0, f0);
        let thinner = iridescent_fresnel(1.0, 1.3, 250.0, f0);
        for c in [normal, oblique, thinner] {
            assert!(
                c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0,
                "{c}"
            );
        }
        assert!(
            (hue(normal) - hue(oblique)).abs().max_element() > 0.05,
            "{normal} vs {oblique}"
        );
        assert!(
            (hue(normal) - hue(thinner)).abs().max_element() > 0.05,
            "{normal} vs {thinner}"
        );
        // Factor 0 is Schlick's; the inversion gives back F0.
        assert_eq!(
            iridescent_mix(f0, 0.5, Vec3::new(0.0, 1.3, 400.0)),
            f_schlick(f0, 0.5)
        );
        let back = schlick_f0_of(f_schlick(Vec3::new(0.2, 0.5, 0.8), 0.6), 0.6);
        assert!(
            (back - Vec3::new(0.2, 0.5, 0.8)).abs().max_element() < 1e-5,
            "{back}"
        );
    }

    #[test]
    fn extreme_films_stay_in_range() {
        for (cos, ior, d) in [
            (0.0, 1.0, 0.0),
            (1.0, 10.0, 5000.0),
            (f32::NAN, f32::NAN, f32::NAN),
            (0.3, f32::INFINITY, f32::INFINITY),
            (-1.0, 0.5, -10.0),
        ] {
            let f = iridescent_fresnel(cos, ior, d, Vec3::new(0.0, 0.5, 1.0));
            assert!(
                f.is_finite() && f.min_element() >= 0.0 && f.max_element() <= 1.0,
                "{f}"
            );
        }
    }
}

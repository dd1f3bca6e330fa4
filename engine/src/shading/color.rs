//! Colour on the CPU: the sRGB transfer curve, luminance, tone mappers (the same as
//! `shaders/color.wgsl`), and colour temperature.

use glam::{Mat3, Vec3, Vec4};

/// Relative luminance of linear Rec.709/sRGB primaries (ITU-R BT.709):
/// `Y = 0.2126 R + 0.7152 G + 0.0722 B`.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Largest finite f16 (65504), the limit of the half-precision HDR target.
pub const HALF_MAX: f32 = 65504.0;

/// A blended surface's premultiplied colour and coverage, `(L·α, α)` (Porter & Duff 1984,
/// "Compositing Digital Images"): `lit` is the radiance it reflects and emits (cd/m² ×
/// exposure), `alpha` the fraction of the pixel it covers, clamped to [0, 1]. NaN radiance
/// becomes 0, and the colour is capped at [`HALF_MAX`].
pub fn premultiplied(lit: Vec3, alpha: f32) -> Vec4 {
    let a = if alpha.is_nan() {
        0.0
    } else {
        alpha.clamp(0.0, 1.0)
    };
    let finite = Vec3::select(lit.is_nan_mask(), Vec3::ZERO, lit);
    (finite.min(Vec3::splat(HALF_MAX)) * a).extend(a)
}

/// Porter & Duff's "over": premultiplied `src` in front of premultiplied `dst`,
/// `src + dst·(1 − α_src)`; the blend state of the transparent pass.
pub fn over(src: Vec4, dst: Vec4) -> Vec4 {
    src + dst * (1.0 - src.w)
}

/// The exact piecewise sRGB encoding of one linear channel (IEC 61966-2-1):
/// `12.92 x` below 0.0031308, else `1.055 x^(1/2.4) − 0.055`. Input clamped to [0, 1].
pub fn srgb_encode(x: f32) -> f32 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The exact piecewise sRGB decoding (inverse of [`srgb_encode`]).
pub fn srgb_decode(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

crate::choice::choices! {
/// Tone mapping operator applied to exposed scene-referred radiance before sRGB output.
/// The numeric values are the shader constant `TONEMAPPER`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Tonemapper: "tone mapper" {
    /// No curve: values are clamped to [0, 1].
    None(0) = "none",
    /// Reinhard `c / (c + 1)` per channel, as in the seeds (Reinhard et al. 2002).
    Reinhard(1) = "reinhard",
    /// Stephen Hill's fit of the ACES RRT + ODT (sRGB, 100 cd/m² display), as
    /// Bevy's `AcesFitted`.
    AcesFitted(2) = "aces",
    /// AgX (Troy Sobotka), in Benjamin Wrensch's polynomial approximation: hue-stable
    /// desaturation of bright colours.
    Agx(3) = "agx",
    /// Khronos PBR Neutral (2024): colours up to 0.76 are reproduced exactly (after a
    /// small black-level offset), only highlights are compressed. The default: the most
    /// faithful base colours, which is what a renderer measured for accuracy should show.
    #[default]
    PbrNeutral(4) = "pbr-neutral",
}
}

impl Tonemapper {
    /// Applies the operator to one linear colour (exposed radiance).
    pub fn apply(self, c: Vec3) -> Vec3 {
        match self {
            Tonemapper::None => tonemap_none(c),
            Tonemapper::Reinhard => tonemap_reinhard(c),
            Tonemapper::AcesFitted => tonemap_aces_fitted(c),
            Tonemapper::Agx => tonemap_agx(c),
            Tonemapper::PbrNeutral => tonemap_pbr_neutral(c),
        }
    }
}

/// No tone curve: clamp to [0, 1].
pub fn tonemap_none(c: Vec3) -> Vec3 {
    c.clamp(Vec3::ZERO, Vec3::ONE)
}

/// Reinhard: `c / (c + 1)` per channel (seed 002). Negative input is clamped to 0.
pub fn tonemap_reinhard(c: Vec3) -> Vec3 {
    let c = c.max(Vec3::ZERO);
    c / (c + Vec3::ONE)
}

/// sRGB → ACES AP1 input matrix of Hill's fit, with the RRT's saturation folded in
/// (column-major: the constructor takes columns).
fn aces_input_matrix() -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.59719, 0.07600, 0.02840),
        Vec3::new(0.35458, 0.90834, 0.13383),
        Vec3::new(0.04823, 0.01566, 0.83777),
    )
}

/// ODT output matrix of Hill's fit back to linear sRGB (columns).
fn aces_output_matrix() -> Mat3 {
    Mat3::from_cols(
        Vec3::new(1.60475, -0.10208, -0.00327),
        Vec3::new(-0.53108, 1.10813, -0.07276),
        Vec3::new(-0.07367, -0.00605, 1.07602),
    )
}

/// Rational fit of the ACES RRT + ODT curve: `(v(v + a) − b) / (v(c v + d) + e)`.
pub fn aces_rrt_odt_fit(v: Vec3) -> Vec3 {
    let a = v * (v + Vec3::splat(0.024_578_6)) - Vec3::splat(0.000_090_537);
    let b = v * (0.983_729 * v + Vec3::splat(0.432_951)) + Vec3::splat(0.238_081);
    a / b
}

/// ACES fitted (Stephen Hill, "BakingLab", 2016): input matrix, RRT+ODT fit, output
/// matrix, clamped to [0, 1].
pub fn tonemap_aces_fitted(c: Vec3) -> Vec3 {
    let v = aces_input_matrix() * c.max(Vec3::ZERO);
    let v = aces_rrt_odt_fit(v);
    (aces_output_matrix() * v).clamp(Vec3::ZERO, Vec3::ONE)
}

/// AgX inset matrix (linear sRGB → AgX log encoding space), columns.
fn agx_inset() -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.842_479_06, 0.042_328_24, 0.042_375_655),
        Vec3::new(0.078_433_6, 0.878_468_6, 0.078_433_6),
        Vec3::new(0.079_223_745, 0.079_166_13, 0.879_143),
    )
}

/// AgX outset matrix (inverse of the inset), columns.
fn agx_outset() -> Mat3 {
    Mat3::from_cols(
        Vec3::new(1.196_879, -0.052_896_85, -0.052_971_635),
        Vec3::new(-0.098_020_88, 1.151_903_1, -0.098_043_45),
        Vec3::new(-0.099_029_74, -0.098_961_18, 1.151_073_7),
    )
}

/// Wrensch's 6th-order fit of AgX's default contrast curve.
pub fn agx_contrast(x: Vec3) -> Vec3 {
    let x2 = x * x;
    let x4 = x2 * x2;
    15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - Vec3::splat(0.002_32)
}

/// AgX (Sobotka 2023; approximation by Wrensch 2023, "Minimal AgX Implementation"):
/// inset matrix, log2 encoding over [−12.47, 4.03] EV, contrast curve, outset matrix,
/// and the curve's 2.2 display power undone, giving linear display values in [0, 1].
pub fn tonemap_agx(c: Vec3) -> Vec3 {
    const MIN_EV: f32 = -12.473_931;
    const MAX_EV: f32 = 4.026_069;
    let v = agx_inset() * c.max(Vec3::ZERO);
    let v = v
        .max(Vec3::splat(1e-10))
        .log2()
        .clamp(Vec3::splat(MIN_EV), Vec3::splat(MAX_EV));
    let v = (v - Vec3::splat(MIN_EV)) / (MAX_EV - MIN_EV);
    let v = agx_outset() * agx_contrast(v);
    v.max(Vec3::ZERO).powf(2.2).min(Vec3::ONE)
}

/// Khronos PBR Neutral (Khronos 3D Commerce, 2024): subtract a small offset near black,
/// then compress only values whose largest channel exceeds 0.76, desaturating the
/// compressed part towards white.
pub fn tonemap_pbr_neutral(c: Vec3) -> Vec3 {
    const START_COMPRESSION: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let c = c.max(Vec3::ZERO);
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - Vec3::splat(offset);
    let peak = c.max_element();
    if peak < START_COMPRESSION {
        return c;
    }
    let d = 1.0 - START_COMPRESSION;
    let new_peak = 1.0 - d * d / (peak + d - START_COMPRESSION);
    let c = c * (new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c * (1.0 - g) + Vec3::splat(new_peak * g)
}

/// Lowest and highest colour temperature (K) of the Planckian-locus fit used by
/// [`kelvin_to_linear_rgb`]; values outside are clamped.
pub const KELVIN_RANGE: (f32, f32) = (1667.0, 25000.0);

/// CIE 1931 xy chromaticity of a blackbody at `kelvin` (clamped to [`KELVIN_RANGE`]),
/// by the cubic-spline fit of Kim et al. (2002), "Design of Advanced Color Temperature
/// Control System for HDTV Applications".
pub fn planckian_xy(kelvin: f32) -> (f32, f32) {
    let t = kelvin.clamp(KELVIN_RANGE.0, KELVIN_RANGE.1) as f64;
    let (t2, t3) = (t * t, t * t * t);
    let x = if t <= 4000.0 {
        -0.266_123_9e9 / t3 - 0.234_358_9e6 / t2 + 0.877_695_6e3 / t + 0.179_910
    } else {
        -3.025_846_9e9 / t3 + 2.107_037_9e6 / t2 + 0.222_634_7e3 / t + 0.240_390
    };
    let (x2, x3) = (x * x, x * x * x);
    let y = if t <= 2222.0 {
        -1.106_381_4 * x3 - 1.348_110_20 * x2 + 2.185_558_32 * x - 0.202_196_83
    } else if t <= 4000.0 {
        -0.954_947_6 * x3 - 1.374_185_93 * x2 + 2.091_370_15 * x - 0.167_488_67
    } else {
        3.081_758_0 * x3 - 5.873_386_70 * x2 + 3.751_129_97 * x - 0.370_014_83
    };
    (x as f32, y as f32)
}

/// CIE XYZ → linear sRGB (Rec.709 primaries, D65 white), columns.
fn xyz_to_linear_srgb() -> Mat3 {
    Mat3::from_cols(
        Vec3::new(3.240_454_2, -0.969_266, 0.055_643_4),
        Vec3::new(-1.537_138_5, 1.876_010_8, -0.204_025_9),
        Vec3::new(-0.498_531_4, 0.041_556, 1.057_225_2),
    )
}

/// Linear sRGB colour of a blackbody at `kelvin`, with relative luminance 1, so that a
/// light's intensity (lux, lumens, candela) keeps its photometric meaning whatever its
/// colour. Components that fall outside the sRGB gamut (very low temperatures) are clamped
/// to 0 before the luminance is normalised.
pub fn kelvin_to_linear_rgb(kelvin: f32) -> Vec3 {
    let (x, y) = planckian_xy(kelvin);
    let xyz = Vec3::new(x / y, 1.0, (1.0 - x - y) / y);
    let rgb = (xyz_to_linear_srgb() * xyz).max(Vec3::ZERO);
    rgb / luminance(rgb).max(1e-6)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::choice::Choice;

    #[test]
    fn srgb_curve_known_values() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        // Linear segment.
        assert!((srgb_encode(0.002) - 0.02584).abs() < 1e-6);
        // Linear 0.5 → 0.735357 (not 0.5^(1/2.2) = 0.72974).
        assert!((srgb_encode(0.5) - 0.735_357).abs() < 1e-5);
        // 18 % grey → 0.461356.
        assert!((srgb_encode(0.18) - 0.461_356).abs() < 1e-5);
        for i in 0..=255 {
            let v = i as f32 / 255.0;
            assert!((srgb_encode(srgb_decode(v)) - v).abs() < 1e-5);
        }
        assert_eq!(srgb_encode(f32::NAN), 0.0);
        assert_eq!(srgb_encode(7.0), srgb_encode(1.0));
    }

    #[test]
    fn tonemappers_map_zero_to_zero_and_are_monotonic() {
        for (i, &t) in Tonemapper::ALL.iter().enumerate() {
            assert_eq!(t as usize, i, "ALL is in shader-constant order");
            assert!(t.apply(Vec3::ZERO).max_element().abs() < 1e-3, "{t:?}");
            let mut last = -1.0f32;
            for i in 0..2000 {
                let x = (i as f32 * 0.01).powi(2);
                let y = luminance(t.apply(Vec3::splat(x)));
                assert!(y >= last - 1e-6, "{t:?} not monotonic at {x}");
                assert!((0.0..=1.0).contains(&y));
                last = y;
            }
            assert_eq!(Tonemapper::from_name(t.name()), Some(t));
        }
        assert_eq!(tonemap_reinhard(Vec3::ONE), Vec3::splat(0.5));
        // ACES fitted: white saturates; mid grey 0.18 → 0.1056 display-linear (the RRT+ODT
        // fit alone gives (0.18·0.20458 − 0.00009)/(0.18·0.61003 + 0.23808) = 0.1056 for a
        // grey, which the two matrices keep grey).
        assert!(tonemap_aces_fitted(Vec3::splat(100.0)).min_element() > 0.99);
        // PBR Neutral: below the compression start only the 0.04 black-level offset.
        let c = tonemap_pbr_neutral(Vec3::new(0.6, 0.3, 0.1));
        assert!(
            (c - Vec3::new(0.56, 0.26, 0.06)).abs().max_element() < 1e-6,
            "{c}"
        );
        assert!(tonemap_pbr_neutral(Vec3::splat(1e4)).max_element() <= 1.0);
        let mid = tonemap_aces_fitted(Vec3::splat(0.18));
        assert!(
            (mid - Vec3::splat(0.1056)).abs().max_element() < 2e-3,
            "{mid}"
        );
    }

    #[test]
    fn planckian_locus_known_points() {
        // CIE illuminant A (2856 K) lies on the locus: x = 0.44757, y = 0.40745.
        let (x, y) = planckian_xy(2856.0);
        assert!(
            (x - 0.44757).abs() < 1e-3 && (y - 0.40745).abs() < 1e-3,
            "{x} {y}"
        );
        // 6500 K blackbody: x ≈ 0.3135, y ≈ 0.3236.
        let (x, y) = planckian_xy(6500.0);
        assert!(
            (x - 0.3135).abs() < 1e-3 && (y - 0.3236).abs() < 1e-3,
            "{x} {y}"
        );
    }

    #[test]
    fn kelvin_colours() {
        let warm = kelvin_to_linear_rgb(2700.0);
        let white = kelvin_to_linear_rgb(6500.0);
        let cold = kelvin_to_linear_rgb(12000.0);
        for c in [warm, white, cold] {
            assert!((luminance(c) - 1.0).abs() < 1e-4);
            assert!(c.min_element() >= 0.0);
        }
        assert!(warm.x > warm.z * 2.0, "{warm}");
        assert!(cold.z > cold.x, "{cold}");
        // 6500 K is close to the D65 white point, so close to (1, 1, 1).
        assert!((white - Vec3::ONE).abs().max_element() < 0.08, "{white}");
        // Out of range is clamped, not NaN.
        assert_eq!(kelvin_to_linear_rgb(100.0), kelvin_to_linear_rgb(1667.0));
        assert!(kelvin_to_linear_rgb(f32::INFINITY).is_finite());
    }
}

//! The anti-aliasing formulas on the CPU, each the twin of the function with the same
//! name in `shaders/antialiasing.wgsl` (held together by `tests/shader_parity.rs`).
//!
//! Colours are pre-exposed linear HDR luminance (dimensionless once exposed, 1 ≈ the
//! display's white before tone mapping).

use crate::color::luminance;
use glam::{Vec3, Vec4};

/// One step of a running mean (Welford 1962): the mean of n samples from the mean of the
/// first n − 1 and the n-th sample, `m + (x − m) w` with `w = 1/n`. A weight of 1 (or
/// more) starts a new mean at `sample`. A sample with a non-finite channel is left out
/// (the mean stays; a new mean starts at 0), so NaN and ∞ never enter the accumulation.
pub fn running_mean(mean: Vec4, sample: Vec4, weight: f32) -> Vec4 {
    let finite = sample.is_finite();
    if weight >= 1.0 {
        return if finite { sample } else { Vec4::ZERO };
    }
    if !finite {
        return mean;
    }
    mean + (sample - mean) * weight
}

/// Karis's luminance compression (Karis 2014, "High Quality Temporal Supersampling"):
/// `c / (1 + Y(c))`, which maps HDR colour into [0, 1) luminance so that a filter that
/// blends neighbours weighs a highlight as the display shows it, not by its radiance.
pub fn compress_hdr(c: Vec3) -> Vec3 {
    c / (1.0 + luminance(c).max(0.0))
}

/// The inverse of [`compress_hdr`]: `c / (1 − Y(c))`, with the denominator kept ≥ 10⁻⁴
/// (a compressed luminance of 1 would be infinite radiance). The round trip loses
/// precision as the luminance grows (relative error about Y · 2⁻²⁴ in f32): 10⁻⁴ at
/// Y = 1000, far above a pre-exposed frame's highlights.
pub fn expand_hdr(c: Vec3) -> Vec3 {
    c / (1.0 - luminance(c)).max(1e-4)
}

/// The perceptual luma FXAA compares (Lottes 2009, "FXAA"): the square root of the
/// compressed colour's luminance, close to a display's gamma-encoded brightness.
pub fn fxaa_luma(compressed: Vec3) -> f32 {
    luminance(compressed).max(0.0).sqrt()
}

/// RGB → YCoCg (Malvar & Sullivan 2003): luma and two chroma differences, the space in
/// which TAA measures a neighbourhood's colour range (luma and chroma separate, so the
/// range is tight along the colours that actually vary).
pub fn rgb_to_ycocg(c: Vec3) -> Vec3 {
    Vec3::new(
        0.25 * c.x + 0.5 * c.y + 0.25 * c.z,
        0.5 * c.x - 0.5 * c.z,
        -0.25 * c.x + 0.5 * c.y - 0.25 * c.z,
    )
}

/// YCoCg → RGB, the inverse of [`rgb_to_ycocg`].
pub fn ycocg_to_rgb(c: Vec3) -> Vec3 {
    Vec3::new(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z)
}

/// Clips `history` towards `mean` into the box `mean ± extent` (Karis 2014, "High
/// Quality Temporal Supersampling"): a history colour outside the box moves along the
/// line to the mean until it meets the box, so a stale colour is replaced by the nearest
/// plausible one instead of being clamped channel by channel. `extent` is per channel,
/// > 0 (Salvi 2016's variance clipping: γ σ of the neighbourhood).
pub fn clip_towards_mean(history: Vec3, mean: Vec3, extent: Vec3) -> Vec3 {
    let d = history - mean;
    let t = (d.abs() / extent.max(Vec3::splat(1e-6))).max_element();
    if t > 1.0 { mean + d / t } else { history }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_mean_is_the_mean_and_keeps_nan_out() {
        let xs = [1.0f32, 4.0, -2.0, 9.0];
        let mut m = Vec4::splat(123.0);
        for (i, x) in xs.iter().enumerate() {
            m = running_mean(m, Vec4::splat(*x), 1.0 / (i + 1) as f32);
        }
        assert!((m.x - 3.0).abs() < 1e-6, "{m}");
        assert_eq!(running_mean(m, Vec4::splat(f32::NAN), 0.2), m);
        assert_eq!(running_mean(m, Vec4::splat(f32::INFINITY), 1.0), Vec4::ZERO);
    }

    #[test]
    fn ycocg_round_trips_and_clipping_lands_on_the_box() {
        let c = Vec3::new(0.3, 0.7, 0.1);
        assert!((ycocg_to_rgb(rgb_to_ycocg(c)) - c).abs().max_element() < 1e-6);
        let mean = Vec3::new(0.5, 0.0, 0.0);
        let extent = Vec3::new(0.1, 0.05, 0.05);
        let inside = Vec3::new(0.55, 0.01, -0.02);
        assert_eq!(clip_towards_mean(inside, mean, extent), inside);
        let clipped = clip_towards_mean(Vec3::new(0.9, 0.0, 0.0), mean, extent);
        assert!(
            (clipped - Vec3::new(0.6, 0.0, 0.0)).length() < 1e-6,
            "{clipped}"
        );
    }

    #[test]
    fn compression_round_trips_and_stays_below_one() {
        for c in [
            Vec3::ZERO,
            Vec3::new(0.2, 0.5, 0.9),
            Vec3::splat(1000.0),
            Vec3::new(900.0, 3.0, 0.0),
        ] {
            let k = compress_hdr(c);
            assert!(luminance(k) < 1.0, "{c} → {k}");
            let back = expand_hdr(k);
            assert!(
                (back - c).abs().max_element() <= 1e-3 * c.max_element().max(1.0),
                "{c} → {k} → {back}"
            );
        }
    }
}

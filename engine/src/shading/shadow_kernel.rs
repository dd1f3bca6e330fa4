//! CPU twin of `shaders/shadow_kernel.wgsl`: the taps of the `tent` shadow filter
//! ([`crate::quality::ShadowFilter::Tent`]).
//!
//! Castaño's optimised PCF (Castaño 2013, "Shadow Mapping Summary – Part 1"): per axis the
//! kernel [1 3 4 3 1] / 12 (the 3-texel box convolved with the [1 2 1] tent), 5 × 5
//! texels, moved continuously with the receiver by bilinear interpolation. Per axis its
//! weights over 6 texels are (1 − s, 3 − 2s, 4 − s, 3 + s, 1 + 2s, s) / 12, where
//! s ∈ [0, 1) is how far the receiver lies past the centre of the texel just before its
//! nearest texel corner. Three bilinear comparison taps per axis give exactly those
//! weights: 9 taps in all instead of 36 point comparisons.

use glam::Vec3;

/// The weights of the three taps along one axis (dimensionless, sum 1), for the receiver
/// `s` texels past the centre of the texel just before its nearest corner (0 ≤ s < 1).
pub fn shadow_tent_weights(s: f32) -> Vec3 {
    Vec3::new(4.0 - 3.0 * s, 7.0, 1.0 + 3.0 * s) / 12.0
}

/// Where the three taps along one axis sample, in texels from the centre of the texel
/// just before the receiver's nearest corner (`s` as for [`shadow_tent_weights`]).
pub fn shadow_tent_offsets(s: f32) -> Vec3 {
    Vec3::new(
        (3.0 - 2.0 * s) / (4.0 - 3.0 * s) - 2.0,
        (3.0 + s) / 7.0,
        s / (1.0 + 3.0 * s) + 2.0,
    )
}

/// The 2 × 2 Bayer index of (x, y) in {0, 1}²: `0 2 / 3 1` by rows.
pub fn bayer2(x: u32, y: u32) -> u32 {
    2 * (x ^ y) + y
}

/// The ordered-dither threshold (0..1) of shadow-atlas texel (x, y) for a blended caster:
/// the 4 × 4 Bayer matrix (Bayer 1973, "An optimum method for two-level rendition of
/// continuous-tone pictures"), built from the 2 × 2 one, as (index + 0.5) / 16. A blended
/// caster of coverage α keeps the texels whose threshold is below α: every 4 × 4 block
/// holds 16 α of them (rounded), and the `tent` filter's 5 × 5 footprint reads a visibility
/// close to 1 − α.
pub fn blended_shadow_threshold(x: u32, y: u32) -> f32 {
    let (x, y) = (x & 3, y & 3);
    let index = 4 * bayer2(x & 1, y & 1) + bayer2(x >> 1, y >> 1);
    (index as f32 + 0.5) / 16.0
}

/// Relative depth difference (of the pixel's view depth) at which a shadow-mask texel
/// stops counting in the depth-aware upsample: 5 %.
pub const SHADOW_MASK_DEPTH_TOLERANCE: f32 = 0.05;

/// The weight (dimensionless) of one shadow-mask texel in a pixel's depth-aware upsample
/// ([`crate::render::shadow::mask`]): its bilinear weight `bilinear`, times a tent in depth
/// that falls from 1 where the texel's view depth `texel_depth` (m) equals the pixel's
/// `depth` (m) to 0 at [`SHADOW_MASK_DEPTH_TOLERANCE`] × `depth`, so that a shadow is not
/// carried across a depth edge (the joint bilateral upsample of Kopf et al. 2007, "Joint
/// Bilateral Upsampling", with a tent range kernel).
pub fn shadow_mask_weight(bilinear: f32, texel_depth: f32, depth: f32) -> f32 {
    let range = SHADOW_MASK_DEPTH_TOLERANCE * depth.max(1e-6);
    bilinear * (1.0 - (texel_depth - depth).abs() / range).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weight each texel gets from the three bilinear taps, for texels −2..=3 from the
    /// texel before the corner: a tap at offset u splits its weight between the texels
    /// floor(u) and floor(u) + 1 by the fraction of u.
    fn texel_weights(s: f32) -> [f32; 6] {
        let (w, o) = (shadow_tent_weights(s), shadow_tent_offsets(s));
        let mut out = [0.0; 6];
        for k in 0..3 {
            let first = o[k].floor();
            let f = o[k] - first;
            let i = (first as i32 + 2) as usize;
            out[i] += w[k] * (1.0 - f);
            if f > 0.0 {
                out[i + 1] += w[k] * f;
            }
        }
        out
    }

    #[test]
    fn three_bilinear_taps_are_the_box_convolved_with_the_tent() {
        for i in 0..=64 {
            let s = i as f32 / 64.0 * 0.999;
            let want =
                [1.0 - s, 3.0 - 2.0 * s, 4.0 - s, 3.0 + s, 1.0 + 2.0 * s, s].map(|x| x / 12.0);
            let got = texel_weights(s);
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() < 1e-6, "s = {s}: {got:?} vs {want:?}");
            }
            assert!((shadow_tent_weights(s).element_sum() - 1.0).abs() < 1e-6);
        }
        // Continuous as the receiver crosses a corner: s → 1 is s = 0 one texel on.
        let end = texel_weights(0.99999);
        let start = texel_weights(0.0);
        for k in 0..5 {
            assert!((end[k + 1] - start[k]).abs() < 1e-4, "{end:?} vs {start:?}");
        }
    }

    #[test]
    fn every_4x4_block_holds_each_dither_threshold_once() {
        // The 16 thresholds of any aligned 4 × 4 block are (k + 0.5) / 16 for k = 0..15,
        // so a coverage α keeps round(16 α) texels of every block.
        for (bx, by) in [(0, 0), (4, 8), (1000, 12)] {
            let mut seen: Vec<f32> = (0..16)
                .map(|k| blended_shadow_threshold(bx + k % 4, by + k / 4))
                .collect();
            seen.sort_by(f32::total_cmp);
            let want: Vec<f32> = (0..16).map(|k| (k as f32 + 0.5) / 16.0).collect();
            assert_eq!(seen, want);
        }
        // The 2 × 2 matrix 0 2 / 3 1, and its first row spread out: 0 8 2 10.
        assert_eq!(
            [bayer2(0, 0), bayer2(1, 0), bayer2(0, 1), bayer2(1, 1)],
            [0, 2, 3, 1]
        );
        let row: Vec<f32> = (0..4)
            .map(|x| blended_shadow_threshold(x, 0) * 16.0 - 0.5)
            .collect();
        assert_eq!(row, [0.0, 8.0, 2.0, 10.0]);
    }

    #[test]
    fn a_mask_texel_across_a_depth_edge_gets_no_weight() {
        // Same depth: the bilinear weight alone.
        assert_eq!(shadow_mask_weight(0.25, 10.0, 10.0), 0.25);
        // Half the tolerance away: half the weight, on either side.
        assert!((shadow_mask_weight(1.0, 10.25, 10.0) - 0.5).abs() < 1e-6);
        assert!((shadow_mask_weight(1.0, 9.75, 10.0) - 0.5).abs() < 1e-6);
        // At or past the tolerance, and on the background (depth −1): none.
        assert_eq!(shadow_mask_weight(1.0, 10.5, 10.0), 0.0);
        assert_eq!(shadow_mask_weight(1.0, 20.0, 10.0), 0.0);
        assert_eq!(shadow_mask_weight(1.0, -1.0, 10.0), 0.0);
    }
}

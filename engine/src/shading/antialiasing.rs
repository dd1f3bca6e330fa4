//! The anti-aliasing formulas on the CPU, each the twin of the function with the same
//! name in `shaders/antialiasing.wgsl` (held together by `tests/shader_parity.rs`).
//!
//! Colours are pre-exposed linear HDR luminance (dimensionless once exposed, 1 ≈ the
//! display's white before tone mapping).

use crate::shading::color::luminance;
use glam::{Vec2, Vec3, Vec4};

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

/// The perceptual luma FXAA and SMAA compare (Lottes 2009, "FXAA"): the square root of
/// the compressed colour's luminance, close to a display's gamma-encoded brightness.
pub fn perceptual_luma(compressed: Vec3) -> f32 {
    luminance(compressed).max(0.0).sqrt()
}

/// How sharply the depth bends at a pixel, from its reversed-Z depth `centre` and its four
/// neighbours' (north, south, west, east): the larger of the horizontal and vertical second
/// differences, relative to the largest of the five depths (0 where all are 0, the
/// background). Reversed-Z depth is affine in 1/z (z the view depth, m), and 1/z varies
/// linearly across the screen on any plane (Heckbert & Moreton 1991, "Interpolation for
/// Polygon Texture Mapping and Shading"), so the bend is 0 inside a flat surface, small on
/// a curved one, and of the order of 1 where one surface ends in front of another. FXAA
/// filters only pixels whose bend exceeds [`SILHOUETTE_BEND`], or where the normals crease
/// ([`creased`]).
pub fn depth_bend(centre: f32, north: f32, south: f32, west: f32, east: f32) -> f32 {
    let scale = centre.max(north).max(south).max(west).max(east);
    let second = (north + south - 2.0 * centre)
        .abs()
        .max((west + east - 2.0 * centre).abs());
    if scale > 0.0 { second / scale } else { 0.0 }
}

/// The [`depth_bend`] above which FXAA treats a pixel as on a silhouette (dimensionless).
/// A sphere of 50 pixels' radius 3 m away bends by less than 0.006 except on its rim
/// pixel; the rim of an object 2 m away in front of a wall 3 m away, by more than 0.3.
pub const SILHOUETTE_BEND: f32 = 0.02;

/// Whether unit normals `a` and `b` meet at a crease: the edge between two faces of one
/// object (a cube's corner seen against its own faces), which bends the depth too little
/// to count as a silhouette. An angle of more than 60° between them
/// (`a · b` < [`CREASE_COSINE`]).
pub fn creased(a: Vec3, b: Vec3) -> bool {
    a.dot(b) < CREASE_COSINE
}

/// The cosine of the smallest angle between two normals that [`creased`] calls a crease
/// (60°).
pub const CREASE_COSINE: f32 = 0.5;

/// SMAA's luma edge test (Jimenez et al. 2012, "SMAA: Enhanced Subpixel Morphological
/// Antialiasing", §3.1, with local contrast adaptation): a luma step `delta` between two
/// neighbours is an edge if it reaches `threshold` and at least half of `local_max`, the
/// largest step around the pixel, so a weak edge beside a strong one is left to the
/// strong one. Returns 1 for an edge, 0 otherwise.
pub fn smaa_edge(delta: f32, local_max: f32, threshold: f32) -> f32 {
    if delta >= threshold && 2.0 * delta >= local_max {
        1.0
    } else {
        0.0
    }
}

/// The height of a revectorized silhouette at one end of an edge segment (Reshetov 2009,
/// "Morphological Antialiasing"; Jimenez et al. 2012), from the crossing edges found
/// there: `crossing.x` on the neighbour's side of the segment, `crossing.y` on the
/// centre's side, and `beyond` the same two edges one pixel farther from the segment
/// (each 0 or 1). A crossing edge one pixel long is a staircase step to its side and puts
/// the line's end half a pixel onto that side (+½ the neighbour's, −½ the centre's). One
/// that continues beyond is the corner of a shape, which stays sharp (SMAA's corner
/// detection), as does an end with no step or steps to both sides (0).
pub fn smaa_end_height(crossing: Vec2, beyond: Vec2) -> f32 {
    let neighbour = crossing.x > 0.5 && beyond.x < 0.5;
    let centre = crossing.y > 0.5 && beyond.y < 0.5;
    match (neighbour, centre) {
        (true, false) => 0.5,
        (false, true) => -0.5,
        _ => 0.0,
    }
}

/// The area between the edge (height 0) and the straight line from `start` to `end`
/// (`start.x < end.x`; x along the edge in pixels, y across it) over the pixel column
/// `[column, column + 1]`: `.x` the part where the line is on the centre's side (y < 0),
/// `.y` the part on the neighbour's side (y > 0). Both in pixels (a pixel's area is 1).
pub fn line_coverage(column: f32, start: Vec2, end: Vec2) -> Vec2 {
    let lo = column.max(start.x);
    let hi = (column + 1.0).min(end.x);
    if hi <= lo {
        return Vec2::ZERO;
    }
    let slope = (end.y - start.y) / (end.x - start.x);
    let y0 = start.y + slope * (lo - start.x);
    let y1 = start.y + slope * (hi - start.x);
    if y0 * y1 < 0.0 {
        // The line crosses the edge inside the column: two triangles, one on each side.
        let cross = lo + (hi - lo) * y0 / (y0 - y1);
        let (a0, a1) = (0.5 * y0 * (cross - lo), 0.5 * y1 * (hi - cross));
        return Vec2::new((-a0).max(0.0) + (-a1).max(0.0), a0.max(0.0) + a1.max(0.0));
    }
    let area = 0.5 * (y0 + y1) * (hi - lo);
    Vec2::new((-area).max(0.0), area.max(0.0))
}

/// SMAA's coverage of one pixel by its neighbour's colour across an edge segment, and of
/// the neighbour by the pixel's (Jimenez et al. 2012, orthogonal patterns, after
/// Reshetov 2009): the segment is `length` pixels long, the pixel is column `column` of it
/// (from 0), and `ends` are the silhouette's heights at its two ends
/// ([`smaa_end_height`]). The silhouette is revectorized as a straight line between
/// opposite ends (a Z: a staircase step), and otherwise as lines from each stepped end to
/// the segment's middle (an L or a U), but no farther than `reach` pixels (per end): the
/// length of the next stair past the step, so that a short bump on a long edge is not
/// read as a staircase's step. Returns (pixel covered by the neighbour's colour, neighbour
/// covered by the pixel's), each in [0, ½]. This is what SMAA's precomputed area texture
/// holds; Lumen evaluates it directly.
pub fn smaa_coverage(column: f32, length: f32, ends: Vec2, reach: Vec2) -> Vec2 {
    if ends.x * ends.y < 0.0 {
        return line_coverage(column, Vec2::new(0.0, ends.x), Vec2::new(length, ends.y));
    }
    let half = 0.5 * length;
    let start = Vec2::new(half.min(reach.x), 0.0);
    let end = Vec2::new(length - half.min(reach.y), 0.0);
    line_coverage(column, Vec2::new(0.0, ends.x), start)
        + line_coverage(column, end, Vec2::new(length, ends.y))
}

/// The neighbour weight of contrast-adaptive sharpening (Lottes 2019, "FidelityFX
/// Contrast Adaptive Sharpening"), per channel, from the lowest (`lo`) and highest (`hi`)
/// compressed colour of a pixel and its four neighbours, and the strength (0..1):
/// `−strength/5 · √(min(lo, 1 − hi)/hi)`, so a pixel between a dark and a bright
/// neighbour, or near either end of the range, is sharpened least (no overshoot into
/// clipping). 0 at strength 0; at least −1/5.
pub fn cas_weight(lo: Vec3, hi: Vec3, strength: f32) -> Vec3 {
    let room = lo.min(Vec3::ONE - hi) / hi.max(Vec3::splat(1e-6));
    -room.clamp(Vec3::ZERO, Vec3::ONE).powf(0.5) * strength.clamp(0.0, 1.0) / 5.0
}

/// Contrast-adaptive sharpening applied: the centre `c` and the sum of its four
/// neighbours `cross` (compressed colours) mixed with the weight `w` of [`cas_weight`],
/// `(c + w · cross)/(1 + 4w)`, made non-negative and scaled down where its luminance
/// passes `cap` (the brightest compressed luminance around, < 1, so that expanding it
/// stays finite and no pixel outshines its neighbourhood).
pub fn cas_apply(c: Vec3, cross: Vec3, w: Vec3, cap: f32) -> Vec3 {
    let r = ((c + w * cross) / (Vec3::ONE + 4.0 * w)).max(Vec3::ZERO);
    let y = luminance(r);
    if y > cap { r * (cap / y) } else { r }
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
    fn smaa_coverage_is_the_area_under_the_revectorized_line() {
        let far = Vec2::splat(100.0);
        // A Z step over 4 pixels: the line runs from −½ to +½ and crosses the edge in the
        // middle; the first pixel's trapezoid between heights −½ and −¼ is 3/8 of a pixel.
        let ends = Vec2::new(-0.5, 0.5);
        assert!((smaa_coverage(0.0, 4.0, ends, far) - Vec2::new(0.375, 0.0)).length() < 1e-6);
        assert!((smaa_coverage(3.0, 4.0, ends, far) - Vec2::new(0.0, 0.375)).length() < 1e-6);
        // The middle of an odd segment is split into two triangles of 1/24 each.
        let mid = smaa_coverage(1.0, 3.0, ends, far);
        assert!((mid - Vec2::splat(1.0 / 24.0)).length() < 1e-6, "{mid}");
        // An L only covers the half on its stepped end, and no more than its reach; no
        // step, no coverage.
        let l = Vec2::new(0.5, 0.0);
        assert!(smaa_coverage(0.0, 4.0, l, far).y > 0.2);
        assert_eq!(smaa_coverage(2.0, 4.0, l, far), Vec2::ZERO);
        assert!(smaa_coverage(3.0, 16.0, l, far).y > 0.0);
        assert_eq!(smaa_coverage(3.0, 16.0, l, Vec2::splat(3.0)), Vec2::ZERO);
        assert_eq!(smaa_coverage(0.0, 4.0, Vec2::ZERO, far), Vec2::ZERO);
        // Over the whole segment, a Z covers on each side the triangle between its line
        // and the edge: ½ · (8/2) · ½ = 1 pixel.
        let total: Vec2 = (0..8)
            .map(|c| smaa_coverage(c as f32, 8.0, ends, far))
            .sum();
        assert!((total - Vec2::new(1.0, 1.0)).length() < 1e-5, "{total}");
        assert_eq!(smaa_end_height(Vec2::new(1.0, 1.0), Vec2::ZERO), 0.0);
        assert_eq!(smaa_end_height(Vec2::new(0.0, 1.0), Vec2::ZERO), -0.5);
        assert_eq!(
            smaa_end_height(Vec2::new(0.0, 1.0), Vec2::new(0.0, 1.0)),
            0.0
        );
        assert_eq!(
            smaa_end_height(Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)),
            0.5
        );
    }

    #[test]
    fn sharpening_steepens_and_stays_in_range() {
        // A pixel a little brighter than its neighbours gets brighter, but not past the cap.
        let c = Vec3::splat(0.5);
        let cross = Vec3::splat(4.0 * 0.4);
        let w = cas_weight(Vec3::splat(0.4), Vec3::splat(0.5), 1.0);
        assert!((w.x - (-0.2 * (0.4f32 / 0.5).sqrt())).abs() < 1e-6, "{w}");
        let out = cas_apply(c, cross, w, 0.9);
        assert!(out.x > 0.5 && luminance(out) <= 0.9 + 1e-6, "{out}");
        let capped = cas_apply(c, cross, w, 0.52);
        assert!((luminance(capped) - 0.52).abs() < 1e-5, "{capped}");
        assert_eq!(
            cas_weight(Vec3::splat(0.4), Vec3::splat(0.5), 0.0),
            Vec3::ZERO
        );
        assert_eq!(cas_weight(Vec3::ZERO, Vec3::splat(0.5), 1.0), Vec3::ZERO);
        assert_eq!(cas_apply(c, cross, Vec3::ZERO, 1.0), c);
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

    #[test]
    fn depth_bends_only_where_one_surface_ends_in_front_of_another() {
        // The bend at pixel (0, 0) of a depth image given as a function of the pixel.
        let bend_of = |d: &dyn Fn(f32, f32) -> f32| {
            depth_bend(
                d(0.0, 0.0),
                d(0.0, -1.0),
                d(0.0, 1.0),
                d(-1.0, 0.0),
                d(1.0, 0.0),
            )
        };
        // A plane seen at an angle: reversed-Z depth 1/z steps evenly across the screen.
        let flat = bend_of(&|x, y| 0.4 + 0.03 * x - 0.02 * y);
        assert!(flat < 1e-6, "{flat}");
        // A sphere of 50 pixels' radius, 3 m away, half-way to its rim: 1/z of its surface.
        let curved = bend_of(&|x, y| {
            let (dx, dy) = (x / 50.0, y / 50.0);
            1.0 / (3.0 - (1.0 - (0.5 + dx).powi(2) - dy * dy).sqrt())
        });
        assert!(curved < 0.2 * SILHOUETTE_BEND, "{curved}");
        // The rim of an object 2 m away in front of a wall 3 m away, and in front of sky.
        let (near, far) = (1.0 / 2.0, 1.0 / 3.0);
        let rim = depth_bend(near, near, near, far, near);
        assert!(rim > 10.0 * SILHOUETTE_BEND, "{rim}");
        assert!(depth_bend(near, near, near, 0.0, near) > 0.9);
        assert_eq!(depth_bend(0.0, 0.0, 0.0, 0.0, 0.0), 0.0);
    }

    #[test]
    fn normals_crease_beyond_sixty_degrees() {
        let turned = |deg: f32| Vec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        assert!(!creased(Vec3::Z, Vec3::Z));
        assert!(!creased(Vec3::Z, turned(45.0)));
        assert!(!creased(Vec3::Z, turned(59.0)));
        assert!(creased(Vec3::Z, turned(61.0)));
        // Two faces of a cube.
        assert!(creased(Vec3::X, Vec3::Y));
    }
}

//! Reflection probes: the formulas, the same as `shaders/reflection_probe.wgsl` (same
//! names, bound by the parity test).
//!
//! A probe's cube map is what the scene looks like from one point. A surface elsewhere
//! that looks it up along its reflected direction would see the scene from the wrong place.
//! Parallax correction (Lagarde & Zanuttini 2012, "Local Image-based Lighting With
//! Parallax-corrected Cubemap", SIGGRAPH talk) treats the probe's box as the walls the
//! probe saw: it intersects the reflected ray with the box and looks up the direction from
//! the probe to that hit instead.

use glam::Vec3;

/// The direction (not normalised) from `probe` to where the ray from `p` along `dir`
/// leaves the box `box_min`..`box_max` (m). A point outside the box, or a zero direction,
/// gets `dir` back.
pub fn parallax_corrected(p: Vec3, dir: Vec3, box_min: Vec3, box_max: Vec3, probe: Vec3) -> Vec3 {
    let inv = Vec3::new(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z);
    let a = (box_max - p) * inv;
    let b = (box_min - p) * inv;
    let far = a.max(b);
    let t = far.x.min(far.y).min(far.z);
    if !(t.is_finite() && t > 0.0) {
        return dir;
    }
    p + dir * t - probe
}

/// A probe's weight at `p`: 1 deeper than `blend_m` metres inside its box (centre
/// `center`, half-size `half_extents`, m), falling linearly to 0 at the box's faces, 0
/// outside.
pub fn box_weight(p: Vec3, center: Vec3, half_extents: Vec3, blend_m: f32) -> f32 {
    let inside = half_extents - (p - center).abs();
    let depth = inside.min_element();
    if depth.is_nan() || depth <= 0.0 {
        return 0.0;
    }
    (depth / blend_m.max(1e-6)).min(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_from_the_probe_needs_no_correction() {
        let probe = Vec3::new(0.5, 1.0, -0.5);
        let dir = Vec3::new(0.3, -0.8, 0.2);
        let c = parallax_corrected(probe, dir, Vec3::splat(-2.0), Vec3::splat(3.0), probe);
        assert!((c.normalize() - dir.normalize()).length() < 1e-6);
    }

    #[test]
    fn a_ray_elsewhere_looks_up_the_wall_it_hits() {
        // A floor at y = 0 seen straight down from (1, 1, 0), probe at (0, 1, 0): the hit
        // is (1, 0, 0), which the probe sees along (1, −1, 0).
        let c = parallax_corrected(
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::NEG_Y,
            Vec3::new(-5.0, 0.0, -5.0),
            Vec3::new(5.0, 5.0, 5.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        assert!((c - Vec3::new(1.0, -1.0, 0.0)).length() < 1e-6, "{c}");
        let outside =
            parallax_corrected(Vec3::splat(9.0), Vec3::X, Vec3::ZERO, Vec3::ONE, Vec3::ZERO);
        assert_eq!(outside, Vec3::X);
    }

    #[test]
    fn weights_fade_at_the_faces() {
        let h = Vec3::splat(2.0);
        assert_eq!(box_weight(Vec3::ZERO, Vec3::ZERO, h, 0.5), 1.0);
        assert!((box_weight(Vec3::new(1.75, 0.0, 0.0), Vec3::ZERO, h, 0.5) - 0.5).abs() < 1e-6);
        assert_eq!(
            box_weight(Vec3::new(2.5, 0.0, 0.0), Vec3::ZERO, h, 0.5),
            0.0
        );
        assert_eq!(box_weight(Vec3::splat(f32::NAN), Vec3::ZERO, h, 0.5), 0.0);
        assert_eq!(box_weight(Vec3::ZERO, Vec3::ZERO, h, 0.0), 1.0);
    }
}

//! Ambient occlusion's formulas: ground-truth ambient occlusion (GTAO, Jimenez, Wu,
//! Pesce & Jarabo 2016, "Practical Real-Time Strategies for Accurate Indirect
//! Occlusion"), the CPU twins of `shaders/ambient_occlusion.wgsl` (same names; the parity
//! test `tests/shader_parity.rs` binds them).
//!
//! GTAO measures, per pixel, the cosine-weighted fraction of the hemisphere above the
//! surface that the depth buffer leaves open. The hemisphere is cut into slices: planes
//! that contain the view direction, one per screen-space direction. In each slice the
//! depth buffer is marched on both sides to find the highest horizon, and the visible arc
//! between the two horizons is integrated in closed form against the normal projected into
//! the slice ([`gtao_slice`]). The mean over slices, weighted by the projected normal's
//! length, is 1 on an open plane whatever the view angle (a test below checks it).
//! Chapter "Indirect light" of the book gives the derivation's steps.

use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_PI_2;

/// Fraction of the AO radius over which an occluder's weight falls from 1 to 0 (its outer
/// part); [`ao_falloff`].
pub const FALLOFF_RANGE: f32 = 0.4;

/// Weight (0..1) of an occluder at `distance_m` metres from the shaded point, for an AO
/// radius of `radius_m` metres: 1 up to `(1 − FALLOFF_RANGE) · radius`, then falling
/// linearly to 0 at the radius. Both the screen-space pass and the path tracer's AO mode
/// weight occluders with it, so they measure the same quantity.
pub fn ao_falloff(distance_m: f32, radius_m: f32) -> f32 {
    ((radius_m - distance_m) / (FALLOFF_RANGE * radius_m).max(1e-6)).clamp(0.0, 1.0)
}

/// The normal `n` projected into the slice plane spanned by the view direction `v` (unit,
/// towards the camera) and the world direction `dir` of the slice's positive screen side:
/// (length of the projection, its signed angle from `v` in radians, positive towards
/// `dir`).
pub fn gtao_projected_normal(n: Vec3, v: Vec3, dir: Vec3) -> Vec2 {
    let ortho = (dir - v * dir.dot(v)).normalize_or_zero();
    let axis = ortho.cross(v);
    let projected = n - axis * n.dot(axis);
    let length = projected.length();
    if length <= 1e-6 {
        return Vec2::ZERO;
    }
    let cos_n = (projected.dot(v) / length).clamp(-1.0, 1.0);
    Vec2::new(length, sign(projected.dot(ortho)) * cos_n.acos())
}

/// The cosines of the horizons of an unoccluded slice: the tangent plane, at angles
/// `n − π/2` (negative side) and `n + π/2` (positive side) for a projected normal at
/// angle `n` (radians).
pub fn gtao_open_horizons(n_angle: f32) -> Vec2 {
    Vec2::new(n_angle.sin(), -n_angle.sin())
}

/// Cosine-weighted visible arc of one slice between horizon angles `h0 ≤ 0 ≤ h1`
/// (radians from the view direction) for a projected normal at angle `n` (Jimenez et al.
/// 2016, eq. 10): `¼(−cos(2h₀ − n) + cos n + 2h₀ sin n) + ¼(−cos(2h₁ − n) + cos n +
/// 2h₁ sin n)`; 1 for `n = 0` and an open slice.
pub fn gtao_slice_visibility(h0: f32, h1: f32, n: f32) -> f32 {
    let arc = |h: f32| 0.25 * (-(2.0 * h - n).cos() + n.cos() + 2.0 * h * n.sin());
    arc(h0) + arc(h1)
}

/// One slice's visibility weighted by the projected normal's length: `projected` from
/// [`gtao_projected_normal`], `horizon_cos` the cosines (with `v`) of the highest
/// horizon found on the negative and positive sides. Each horizon is clamped to the
/// hemisphere around the projected normal.
pub fn gtao_slice(projected: Vec2, horizon_cos: Vec2) -> f32 {
    let (length, n) = (projected.x, projected.y);
    let h0 = -horizon_cos.x.clamp(-1.0, 1.0).acos();
    let h1 = horizon_cos.y.clamp(-1.0, 1.0).acos();
    let h0 = n + (h0 - n).max(-FRAC_PI_2);
    let h1 = n + (h1 - n).min(FRAC_PI_2);
    length * gtao_slice_visibility(h0, h1, n)
}

/// Multiple-bounce ambient occlusion (Jimenez et al. 2016, eq. 16): the visibility
/// `visibility` of a surface of albedo `albedo` brightened by the light its occluders
/// (assumed of the same albedo) bounce back, a cubic fitted to path-traced scenes:
/// `max(x, ((a·x + b)·x + c)·x)` with `a = 2.0404ρ − 0.3324`, `b = −4.7951ρ + 0.6417`,
/// `c = 2.7552ρ + 0.6903`.
pub fn gtao_multi_bounce(visibility: f32, albedo: Vec3) -> Vec3 {
    let a = 2.0404 * albedo - Vec3::splat(0.3324);
    let b = -4.7951 * albedo + Vec3::splat(0.6417);
    let c = 2.7552 * albedo + Vec3::splat(0.6903);
    let x = Vec3::splat(visibility);
    x.max(((a * x + b) * x + c) * x)
}

/// The occlusion indirect light sees, from the material's baked occlusion and the
/// screen-space pass's: the smaller. Both estimate the same visibility integral (a baked
/// map from the mesh's own geometry, the pass from the depth buffer), so where both see
/// the same occluder a product would count it twice; the minimum keeps the stronger
/// estimate and never darkens below either (Filament combines them the same way).
pub fn combine_occlusion(material: f32, screen: f32) -> f32 {
    material.min(screen)
}

/// WGSL's `sign`: −1, 0 or 1.
fn sign(x: f32) -> f32 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// The slice-weighted mean of an open hemisphere, over `slices` slices around `v`.
    fn open_visibility(n: Vec3, v: Vec3, slices: u32) -> f32 {
        let b1 = v.any_orthonormal_vector();
        let b2 = v.cross(b1);
        let sum: f32 = (0..slices)
            .map(|i| {
                let phi = (i as f32 + 0.5) / slices as f32 * PI;
                let dir = b1 * phi.cos() + b2 * phi.sin();
                let projected = gtao_projected_normal(n, v, dir);
                gtao_slice(projected, gtao_open_horizons(projected.y))
            })
            .sum();
        sum / slices as f32
    }

    #[test]
    fn an_open_plane_is_unoccluded_from_any_view() {
        for (n, v) in [
            (Vec3::Y, Vec3::Y),
            (Vec3::Y, Vec3::new(0.0, 0.2, 1.0).normalize()),
            (
                Vec3::new(0.3, 1.0, -0.2).normalize(),
                Vec3::new(-0.5, 0.6, 0.6).normalize(),
            ),
            (Vec3::X, Vec3::new(0.05, 0.0, 1.0).normalize()),
        ] {
            let ao = open_visibility(n, v, 512);
            assert!((ao - 1.0).abs() < 2e-3, "n {n} v {v}: {ao}");
        }
    }

    #[test]
    fn a_horizon_at_the_view_direction_halves_a_facing_slice() {
        // Normal towards the viewer, positive side blocked up to the view direction.
        let v = gtao_slice(Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0));
        assert!((v - 0.5).abs() < 1e-6, "{v}");
        assert!((gtao_slice_visibility(-FRAC_PI_2, FRAC_PI_2, 0.0) - 1.0).abs() < 1e-6);
        assert_eq!(gtao_slice(Vec2::ZERO, Vec2::ZERO), 0.0);
    }

    #[test]
    fn falloff_and_combination() {
        assert_eq!(ao_falloff(0.0, 1.0), 1.0);
        assert_eq!(ao_falloff(0.4, 1.0), 1.0);
        assert!((ao_falloff(0.8, 1.0) - 0.5).abs() < 1e-6);
        assert_eq!(ao_falloff(1.0, 1.0), 0.0);
        assert_eq!(ao_falloff(5.0, 0.0), 0.0);
        assert_eq!(combine_occlusion(0.3, 0.8), 0.3);
        assert_eq!(combine_occlusion(1.0, 0.6), 0.6);
    }

    #[test]
    fn multi_bounce_brightens_with_albedo_and_keeps_the_ends() {
        for albedo in [0.0f32, 0.5, 1.0] {
            let one = gtao_multi_bounce(1.0, Vec3::splat(albedo));
            assert!((one.x - 1.0).abs() < 2e-3, "{albedo}: {one}");
            assert_eq!(gtao_multi_bounce(0.0, Vec3::splat(albedo)), Vec3::ZERO);
        }
        let dark = gtao_multi_bounce(0.5, Vec3::splat(0.1)).x;
        let bright = gtao_multi_bounce(0.5, Vec3::splat(0.9)).x;
        assert!(dark >= 0.5 && bright > dark + 0.1, "{dark} {bright}");
    }
}

//! Shared pieces of the path tracer's lobes and samplers: a shading frame, Smith's
//! masking and the concentric disk map.

use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

/// An orthonormal basis with `n` as its third column (Duff et al. 2017).
pub fn basis(n: Vec3) -> Mat3 {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Mat3::from_cols(
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
        n,
    )
}

/// Smith's masking for GGX (the exact separable form).
pub fn g1_ggx(n_dot_x: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    2.0 * n_dot_x / (n_dot_x + (a2 + (1.0 - a2) * n_dot_x * n_dot_x).sqrt())
}

/// Concentric map of the unit square onto the unit disk (Shirley & Chiu 1997).
pub fn concentric_disk(xi: Vec2) -> Vec2 {
    let p = xi * 2.0 - Vec2::ONE;
    if p == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if p.x.abs() > p.y.abs() {
        (p.x, PI / 4.0 * (p.y / p.x))
    } else {
        (p.y, PI / 2.0 - PI / 4.0 * (p.x / p.y))
    };
    Vec2::new(r * theta.cos(), r * theta.sin())
}

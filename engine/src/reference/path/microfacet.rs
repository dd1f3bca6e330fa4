//! Shared pieces of the path tracer's microfacet lobes: a shading frame and Smith's
//! masking.

use glam::{Mat3, Vec3};

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

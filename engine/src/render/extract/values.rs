//! Value hygiene the extraction systems share: fallbacks for non-finite values, and
//! pre-exposure.

use glam::Vec3;

/// `x`, or `fallback` where `x` is NaN or infinite.
pub fn finite_or(x: f32, fallback: f32) -> f32 {
    if x.is_finite() { x } else { fallback }
}

/// `color` × `intensity` × `exposure`, pre-exposed radiance in f32 (negative or
/// non-finite intensities are 0).
pub fn exposed(color: Vec3, intensity: f32, exposure: f32) -> [f32; 3] {
    let intensity = finite_or(intensity, 0.0).max(0.0);
    let v = color * (intensity * exposure);
    // Huge values stay finite in f32; the lighting pass clamps what it writes to f16.
    v.min(Vec3::splat(f32::MAX)).into()
}

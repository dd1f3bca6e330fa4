//! Falloff of punctual (point and spot) lights on the CPU, the same as `shaders/punctual.wgsl`.
//!
//! Units (docs/src/formulas.md#photometric-lights): a punctual light has a luminous intensity I in candela
//! (lm/sr); at distance d (m) it gives the illuminance `E = I / d²` lux on a surface facing
//! it. A directional light gives its illuminance in lux directly.

/// Smallest squared distance (m²) used in the inverse-square law: a light closer than 1 cm
/// to a surface would otherwise give an infinite illuminance (docs/src/formulas.md#numerical-guards, Filament).
pub const MIN_DISTANCE_SQUARED: f32 = 1e-4;

/// Smallest difference of cosines between a spot light's inner and outer cone, so that
/// `inner = outer` never divides by zero (docs/src/formulas.md#numerical-guards).
pub const MIN_SPOT_COS_DELTA: f32 = 1e-4;

/// Inverse-square law `1 / max(d², 1e-4)` (1/m²).
pub fn inverse_square(distance_squared: f32) -> f32 {
    1.0 / distance_squared.max(MIN_DISTANCE_SQUARED)
}

/// Smooth window that takes the falloff to exactly 0 at the light's range r (m):
/// `saturate(1 − (d/r)⁴)²` (Karis 2013), computed from `d²` and `1/r²`, so culling lights at
/// their range never pops. `inv_range_squared = 0` means an unlimited range.
pub fn range_window(distance_squared: f32, inv_range_squared: f32) -> f32 {
    let factor = distance_squared * inv_range_squared;
    let window = (1.0 - factor * factor).clamp(0.0, 1.0);
    window * window
}

/// Distance attenuation of a punctual light: inverse-square law times the range window.
pub fn distance_attenuation(distance_squared: f32, inv_range_squared: f32) -> f32 {
    inverse_square(distance_squared) * range_window(distance_squared, inv_range_squared)
}

/// Scale and offset that map `cos(angle to the spot axis)` to the cone factor:
/// `scale = 1 / max(cos_inner − cos_outer, 1e-4)`, `offset = −cos_outer · scale`
/// (Filament). Angles are half-angles from the axis in radians.
pub fn spot_scale_offset(inner_angle: f32, outer_angle: f32) -> (f32, f32) {
    let outer = outer_angle.clamp(0.0, std::f32::consts::FRAC_PI_2);
    let inner = inner_angle.clamp(0.0, outer);
    let cos_outer = outer.cos();
    let cos_inner = inner.cos();
    let scale = 1.0 / (cos_inner - cos_outer).max(MIN_SPOT_COS_DELTA);
    (scale, -cos_outer * scale)
}

/// Smooth cone factor of a spot light: `saturate(cos θ · scale + offset)²`, 1 inside the
/// inner cone, 0 outside the outer cone.
pub fn spot_attenuation(cos_to_axis: f32, scale: f32, offset: f32) -> f32 {
    let t = (cos_to_axis * scale + offset).clamp(0.0, 1.0);
    t * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_square_law_and_its_guard() {
        assert_eq!(inverse_square(4.0), 0.25);
        assert_eq!(inverse_square(0.0), 1e4);
        assert_eq!(inverse_square(1e-12), 1e4);
    }

    #[test]
    fn range_window_goes_smoothly_to_zero() {
        let inv_r2 = 1.0 / (10.0f32 * 10.0);
        assert_eq!(range_window(0.0, inv_r2), 1.0);
        assert_eq!(range_window(100.0, inv_r2), 0.0);
        assert_eq!(range_window(400.0, inv_r2), 0.0);
        // d = r/2: (1 − 1/16)² = 0.87890625.
        assert!((range_window(25.0, inv_r2) - 0.878_906_25).abs() < 1e-6);
        // Unlimited range.
        assert_eq!(range_window(1e12, 0.0), 1.0);
        // Monotonic decrease.
        let mut last = 1.0;
        for i in 0..=100 {
            let w = range_window((i as f32 * 0.1).powi(2), inv_r2);
            assert!(w <= last + 1e-7);
            last = w;
        }
    }

    #[test]
    fn spot_cone() {
        let (s, o) = spot_scale_offset(0.3, 0.5);
        assert!((spot_attenuation(1.0, s, o) - 1.0).abs() < 1e-6);
        assert!((spot_attenuation(0.3f32.cos(), s, o) - 1.0).abs() < 1e-4);
        assert_eq!(spot_attenuation(0.6f32.cos(), s, o), 0.0);
        // inner = outer: a hard edge, finite.
        let (s, o) = spot_scale_offset(0.4, 0.4);
        assert!(s.is_finite() && o.is_finite());
        assert_eq!(spot_attenuation(0.5f32.cos(), s, o), 0.0);
        assert_eq!(spot_attenuation(0.3f32.cos(), s, o), 1.0);
        // inner > outer is clamped to inner = outer.
        let (s2, o2) = spot_scale_offset(0.9, 0.4);
        assert_eq!((s, o), (s2, o2));
    }
}

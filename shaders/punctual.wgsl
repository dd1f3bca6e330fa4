// Falloff of punctual lights, the same as engine/src/shading/punctual.rs (same names).
// Intensity in candela; E = I / d² lux (docs/src/formulas.md#photometric-lights).

const MIN_DISTANCE_SQUARED: f32 = 1e-4;

fn inverse_square(distance_squared: f32) -> f32 {
    return 1.0 / max(distance_squared, MIN_DISTANCE_SQUARED);
}

// saturate(1 − (d/r)⁴)² (Karis 2013); inv_range_squared = 0 is an unlimited range.
fn range_window(distance_squared: f32, inv_range_squared: f32) -> f32 {
    let factor = distance_squared * inv_range_squared;
    let window = clamp(1.0 - factor * factor, 0.0, 1.0);
    return window * window;
}

fn distance_attenuation(distance_squared: f32, inv_range_squared: f32) -> f32 {
    return inverse_square(distance_squared) * range_window(distance_squared, inv_range_squared);
}

// saturate(cos θ · scale + offset)², scale and offset from spot_scale_offset on the CPU.
fn spot_attenuation(cos_to_axis: f32, scale: f32, offset: f32) -> f32 {
    let t = clamp(cos_to_axis * scale + offset, 0.0, 1.0);
    return t * t;
}

// Camera optics, the same as the functions in engine/src/scene/camera.rs (same names).

// Signed thin-lens circle of confusion (diameter on the sensor, m), docs/src/formulas.md#thin-lens-depth-of-field:
// c = A f (z − S) / (z (S − f)); negative in front of the focus plane; S = ∞ → −A f / z.
fn circle_of_confusion(depth_m: f32, focus_m: f32, focal_length_m: f32, aperture_diameter_m: f32) -> f32 {
    let z = max(depth_m, 1e-6);
    let f = focal_length_m;
    if !(focus_m <= 3.0e38) {
        return -aperture_diameter_m * f / z;
    }
    let s = max(focus_m, f * 1.01);
    return aperture_diameter_m * f * (z - s) / (z * (s - f));
}

// Natural vignetting: cos⁴θ from tan²θ, blended by strength (0 none, 1 physical).
fn vignetting(tan2_theta: f32, strength: f32) -> f32 {
    let cos2 = 1.0 / (1.0 + max(tan2_theta, 0.0));
    return 1.0 + (cos2 * cos2 - 1.0) * clamp(strength, 0.0, 1.0);
}

// Reflection-probe formulas, the same as engine/src/shading/reflection_probe.rs (same names):
// parallax correction against the probe's box (Lagarde & Zanuttini 2012) and the box's
// weight.

// The direction from `probe` to where the ray from p along dir leaves the box
// box_min..box_max; dir itself for a point outside the box or a zero direction.
fn parallax_corrected(p: vec3<f32>, dir: vec3<f32>, box_min: vec3<f32>, box_max: vec3<f32>, probe: vec3<f32>) -> vec3<f32> {
    let inv = vec3<f32>(1.0) / dir;
    let a = (box_max - p) * inv;
    let b = (box_min - p) * inv;
    let far = max(a, b);
    let t = min(far.x, min(far.y, far.z));
    if !(t > 0.0 && t < 3.0e38) {
        return dir;
    }
    return p + dir * t - probe;
}

// 1 deeper than blend_m inside the box (centre, half-size), 0 at its faces and outside.
fn box_weight(p: vec3<f32>, center: vec3<f32>, half_extents: vec3<f32>, blend_m: f32) -> f32 {
    let inside = half_extents - abs(p - center);
    let depth = min(inside.x, min(inside.y, inside.z));
    if !(depth > 0.0) {
        return 0.0;
    }
    return min(depth / max(blend_m, 1e-6), 1.0);
}

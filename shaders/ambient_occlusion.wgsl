// Ambient occlusion's formulas (GTAO, Jimenez et al. 2016), the same as the functions in
// engine/src/shading/ambient_occlusion.rs (same names), where each is documented.
#import common

const FALLOFF_RANGE: f32 = 0.4;

// Weight of an occluder at distance_m for an AO radius radius_m: 1, then linear to 0.
fn ao_falloff(distance_m: f32, radius_m: f32) -> f32 {
    return clamp((radius_m - distance_m) / max(FALLOFF_RANGE * radius_m, 1e-6), 0.0, 1.0);
}

// The normal projected into the slice plane of v and dir: (length, signed angle from v).
fn gtao_projected_normal(n: vec3<f32>, v: vec3<f32>, dir: vec3<f32>) -> vec2<f32> {
    let o = dir - v * dot(dir, v);
    let ortho = select(vec3<f32>(0.0), o / sqrt(dot(o, o)), dot(o, o) > 0.0);
    let axis = cross(ortho, v);
    let projected = n - axis * dot(n, axis);
    let len = length(projected);
    if len <= 1e-6 {
        return vec2<f32>(0.0);
    }
    let cos_n = clamp(dot(projected, v) / len, -1.0, 1.0);
    return vec2<f32>(len, sign(dot(projected, ortho)) * acos(cos_n));
}

// Horizon cosines of an open slice: the tangent plane on both sides.
fn gtao_open_horizons(n_angle: f32) -> vec2<f32> {
    return vec2<f32>(sin(n_angle), -sin(n_angle));
}

// Cosine-weighted visible arc between horizon angles h0 <= 0 <= h1 (eq. 10).
fn gtao_slice_visibility(h0: f32, h1: f32, n: f32) -> f32 {
    let a0 = 0.25 * (-cos(2.0 * h0 - n) + cos(n) + 2.0 * h0 * sin(n));
    let a1 = 0.25 * (-cos(2.0 * h1 - n) + cos(n) + 2.0 * h1 * sin(n));
    return a0 + a1;
}

// One slice's visibility × the projected normal's length, from its horizon cosines.
fn gtao_slice(projected: vec2<f32>, horizon_cos: vec2<f32>) -> f32 {
    let n = projected.y;
    let h0 = n + max(-acos(clamp(horizon_cos.x, -1.0, 1.0)) - n, -0.5 * PI);
    let h1 = n + min(acos(clamp(horizon_cos.y, -1.0, 1.0)) - n, 0.5 * PI);
    return projected.x * gtao_slice_visibility(h0, h1, n);
}

// Multiple-bounce fit (eq. 16).
fn gtao_multi_bounce(visibility: f32, albedo: vec3<f32>) -> vec3<f32> {
    let a = 2.0404 * albedo - vec3<f32>(0.3324);
    let b = -4.7951 * albedo + vec3<f32>(0.6417);
    let c = 2.7552 * albedo + vec3<f32>(0.6903);
    let x = vec3<f32>(visibility);
    return max(x, ((a * x + b) * x + c) * x);
}

// Material and screen-space occlusion: the smaller.
fn combine_occlusion(material: f32, screen: f32) -> f32 {
    return min(material, screen);
}

// Shared constants and helpers. Twin of the helpers in engine/src/brdf.rs.

const PI: f32 = 3.14159265358979;

// Normalises v, or returns `fallback` when v is (nearly) zero, so that normalize(0)
// never produces NaN (docs/src/formulas.md#numerical-guards).
fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    if len2 > 1e-20 && len2 < 3.0e38 {
        return v * inverseSqrt(len2);
    }
    return fallback;
}

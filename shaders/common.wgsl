// Shared constants and helpers. Twin of the helpers in engine/src/shading/brdf.rs.

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

// The shading normal a tangent-space normal map gives (engine/src/scene/texture.rs,
// `normal_from_map`): the texel's rgb × 2 − 1, x and y × `scale`, in the frame of the
// unit normal n, the tangent made perpendicular to it and the bitangent n × t × the sign
// of tangent.w (glTF: bitangent = cross(normal, tangent) × w).
fn normal_from_map(n: vec3<f32>, tangent: vec4<f32>, texel: vec3<f32>, scale: f32) -> vec3<f32> {
    let t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3<f32>(1.0, 0.0, 0.0));
    let b = cross(n, t) * select(-1.0, 1.0, tangent.w >= 0.0);
    let tn = (texel * 2.0 - 1.0) * vec3<f32>(scale, scale, 1.0);
    return safe_normalize(t * tn.x + b * tn.y + n * tn.z, n);
}

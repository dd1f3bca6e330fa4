// G-buffer encodings, the same as engine/src/encoding.rs (same names).
// Octahedral normals (Cigolle et al. 2014).

fn sign_not_zero(v: vec2<f32>) -> vec2<f32> {
    return select(vec2<f32>(-1.0), vec2<f32>(1.0), v >= vec2<f32>(0.0));
}

fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if !(l1 > 1e-20 && l1 < 3.0e38) {
        return vec2<f32>(0.0);
    }
    let p = n.xy / l1;
    if n.z <= 0.0 {
        return (vec2<f32>(1.0) - abs(p.yx)) * sign_not_zero(p);
    }
    return p;
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var v = vec3<f32>(e.x, e.y, 1.0 - abs(e.x) - abs(e.y));
    if v.z < 0.0 {
        let folded = (vec2<f32>(1.0) - abs(v.yx)) * sign_not_zero(v.xy);
        v = vec3<f32>(folded.x, folded.y, v.z);
    }
    return normalize(v);
}

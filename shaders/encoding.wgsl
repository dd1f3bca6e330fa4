// G-buffer encodings, the same as engine/src/shading/encoding.rs (same names).
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

// gbuffer0.a: ambient occlusion in 7 bits and "receives shadows" in the top bit of the
// 8-bit UNORM channel.
fn pack_occlusion_receiver(occlusion: f32, receives_shadows: f32) -> f32 {
    var ao = 1.0;
    if occlusion == occlusion {
        ao = clamp(occlusion, 0.0, 1.0);
    }
    return (round(ao * 127.0) + select(0.0, 128.0, receives_shadows > 0.5)) / 255.0;
}

fn unpack_receives_shadows(a: f32) -> f32 {
    return select(0.0, 1.0, round(a * 255.0) >= 128.0);
}

// gbuffer2.a: the dielectric specular level (0..1), or UNLIT_SPECULAR_LEVEL for a
// surface that shows its base colour unlit (KHR_materials_unlit). Any negative instance
// level marks one (extraction clamps lit materials' levels to ≥ 0).
const UNLIT_SPECULAR_LEVEL: f32 = -1.0;

fn stored_specular_level(level: f32) -> f32 {
    return select(clamp(level, 0.0, 1.0), UNLIT_SPECULAR_LEVEL, level < 0.0);
}

fn is_unlit(stored_level: f32) -> bool {
    return stored_level < 0.0;
}

fn unpack_occlusion(a: f32) -> f32 {
    let v = round(a * 255.0);
    return (v - select(0.0, 128.0, v >= 128.0)) / 127.0;
}

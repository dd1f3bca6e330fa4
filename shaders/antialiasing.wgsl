// Anti-aliasing formulas; each has a Rust twin with the same name in
// engine/src/antialiasing.rs (tests/shader_parity.rs holds them together).
// Needs color.wgsl.

// Whether every channel is finite, from the exponent bits: WGSL lets a compiler assume
// floats are never NaN or ∞, so comparisons like c != c may be folded away.
fn is_finite4(c: vec4<f32>) -> bool {
    let exponent = bitcast<vec4<u32>>(c) & vec4<u32>(0x7f800000u);
    return all(exponent != vec4<u32>(0x7f800000u));
}

// One step of a running mean (Welford 1962): m + (x − m) w with w = 1/n; w ≥ 1 starts a
// new mean. A non-finite sample is left out, so NaN and ∞ never enter the accumulation.
fn running_mean(mean: vec4<f32>, sample: vec4<f32>, weight: f32) -> vec4<f32> {
    let finite = is_finite4(sample);
    if weight >= 1.0 {
        return select(vec4<f32>(0.0), sample, finite);
    }
    if !finite {
        return mean;
    }
    return mean + (sample - mean) * weight;
}

// Karis's luminance compression (Karis 2014): c / (1 + Y(c)).
fn compress_hdr(c: vec3<f32>) -> vec3<f32> {
    return c / (1.0 + max(luminance(c), 0.0));
}

// The inverse of compress_hdr: c / (1 − Y(c)), the denominator kept ≥ 1e-4.
fn expand_hdr(c: vec3<f32>) -> vec3<f32> {
    return c / max(1.0 - luminance(c), 1e-4);
}

// FXAA's perceptual luma (Lottes 2009): √Y of the compressed colour.
fn fxaa_luma(compressed: vec3<f32>) -> f32 {
    return sqrt(max(luminance(compressed), 0.0));
}

// RGB → YCoCg (Malvar & Sullivan 2003).
fn rgb_to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.25 * c.x + 0.5 * c.y + 0.25 * c.z, 0.5 * c.x - 0.5 * c.z, -0.25 * c.x + 0.5 * c.y - 0.25 * c.z);
}

// YCoCg → RGB.
fn ycocg_to_rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// Clips history towards mean into the box mean ± extent (Karis 2014; extent = γσ,
// Salvi 2016).
fn clip_towards_mean(history: vec3<f32>, mean: vec3<f32>, extent: vec3<f32>) -> vec3<f32> {
    let d = history - mean;
    let r = abs(d) / max(extent, vec3<f32>(1e-6));
    let t = max(r.x, max(r.y, r.z));
    if t > 1.0 {
        return mean + d / t;
    }
    return history;
}

// Weighted blended order-independent transparency (McGuire & Bavoil 2013, "Weighted
// Blended Order-Independent Transparency", JCGT 2(2)); the CPU twin is
// engine/src/shading/transparency.rs. Every blended fragment adds its premultiplied colour,
// weighted by oit_weight, to an accumulation target and multiplies a revealage target by
// 1 − α; oit_resolve turns the two into one premultiplied layer.

// The weight of a fragment of coverage `alpha` (0..1) at view depth `depth_m` (metres):
// α · clamp(10 / (10⁻⁵ + (z/5)² + (z/200)⁶), 10⁻², 3·10³), one of McGuire & Bavoil's
// depth weights, favouring near and opaque layers.
fn oit_weight(depth_m: f32, alpha: f32) -> f32 {
    let z = abs(depth_m);
    let a = z / 5.0;
    let b = z / 200.0;
    let b2 = b * b;
    let falloff = 10.0 / (1e-5 + a * a + b2 * b2 * b2);
    return clamp(alpha, 0.0, 1.0) * clamp(falloff, 1e-2, 3e3);
}

// The premultiplied colour and coverage (C·A, A) of a pixel's blended layers from the
// accumulation (Σ wLα in rgb, Σ wα in a) and the revealage Π(1 − α): C = accum.rgb /
// accum.a (the denominator clamped to [10⁻⁴, 5·10⁴]), A = 1 − revealage.
fn oit_resolve(accum: vec4<f32>, reveal: f32) -> vec4<f32> {
    let coverage = clamp(1.0 - reveal, 0.0, 1.0);
    let color = accum.rgb / clamp(accum.a, 1e-4, 5e4);
    return vec4<f32>(color * coverage, coverage);
}

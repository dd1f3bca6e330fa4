// The taps of the `tent` shadow filter (CPU twin: engine/src/shadow_kernel.rs; Castaño
// 2013, "Shadow Mapping Summary – Part 1"): per axis the kernel [1 3 4 3 1] / 12 moved
// continuously with the receiver, whose weights over 6 texels are
// (1 − s, 3 − 2s, 4 − s, 3 + s, 1 + 2s, s) / 12, read with 3 bilinear taps per axis.
// s ∈ [0, 1): how far the receiver lies past the centre of the texel just before its
// nearest texel corner.

// The weights of the three taps along one axis (sum 1).
fn shadow_tent_weights(s: f32) -> vec3<f32> {
    return vec3<f32>(4.0 - 3.0 * s, 7.0, 1.0 + 3.0 * s) / 12.0;
}

// Where the three taps sample, in texels from the centre of the texel just before the
// receiver's nearest corner.
fn shadow_tent_offsets(s: f32) -> vec3<f32> {
    return vec3<f32>((3.0 - 2.0 * s) / (4.0 - 3.0 * s) - 2.0, (3.0 + s) / 7.0, s / (1.0 + 3.0 * s) + 2.0);
}

// The 2 × 2 Bayer index of (x, y) in {0, 1}²: 0 2 / 3 1 by rows.
fn bayer2(x: u32, y: u32) -> u32 {
    return 2u * (x ^ y) + y;
}

// The ordered-dither threshold (0..1) of shadow-atlas texel `texel` for a blended caster:
// the 4 × 4 Bayer matrix (Bayer 1973), recursively from the 2 × 2 one, as (index + 0.5) /
// 16. A blended caster of coverage α keeps the texels whose threshold is below α, so every
// 4 × 4 block holds 16 α of them (rounded), and the tent filter's 5 × 5 footprint reads a
// visibility close to 1 − α.
fn blended_shadow_threshold(texel: vec2<u32>) -> f32 {
    let x = texel.x & 3u;
    let y = texel.y & 3u;
    let index = 4u * bayer2(x & 1u, y & 1u) + bayer2(x >> 1u, y >> 1u);
    return (f32(index) + 0.5) / 16.0;
}

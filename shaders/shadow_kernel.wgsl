// The taps of the `tent` shadow filter (CPU twin: engine/src/shading/shadow_kernel.rs; Castaño
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

// Relative depth difference (of the pixel's view depth) at which a shadow-mask texel stops
// counting in the depth-aware upsample (shadow_mask.wgsl): 5 %.
const SHADOW_MASK_DEPTH_TOLERANCE: f32 = 0.05;

// The weight of one shadow-mask texel in a pixel's depth-aware upsample: its bilinear
// weight `bilinear`, times a tent in depth that falls from 1 where the texel's view depth
// `texel_depth` (m) equals the pixel's `depth` (m) to 0 at SHADOW_MASK_DEPTH_TOLERANCE ×
// depth, so a shadow is not carried across a depth edge (the joint bilateral upsample of
// Kopf et al. 2007 with a tent range kernel).
fn shadow_mask_weight(bilinear: f32, texel_depth: f32, depth: f32) -> f32 {
    let range = SHADOW_MASK_DEPTH_TOLERANCE * max(depth, 1e-6);
    return bilinear * max(0.0, 1.0 - abs(texel_depth - depth) / range);
}

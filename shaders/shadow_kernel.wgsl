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

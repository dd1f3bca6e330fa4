// Where each level of the depth pyramid lies in its storage buffer
// (engine/src/render/indirect/depth_pyramid.rs, `PyramidLayout`).
struct PyramidLayout {
    // Per level: first element, width, height, unused.
    levels: array<vec4<u32>, 16>,
    // The number of levels (x).
    count: vec4<u32>,
}

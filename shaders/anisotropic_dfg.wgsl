// The anisotropic lobe's split sum (engine/src/shading/anisotropy.rs, `dfg_table` and
// `anisotropic_dfg`, same names): (A, B) of the anisotropic GGX lobe with the
// height-correlated Smith term, tabulated over n·v, the view's azimuth from the
// anisotropy direction, the perceptual roughness and the squared strength, read from a
// storage buffer at group 0, binding 2 (the layers pass's view group). The table's layout
// and sizes are the Rust table's (DFG_TABLE_DIMS).
#import common

@group(0) @binding(2) var<storage, read> anisotropic_dfg_table: array<vec2<f32>>;

const DFG_TABLE_DIMS: vec4<u32> = vec4<u32>(16u, 8u, 16u, 8u);

// x clamped to 0..1; NaN: `nan`.
fn dfg_unit(x: f32, nan: f32) -> f32 {
    return select(clamp(x, 0.0, 1.0), nan, !(x == x));
}

// Quadrilinear lookup at n·v, the view's azimuth (rad, from view_azimuth), the perceptual
// roughness and the strength, each clamped (NaN: n·v 1, azimuth 0, roughness 1,
// strength 0).
fn anisotropic_dfg(n_dot_v: f32, azimuth: f32, perceptual_roughness: f32, strength: f32) -> vec2<f32> {
    let s = dfg_unit(strength, 0.0);
    let coords = vec4<f32>(dfg_unit(n_dot_v, 1.0), dfg_unit(azimuth / (0.5 * PI), 0.0),
                           dfg_unit(perceptual_roughness, 1.0), s * s);
    let last = vec4<f32>(DFG_TABLE_DIMS - vec4<u32>(1u));
    let x = coords * last;
    let base = min(vec4<u32>(x), DFG_TABLE_DIMS - vec4<u32>(2u));
    let f = x - vec4<f32>(base);
    var sum = vec2<f32>(0.0);
    for (var corner = 0u; corner < 16u; corner++) {
        let up = vec4<u32>(corner & 1u, (corner >> 1u) & 1u, (corner >> 2u) & 1u, (corner >> 3u) & 1u);
        let w = select(vec4<f32>(1.0) - f, f, up == vec4<u32>(1u));
        let i = base + up;
        let k = ((i.w * DFG_TABLE_DIMS.z + i.z) * DFG_TABLE_DIMS.y + i.y) * DFG_TABLE_DIMS.x + i.x;
        sum += (w.x * w.y * w.z * w.w) * anisotropic_dfg_table[k];
    }
    return sum;
}

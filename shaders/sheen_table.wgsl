// The sheen lobe's directional albedo table on the GPU (engine/src/shading/sheen.rs,
// `albedo_table`; engine/src/render/lobe_tables.rs uploads it): 32 × 32 entries, n·v
// along a row, packed four to a vec4. The entry module declares the uniform
// `sheen_table: SheenTable` (binding 1 of the layers pass's group 0, binding 4 of the
// transparent pass's).
#import common

struct SheenTable {
    entries: array<vec4<f32>, 256>,
}

const SHEEN_TABLE_SIZE: u32 = 32u;

fn sheen_table_at(i: u32, j: u32) -> f32 {
    let k = min(j, SHEEN_TABLE_SIZE - 1u) * SHEEN_TABLE_SIZE + min(i, SHEEN_TABLE_SIZE - 1u);
    return sheen_table.entries[k / 4u][k % 4u];
}

// Bilinear lookup of the table at (n·v, r), both clamped to 0..1, NaN: 1
// (engine/src/shading/sheen.rs, `sheen_albedo`).
fn sheen_albedo(n_dot_v: f32, perceptual_roughness: f32) -> f32 {
    let scale = f32(SHEEN_TABLE_SIZE - 1u);
    var nv = clamp(n_dot_v, 0.0, 1.0);
    if !(n_dot_v == n_dot_v) {
        nv = 1.0;
    }
    let x = nv * scale;
    var r = clamp(perceptual_roughness, 0.0, 1.0);
    if !(perceptual_roughness == perceptual_roughness) {
        r = 1.0;
    }
    let y = r * scale;
    let x0 = u32(x);
    let y0 = u32(y);
    let fx = x - f32(x0);
    let fy = y - f32(y0);
    let row0 = mix(sheen_table_at(x0, y0), sheen_table_at(x0 + 1u, y0), fx);
    let row1 = mix(sheen_table_at(x0, y0 + 1u), sheen_table_at(x0 + 1u, y0 + 1u), fx);
    return mix(row0, row1, fy);
}

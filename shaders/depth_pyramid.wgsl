// The depth pyramid (engine/src/render/indirect/depth_pyramid.rs): level 0 is the depth
// buffer itself (read in place, never copied), each level above holds, per texel, the
// largest depth (reversed Z: the nearest surface) of the texels it covers in the level
// below, so a ray that stays in front of a level-k texel's value passes in front of
// everything under it.
//
// The levels are stored one after the other in a storage buffer, each row by row, as
// the bits of the depths: depths are ≥ 0, whose bit patterns order as the numbers do, so
// the maximum of the bits is the bits of the maximum. (A mip chain of an R32Float or
// R32Uint texture does not serve every backend: GL cannot render R32Float, and reads an
// integer texture's upper mips as 0.) One dispatch per level from level 1 up, in order.
#import pyramid_layout

@group(0) @binding(0) var depth_buffer: texture_2d<f32>;
@group(0) @binding(1) var<uniform> levels: PyramidLayout;
// The level this dispatch writes (x).
@group(0) @binding(2) var<uniform> step: vec4<u32>;
@group(0) @binding(3) var<storage, read_write> pyramid: array<u32>;

@compute @workgroup_size(8, 8)
fn cs_build(@builtin(global_invocation_id) id: vec3<u32>) {
    let level = step.x;
    let l = levels.levels[level];
    if id.x >= l.y || id.y >= l.z {
        return;
    }
    // The texels (2x, 2y) to (2x + 1, 2y + 1) of the level below, and its last row and
    // column too where its size is odd and this texel is the last one.
    let below = levels.levels[level - 1u];
    let size = vec2<u32>(below.y, below.z);
    let base = id.xy * 2u;
    let odd = ((size & vec2<u32>(1u)) == vec2<u32>(1u)) & (base + vec2<u32>(3u) > size);
    let extra = select(vec2<u32>(1u), vec2<u32>(2u), odd);
    var nearest = 0u;
    for (var dy = 0u; dy <= extra.y; dy++) {
        for (var dx = 0u; dx <= extra.x; dx++) {
            let q = min(base + vec2<u32>(dx, dy), size - vec2<u32>(1u));
            if level == 1u {
                nearest = max(nearest, bitcast<u32>(max(textureLoad(depth_buffer, vec2<i32>(q), 0).r, 0.0)));
            } else {
                nearest = max(nearest, pyramid[below.x + q.y * size.x + q.x]);
            }
        }
    }
    pyramid[l.x + id.y * l.y + id.x] = nearest;
}

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
// integer texture's upper mips as 0.) One dispatch per level from level 1 up, in order:
// level 1 by cs_first, which reads the depth buffer, the others by cs_build, which read
// the level below in the buffer.
#import pyramid_layout

@group(0) @binding(0) var depth_buffer: texture_2d<f32>;
@group(0) @binding(1) var<uniform> levels: PyramidLayout;
// The level this dispatch writes (x).
@group(0) @binding(2) var<uniform> step: vec4<u32>;
@group(0) @binding(3) var<storage, read_write> pyramid: array<u32>;

// The texels of the level below that texel `id` of level `level` covers, (2x, 2y) to
// (2x + 1, 2y + 1), and its last row and column too where its size is odd and this texel
// is the last one: the first (`base`), the last offset (`extra`) and that level's size.
struct Footprint {
    base: vec2<u32>,
    extra: vec2<u32>,
    size: vec2<u32>,
}

fn footprint(level: u32, id: vec2<u32>) -> Footprint {
    let below = levels.levels[level - 1u];
    var f: Footprint;
    f.size = vec2<u32>(below.y, below.z);
    f.base = id * 2u;
    let odd = ((f.size & vec2<u32>(1u)) == vec2<u32>(1u)) & (f.base + vec2<u32>(3u) > f.size);
    f.extra = select(vec2<u32>(1u), vec2<u32>(2u), odd);
    return f;
}

// Level 1, from the depth buffer. It has its own entry point so that neither dispatch
// carries the other's loads: a SIMD rasterizer such as llvmpipe runs both sides of a
// branch under a lane mask.
@compute @workgroup_size(8, 8)
fn cs_first(@builtin(global_invocation_id) id: vec3<u32>) {
    let l = levels.levels[1];
    if id.x >= l.y || id.y >= l.z {
        return;
    }
    let f = footprint(1u, id.xy);
    var nearest = 0u;
    for (var dy = 0u; dy <= f.extra.y; dy++) {
        for (var dx = 0u; dx <= f.extra.x; dx++) {
            let q = min(f.base + vec2<u32>(dx, dy), f.size - vec2<u32>(1u));
            nearest = max(nearest, bitcast<u32>(max(textureLoad(depth_buffer, vec2<i32>(q), 0).r, 0.0)));
        }
    }
    pyramid[l.x + id.y * l.y + id.x] = nearest;
}

// Level step.x ≥ 2, from the level below in the buffer.
@compute @workgroup_size(8, 8)
fn cs_build(@builtin(global_invocation_id) id: vec3<u32>) {
    let level = step.x;
    let l = levels.levels[level];
    if id.x >= l.y || id.y >= l.z {
        return;
    }
    let f = footprint(level, id.xy);
    let first = levels.levels[level - 1u].x;
    var nearest = 0u;
    for (var dy = 0u; dy <= f.extra.y; dy++) {
        for (var dx = 0u; dx <= f.extra.x; dx++) {
            let q = min(f.base + vec2<u32>(dx, dy), f.size - vec2<u32>(1u));
            nearest = max(nearest, pyramid[first + q.y * f.size.x + q.x]);
        }
    }
    pyramid[l.x + id.y * l.y + id.x] = nearest;
}

// SMAA's edge step (engine/src/render/antialias/smaa.rs; Jimenez et al. 2012, §3.1):
// each pixel marks its left (r) and top (g) edge where the perceptual luma steps by at least SMAA_THRESHOLD and by at least half the largest
// step around it (local contrast adaptation, smaa_edge). The luma is the one
// aa_prepare.wgsl stored in a. Pixels without an edge are discarded (the target is
// cleared to 0); those with one also write depth 1 into the mask the coverage step is
// depth-tested against (smaa.rs), so that only they are shaded there.
#import color
#import antialiasing
#import fullscreen

@group(0) @binding(0) var prepared: texture_2d<f32>;

// Smallest luma step that is an edge (the paper's medium and high presets).
const SMAA_THRESHOLD: f32 = 0.1;

fn luma_px(p: vec2<i32>) -> f32 {
    let last = vec2<i32>(textureDimensions(prepared)) - vec2<i32>(1);
    return textureLoad(prepared, clamp(p, vec2<i32>(0), last), 0).a;
}

struct Edges {
    @location(0) edges: vec4<f32>,
    @builtin(frag_depth) mask: f32,
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Edges {
    let p = vec2<i32>(frag.xy);
    let centre = luma_px(p);
    let left = luma_px(p + vec2<i32>(-1, 0));
    let top = luma_px(p + vec2<i32>(0, -1));
    let delta = abs(vec2<f32>(centre) - vec2<f32>(left, top));
    if max(delta.x, delta.y) < SMAA_THRESHOLD {
        discard;
    }
    // The largest step around the pixel: to its right and bottom neighbours, and beyond
    // its left and top ones.
    let right = abs(centre - luma_px(p + vec2<i32>(1, 0)));
    let bottom = abs(centre - luma_px(p + vec2<i32>(0, 1)));
    let left2 = abs(left - luma_px(p + vec2<i32>(-2, 0)));
    let top2 = abs(top - luma_px(p + vec2<i32>(0, -2)));
    let local_max = max(max(max(delta.x, delta.y), max(right, bottom)), max(left2, top2));
    let edges = vec2<f32>(
        smaa_edge(delta.x, local_max, SMAA_THRESHOLD),
        smaa_edge(delta.y, local_max, SMAA_THRESHOLD),
    );
    if max(edges.x, edges.y) == 0.0 {
        discard;
    }
    return Edges(vec4<f32>(edges, 0.0, 0.0), 1.0);
}

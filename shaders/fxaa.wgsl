// Fast approximate anti-aliasing (Lottes 2009, "FXAA", the quality variant's steps),
// on the image aa_prepare.wgsl wrote (linear colour, perceptual luma in a), back into the
// HDR target:
// 1. the local contrast of the centre and its four neighbours decides whether the pixel
//    is on an edge at all;
// 2. second differences over the 3×3 neighbourhood decide whether the edge runs
//    horizontally or vertically, and the steeper neighbour across it which side it is on;
//    then a geometric edge across it (a silhouette in the depth buffer, depth_bend, or a
//    crease between the G-buffer's normals, creased) decides whether it is blended at
//    all: edges of texture and shading inside a surface are left as they are, since a
//    blur there softens detail the frame had right;
// 3. a search along the edge, half a pixel across it, finds both of its ends (where the
//    luma leaves the edge's average by a quarter of its gradient);
// 4. the pixel's distance to the nearer end gives how far across the edge to sample: the
//    blend an exact coverage of the edge's line would give;
// 5. a sub-pixel term from the 3×3 average blurs isolated single-pixel features.
// fs_mark runs step 1 alone and marks the pixels on a luma edge in a depth mask; fs_main
// is depth-tested against it (fxaa.rs).
#import color
#import encoding
#import antialiasing
#import fullscreen

@group(0) @binding(0) var prepared: texture_2d<f32>;
@group(0) @binding(1) var linear_sampler: sampler;
@group(0) @binding(2) var depth_buffer: texture_2d<f32>;
@group(0) @binding(3) var gbuffer1: texture_2d<f32>;

fn depth_px(p: vec2<i32>) -> f32 {
    let last = vec2<i32>(textureDimensions(depth_buffer)) - vec2<i32>(1);
    return textureLoad(depth_buffer, clamp(p, vec2<i32>(0), last), 0).r;
}

fn normal_px(p: vec2<i32>) -> vec3<f32> {
    let last = vec2<i32>(textureDimensions(gbuffer1)) - vec2<i32>(1);
    return oct_decode(textureLoad(gbuffer1, clamp(p, vec2<i32>(0), last), 0).rg);
}

// Whether a geometric edge runs between pixel p and its neighbours p ± step (the two
// across the luma edge): a silhouette (depth_bend along that axis alone), or a crease
// between two faces of one surface (creased).
fn geometric_edge_across(p: vec2<i32>, step: vec2<i32>) -> bool {
    let c = depth_px(p);
    if depth_bend(c, depth_px(p - step), depth_px(p + step), c, c) > SILHOUETTE_BEND {
        return true;
    }
    let n = normal_px(p);
    return creased(n, normal_px(p - step)) || creased(n, normal_px(p + step));
}

// Smallest contrast, relative to the local maximum, that is treated as an edge.
const EDGE_THRESHOLD: f32 = 0.125;
// Smallest absolute contrast treated as an edge (dark regions).
const EDGE_THRESHOLD_MIN: f32 = 0.0625;
// Strength of the sub-pixel blur, 0..1.
const SUBPIXEL: f32 = 0.75;
// Search iterations along the edge, each a step of search_step(i) pixels.
const SEARCH_STEPS: u32 = 10u;

fn search_step(i: u32) -> f32 {
    switch i {
        case 0u, 1u, 2u, 3u, 4u: { return 1.0; }
        case 5u: { return 1.5; }
        case 6u, 7u: { return 2.0; }
        case 8u: { return 4.0; }
        default: { return 8.0; }
    }
}

fn luma_at(uv: vec2<f32>) -> f32 {
    return textureSampleLevel(prepared, linear_sampler, uv, 0.0).a;
}

fn luma_px(p: vec2<i32>) -> f32 {
    let last = vec2<i32>(textureDimensions(prepared)) - vec2<i32>(1);
    return textureLoad(prepared, clamp(p, vec2<i32>(0), last), 0).a;
}

// The lumas of pixel p's 3×3 neighbourhood (north is up, −y on screen), their range
// around the centre, the edge's direction, and whether FXAA blends p: the luma has an
// edge there (step 1) and a geometric edge runs across it (step 2).
struct Neighbourhood {
    m: f32,
    n: f32,
    s: f32,
    w: f32,
    e: f32,
    nw: f32,
    ne: f32,
    sw: f32,
    se: f32,
    range: f32,
    is_horizontal: bool,
    blended: bool,
}

// Whether the luma range of m and its four neighbours n, s, w, e is an edge (step 1).
fn luma_edge(m: f32, n: f32, s: f32, w: f32, e: f32) -> bool {
    let lo = min(m, min(min(n, s), min(w, e)));
    let hi = max(m, max(max(n, s), max(w, e)));
    return hi - lo >= max(EDGE_THRESHOLD_MIN, hi * EDGE_THRESHOLD);
}

fn neighbourhood(p: vec2<i32>) -> Neighbourhood {
    var h: Neighbourhood;
    h.m = luma_px(p);
    h.n = luma_px(p + vec2<i32>(0, -1));
    h.s = luma_px(p + vec2<i32>(0, 1));
    h.w = luma_px(p + vec2<i32>(-1, 0));
    h.e = luma_px(p + vec2<i32>(1, 0));
    h.range = max(h.m, max(max(h.n, h.s), max(h.w, h.e))) - min(h.m, min(min(h.n, h.s), min(h.w, h.e)));
    if !luma_edge(h.m, h.n, h.s, h.w, h.e) {
        h.blended = false;
        return h;
    }
    h.nw = luma_px(p + vec2<i32>(-1, -1));
    h.ne = luma_px(p + vec2<i32>(1, -1));
    h.sw = luma_px(p + vec2<i32>(-1, 1));
    h.se = luma_px(p + vec2<i32>(1, 1));
    // A horizontal edge changes luma from north to south.
    let horizontal = 2.0 * abs(h.n + h.s - 2.0 * h.m) + abs(h.nw + h.sw - 2.0 * h.w)
        + abs(h.ne + h.se - 2.0 * h.e);
    let vertical = 2.0 * abs(h.w + h.e - 2.0 * h.m) + abs(h.nw + h.ne - 2.0 * h.n)
        + abs(h.sw + h.se - 2.0 * h.s);
    h.is_horizontal = horizontal >= vertical;
    // Only where the luma has an edge: are the depth or the normals broken across it?
    h.blended = geometric_edge_across(p, select(vec2<i32>(1, 0), vec2<i32>(0, 1), h.is_horizontal));
    return h;
}

// Writes depth 1 into the mask (fxaa.rs) where the luma has an edge (step 1 alone: five
// loads); the filter is depth-tested against it, so that no other pixel is shaded, and
// tests the geometric edge itself.
@fragment
fn fs_mark(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    let p = vec2<i32>(frag.xy);
    let m = luma_px(p);
    let n = luma_px(p + vec2<i32>(0, -1));
    let s = luma_px(p + vec2<i32>(0, 1));
    let w = luma_px(p + vec2<i32>(-1, 0));
    let e = luma_px(p + vec2<i32>(1, 0));
    if !luma_edge(m, n, s, w, e) {
        discard;
    }
    return 1.0;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let texel = 1.0 / vec2<f32>(textureDimensions(prepared));
    let p = vec2<i32>(frag.xy);
    let h = neighbourhood(p);
    // Off every edge or inside a surface: the HDR target keeps its own value (the pass
    // loads it), not the f16 copy's.
    if !h.blended {
        discard;
    }
    let m = h.m;
    let n = h.n;
    let s = h.s;
    let w = h.w;
    let e = h.e;
    let nw = h.nw;
    let ne = h.ne;
    let sw = h.sw;
    let se = h.se;
    let range = h.range;
    let is_horizontal = h.is_horizontal;
    let before = select(w, n, is_horizontal);
    let after = select(e, s, is_horizontal);
    let g_before = abs(before - m);
    let g_after = abs(after - m);
    let towards_before = g_before >= g_after;
    let gradient = 0.25 * max(g_before, g_after);
    var across = select(vec2<f32>(texel.x, 0.0), vec2<f32>(0.0, texel.y), is_horizontal);
    var edge_luma = 0.5 * (after + m);
    if towards_before {
        across = -across;
        edge_luma = 0.5 * (before + m);
    }
    let along = select(vec2<f32>(0.0, texel.y), vec2<f32>(texel.x, 0.0), is_horizontal);

    // Walk both ways along the edge, half a pixel across it.
    let uv = frag.xy * texel;
    let on_edge = uv + 0.5 * across;
    var uv_neg = on_edge - along;
    var uv_pos = on_edge + along;
    var d_neg = luma_at(uv_neg) - edge_luma;
    var d_pos = luma_at(uv_pos) - edge_luma;
    var done_neg = abs(d_neg) >= gradient;
    var done_pos = abs(d_pos) >= gradient;
    for (var i = 1u; i < SEARCH_STEPS; i++) {
        if done_neg && done_pos {
            break;
        }
        let step = search_step(i);
        if !done_neg {
            uv_neg -= along * step;
            d_neg = luma_at(uv_neg) - edge_luma;
            done_neg = abs(d_neg) >= gradient;
        }
        if !done_pos {
            uv_pos += along * step;
            d_pos = luma_at(uv_pos) - edge_luma;
            done_pos = abs(d_pos) >= gradient;
        }
    }
    let dist_neg = select(uv.y - uv_neg.y, uv.x - uv_neg.x, is_horizontal);
    let dist_pos = select(uv_pos.y - uv.y, uv_pos.x - uv.x, is_horizontal);
    let nearer_neg = dist_neg < dist_pos;
    let dist = min(dist_neg, dist_pos);
    let edge_length = max(dist_neg + dist_pos, 1e-9);
    // Blend only when the nearer end is where the edge crosses to the centre's side.
    let end_delta = select(d_pos, d_neg, nearer_neg);
    let centre_darker = m < edge_luma;
    var offset = select(0.0, 0.5 - dist / edge_length, (end_delta < 0.0) != centre_darker);

    // Sub-pixel aliasing: how far the centre stands out of its 3×3 neighbourhood.
    let average = (2.0 * (n + s + w + e) + nw + ne + sw + se) / 12.0;
    let sub = smoothstep(0.0, 1.0, clamp(abs(average - m) / range, 0.0, 1.0));
    offset = max(offset, sub * sub * SUBPIXEL);

    // The bilinear tap mixes the two pixels' linear colours.
    let c = textureSampleLevel(prepared, linear_sampler, uv + across * offset, 0.0);
    return vec4<f32>(c.rgb, 1.0);
}

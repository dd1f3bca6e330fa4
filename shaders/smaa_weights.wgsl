// SMAA's coverage step (engine/src/render/antialias/smaa.rs; Jimenez et al. 2012, §3.2,
// orthogonal patterns): for each edge of the pixel, follow it both ways to its ends, read
// the crossing edges there (smaa_end_height), and evaluate the revectorized silhouette's
// coverage of the pixel and of its neighbour across the edge (smaa_coverage).
// Output: (x, y) for the top edge: the pixel covered by the pixel above's colour, and the
// pixel above covered by this one's; (z, w) the same for the left edge and the pixel to
// the left. Pixels without an edge are discarded (the target is cleared to 0).
#import color
#import antialiasing
#import fullscreen

@group(0) @binding(0) var edges: texture_2d<f32>;

// Header constant MAX_SEARCH (u32): the farthest an edge is followed each way, in pixels
// (smaa.rs).

// The edges of pixel q (left, top); none outside the image.
fn edges_at(q: vec2<i32>) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(edges));
    if any(q < vec2<i32>(0)) || any(q >= size) {
        return vec2<f32>(0.0);
    }
    return textureLoad(edges, q, 0).rg;
}

// The crossing edges at the boundary in front of pixel b (between b − along and b): the
// `cross` channel of b on the neighbour's side (b + across) and on the centre's (b).
fn crossing(b: vec2<i32>, across: vec2<i32>, cross: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(dot(edges_at(b + across), cross), dot(edges_at(b), cross));
}

// Whether q carries an edge in channel `own`.
fn has_edge(q: vec2<i32>, own: vec2<f32>) -> bool {
    return dot(edges_at(q), own) > 0.5;
}

// Longest next stair measured, in pixels: a stair this long lets the revectorized line
// reach the segment's middle.
const MAX_STAIR: i32 = 8;

// The length of the stair that starts at `first` and runs `outward` (pixels carrying an
// edge in channel `own`), up to MAX_STAIR.
fn stair_length(first: vec2<i32>, outward: vec2<i32>, own: vec2<f32>) -> i32 {
    var n = 0;
    loop {
        if n >= MAX_STAIR || !has_edge(first + n * outward, own) {
            break;
        }
        n += 1;
    }
    return n;
}

// The next stair's length past the segment's end on the `side` of the segment (`out` the
// first pixel past the end, `inside` the last one in it), MAX_STAIR for a thin feature's
// end (segment_end).
fn next_stair(out: vec2<i32>, inside: vec2<i32>, outward: vec2<i32>, side: vec2<i32>,
              own: vec2<f32>) -> i32 {
    let n = stair_length(out + side, outward, own);
    let thin = has_edge(inside + side, own) && has_edge(inside + side - outward, own)
        && !has_edge(out, own) && n == 0;
    return select(n, MAX_STAIR, thin);
}

// One end of a segment: the silhouette's height there and how far its line reaches.
struct End {
    height: f32,
    reach: f32,
}

// The end at the boundary in front of b, `out` the first pixel past it along the edge and
// `outward` the step away from the segment. A crossing edge is a staircase step
// (smaa_end_height) unless it continues one pixel farther from the segment (b + 2 across,
// b − across), or, for a segment `long`er than 2 pixels, the next stair (the edge one
// pixel to the step's side, past the boundary) is shorter than 2 pixels: a long segment
// beside a short one is a shape's corner with a slanted side. The line reaches as far as
// the next stair is long (the whole half segment for MAX_STAIR or more). Only the sides
// with a crossing edge are measured. A thin feature's end is a step with a full reach,
// whatever the next stair: the segment's edge stops there, no stair follows, and the
// edge on the step's side of the segment's last two pixels (the feature's other side)
// stops there too. That is a dash one pixel thick, SMAA's U pattern, whose corners it
// cuts; the stair rules alone left it untouched.
fn segment_end(b: vec2<i32>, out: vec2<i32>, outward: vec2<i32>, across: vec2<i32>,
               own: vec2<f32>, cross: vec2<f32>, long: bool) -> End {
    let c = crossing(b, across, cross);
    let inside = out - outward;
    var stairs = vec2<i32>(0);
    var corner = vec2<bool>(false);
    if c.x > 0.5 {
        stairs.x = next_stair(out, inside, outward, across, own);
        corner.x = has_edge(b + 2 * across, cross) || (long && stairs.x < 2);
    }
    if c.y > 0.5 {
        stairs.y = next_stair(out, inside, outward, -across, own);
        corner.y = has_edge(b - across, cross) || (long && stairs.y < 2);
    }
    let height = smaa_end_height(c, select(vec2<f32>(0.0), vec2<f32>(1.0), corner));
    let stair = select(stairs.y, stairs.x, height > 0.0);
    return End(height, select(f32(stair), 1e9, stair >= MAX_STAIR));
}

// The coverage pair for the edge of p running along `along` (the edge's own channel
// `own`, its crossing edges in channel `cross`), the neighbour lying at p + across.
fn edge_coverage(p: vec2<i32>, along: vec2<i32>, across: vec2<i32>, own: vec2<f32>,
                 cross: vec2<f32>) -> vec2<f32> {
    let most = i32(MAX_SEARCH);
    // Backwards: b is the first pixel of the segment. The search is cut off when the edge
    // still goes on after `most` pixels.
    var b = p;
    var back = 0;
    var cut_back = false;
    loop {
        let c = crossing(b, across, cross);
        if max(c.x, c.y) > 0.5 || !has_edge(b - along, own) {
            break;
        }
        if back >= most {
            cut_back = true;
            break;
        }
        b -= along;
        back += 1;
    }
    // Forwards: e is the first pixel past the segment.
    var e = p + along;
    var ahead = 0;
    var cut_ahead = false;
    loop {
        let c = crossing(e, across, cross);
        if max(c.x, c.y) > 0.5 || !has_edge(e, own) {
            break;
        }
        if ahead >= most {
            cut_ahead = true;
            break;
        }
        e += along;
        ahead += 1;
    }
    // A segment cut off by the search has no step at that end.
    let long = back + ahead + 1 > 2;
    let first = segment_end(b, b - along, -along, across, own, cross, long);
    let last = segment_end(e, e, along, across, own, cross, long);
    let ends = vec2<f32>(select(first.height, 0.0, cut_back), select(last.height, 0.0, cut_ahead));
    return smaa_coverage(f32(back), f32(back + ahead + 1), ends, vec2<f32>(first.reach, last.reach));
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let e = edges_at(p);
    if max(e.x, e.y) < 0.5 {
        discard;
    }
    var w = vec4<f32>(0.0);
    let left = vec2<f32>(1.0, 0.0);
    let top = vec2<f32>(0.0, 1.0);
    if e.y > 0.5 {
        w = vec4<f32>(edge_coverage(p, vec2<i32>(1, 0), vec2<i32>(0, -1), top, left), w.zw);
    }
    if e.x > 0.5 {
        w = vec4<f32>(w.xy, edge_coverage(p, vec2<i32>(0, 1), vec2<i32>(-1, 0), left, top));
    }
    return w;
}

// Temporal anti-aliasing (engine/src/render/antialias/taa.rs; Karis 2014, "High
// Quality Temporal Supersampling"; Salvi 2016, "An Excursion in Temporal Supersampling").
// Per pixel:
// 1. this frame's colour (non-finite → black, so NaN and ∞ never enter the history);
// 2. the 3 × 3 neighbourhood's mean and standard deviation in YCoCg of the compressed
//    colour, and the motion vector of the nearest depth among the centre and the four
//    corners (dilated, so edges move with the object in front; the G-buffer's for a
//    surface, the camera's rotation for the background);
// 3. the history at the pixel's previous position, rejected where that position left
//    the screen or none of the depths stored around it is the depth the neighbourhood's
//    nearest surface had then (disocclusion), rescaled by the change of exposure;
// 4. the history clipped towards the mean into mean ± γσ (γ wider where nothing moves,
//    so a still image keeps converging);
// 5. a running mean over at most 16 frames while the pixel moves, up to 64 while it is
//    still (the plain mean of a still camera's jitter sequence): weight 1/n on this frame.
// Writes the colour into the new history, and this frame's view depth and frame count
// into the new depth history.
#import color
#import antialiasing
#import fullscreen

struct TaaParams {
    // Clip from world without jitter, the previous frame.
    previous_clip_from_world: mat4x4<f32>,
    // Clip from world without jitter, this frame.
    clip_from_world: mat4x4<f32>,
    // World from clip with this frame's jitter (the depth buffer's projection).
    world_from_clip: mat4x4<f32>,
    // x: history valid (1) or reset (0); y: exposure now / exposure then; z: most frames
    // a moving pixel averages; w: γ of the clipping box while moving.
    settings: vec4<f32>,
    // x: most frames a still pixel averages; y: the motion (px) below which it is still.
    still: vec4<f32>,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var motion: texture_2d<f32>;
@group(0) @binding(3) var history: texture_2d<f32>;
@group(0) @binding(4) var history_depth: texture_2d<f32>;
@group(0) @binding(5) var<uniform> params: TaaParams;

struct TaaOutput {
    @location(0) color: vec4<f32>,
    // View depth (m) of this pixel's surface, frames averaged.
    @location(1) depth_frames: vec4<f32>,
}

fn finite_or_black(c: vec4<f32>) -> vec4<f32> {
    return select(vec4<f32>(0.0), c, is_finite4(c));
}

// Relative tolerance between the depth a surface had and the depth the history stores.
const DISOCCLUSION_TOLERANCE: f32 = 0.05;

// The centre and the four corners of a 3 × 3 block, where the dilated motion looks for
// the nearest depth. The corners span the block's extent, so a surface that covers part
// of the block almost always covers one of them, at 5 loads instead of 9 (each load is a
// gather on a CPU rasterizer; 8 % of the pass on lavapipe, and no change of the converged
// error). Disocclusion keeps all 9: on thin wires, fewer stored depths reject more
// history (`aliasing`, FLIP against 64 renders, 0.0193 → 0.0209).
// The centre is loaded once, before the loops, and reused: each of the three reads it
// again (colour, depth, stored depth) would cost a gather of its own.
const CORNERS = array<vec2<i32>, 4>(
    vec2<i32>(-1, -1), vec2<i32>(1, -1), vec2<i32>(-1, 1), vec2<i32>(1, 1),
);

// The eight neighbours of a pixel in its 3 × 3 block.
const NEIGHBOURS = array<vec2<i32>, 8>(
    vec2<i32>(-1, -1), vec2<i32>(0, -1), vec2<i32>(1, -1), vec2<i32>(-1, 0),
    vec2<i32>(1, 0), vec2<i32>(-1, 1), vec2<i32>(0, 1), vec2<i32>(1, 1),
);

// The world position seen at uv (0..1, y down) with depth d, through this frame's
// jittered projection.
fn world_at(uv: vec2<f32>, d: f32) -> vec4<f32> {
    let h = params.world_from_clip * vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    return vec4<f32>(h.xyz / h.w, 1.0);
}

// Screen motion (pixels, y down) of the background seen at uv: it is infinitely far, so
// it moves with the camera's rotation only. The direction of the view ray (from the near
// to the far plane) is projected as a point at infinity (w = 0) through the unjittered
// camera now and in the previous frame.
fn background_motion(uv: vec2<f32>, size: vec2<f32>) -> vec2<f32> {
    let direction = vec4<f32>((world_at(uv, 0.0) - world_at(uv, 1.0)).xyz, 0.0);
    let now = params.clip_from_world * direction;
    let before = params.previous_clip_from_world * direction;
    let ndc = now.xy / now.w - before.xy / before.w;
    return vec2<f32>(ndc.x * 0.5, -ndc.y * 0.5) * size;
}

// The history at `uv`, bilinear from its four nearest texels, loaded (an f32 history is
// not filterable on every adapter).
fn history_at(uv: vec2<f32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(history));
    let last = size - vec2<i32>(1);
    let p = uv * vec2<f32>(size) - 0.5;
    let base = floor(p);
    let f = p - base;
    let i = vec2<i32>(base);
    let a = textureLoad(history, clamp(i, vec2<i32>(0), last), 0);
    let b = textureLoad(history, clamp(i + vec2<i32>(1, 0), vec2<i32>(0), last), 0);
    let c = textureLoad(history, clamp(i + vec2<i32>(0, 1), vec2<i32>(0), last), 0);
    let d = textureLoad(history, clamp(i + vec2<i32>(1, 1), vec2<i32>(0), last), 0);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> TaaOutput {
    let dims = vec2<i32>(textureDimensions(hdr));
    let size = vec2<f32>(dims);
    let last = dims - vec2<i32>(1);
    let p = vec2<i32>(frag.xy);
    // A non-finite colour is black in the statistics, and left out of the history.
    let raw = textureLoad(hdr, p, 0);
    let current = finite_or_black(raw);

    let centre_color = rgb_to_ycocg(compress_hdr(current.rgb));
    var m1 = centre_color;
    var m2 = centre_color * centre_color;
    for (var k = 0; k < 8; k++) {
        let q = clamp(p + NEIGHBOURS[k], vec2<i32>(0), last);
        let c = rgb_to_ycocg(compress_hdr(finite_or_black(textureLoad(hdr, q, 0)).rgb));
        m1 += c;
        m2 += c * c;
    }
    let centre_depth = textureLoad(depth, p, 0).r;
    var nearest = p;
    var nearest_depth = centre_depth;
    for (var k = 0; k < 4; k++) {
        let q = clamp(p + CORNERS[k], vec2<i32>(0), last);
        // Reversed Z: the nearest surface has the largest depth.
        let d = textureLoad(depth, q, 0).r;
        if d > nearest_depth {
            nearest_depth = d;
            nearest = q;
        }
    }
    let mean = m1 / 9.0;
    let sigma = sqrt(max(m2 / 9.0 - mean * mean, vec3<f32>(0.0)));
    // The G-buffer wrote the motion of every surface; the background (depth 0 across the
    // neighbourhood) turns with the camera.
    var moved = textureLoad(motion, nearest, 0).xy;
    if nearest_depth <= 0.0 {
        moved = background_motion((vec2<f32>(p) + vec2<f32>(0.5)) / size, size);
    }

    // This pixel's view depth (stored for the next frame), and the view depth the
    // neighbourhood's nearest surface had in the previous frame.
    let uv = frag.xy / size;
    let view_depth = (params.clip_from_world * world_at(uv, centre_depth)).w;
    let nearest_uv = (vec2<f32>(nearest) + vec2<f32>(0.5)) / size;
    // Clamped like the stored depths (f16).
    let expected = min((params.previous_clip_from_world * world_at(nearest_uv, nearest_depth)).w, 65000.0);

    // Disocclusion: the history is kept where any of the 3 × 3 depths stored around the
    // previous position is that surface's (a jittered silhouette shows the surface in
    // some of them, the background in others).
    let previous_uv = uv - moved / size;
    let inside = all(previous_uv >= vec2<f32>(0.0)) && all(previous_uv <= vec2<f32>(1.0));
    let centre = clamp(vec2<i32>(previous_uv * size), vec2<i32>(0), last);
    let stored = textureLoad(history_depth, centre, 0);
    let tolerance = DISOCCLUSION_TOLERANCE * max(abs(expected), 1e-3);
    // The neighbours are read only where the centre is not that surface: a branch, so
    // that a block of pixels that all match (a still or slow camera) skips the loads.
    var same_surface = abs(stored.x - expected) <= tolerance;
    if !same_surface {
        for (var k = 0; k < 8; k++) {
            let q = clamp(centre + NEIGHBOURS[k], vec2<i32>(0), last);
            if abs(textureLoad(history_depth, q, 0).x - expected) <= tolerance {
                same_surface = true;
                break;
            }
        }
    }
    let valid = params.settings.x > 0.5 && inside && same_surface;

    var out: TaaOutput;
    var frames = 1.0;
    out.color = current;
    if valid {
        let most = select(params.settings.z, params.still.x, length(moved) < params.still.y);
        frames = min(stored.y + 1.0, most);
        var past = finite_or_black(history_at(previous_uv));
        past = vec4<f32>(past.rgb * params.settings.y, past.a);
        // γ: the given one while the pixel moves, twice as wide once it is still.
        let still = 1.0 - clamp(length(moved), 0.0, 1.0);
        let gamma = params.settings.w * (1.0 + still);
        let clipped = clip_towards_mean(rgb_to_ycocg(compress_hdr(past.rgb)), mean, gamma * sigma + vec3<f32>(1e-4));
        let history_color = vec4<f32>(expand_hdr(ycocg_to_rgb(clipped)), past.a);
        out.color = running_mean(history_color, raw, 1.0 / frames);
    }
    // f16 storage: depths beyond its range are stored as its largest value.
    out.depth_frames = vec4<f32>(min(view_depth, 65000.0), frames, 0.0, 0.0);
    return out;
}

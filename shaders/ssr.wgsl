// Screen-space reflections (engine/src/render/indirect/reflections.rs): per pixel
// smoother than the cutoff, RAYS reflected rays importance-sampled from the GGX visible
// normals (sample_ggx_vndf), each traced over the depth pyramid (Uludag 2014): a ray
// skips a level-k texel when it stays in front of that texel's nearest depth, climbs a
// level after each skip and descends where it may cross a surface; at level 0 a ray
// that crosses the surface within the pixel, or enters it at most `thickness_m` behind
// the surface, hits it. A hit returns the lit frame
// there (one bounce); a miss, a ray below the surface or one leaving the screen returns
// the reflection probes' prefiltered radiance (REFLECTION_PROBE_SLOTS > 0) blended with the
// environment's, as lighting already added it.
//
// The pass writes the lit frame (read from its copy) plus W · (L̄ − E): W the split-sum specular weight
// lighting used for environment light (F0·A + B, energy compensation, specular
// occlusion), E that environment radiance and L̄ the rays' mean. Where every ray misses
// it adds nothing: the reflection falls back to the environment, never to black.
//
// At full resolution fs_mark_full marks the pixels smooth enough to trace in a depth
// target, and fs_main, depth-tested against it, writes their reflections. At half
// resolution fs_mark_trace_half marks the 2×2 blocks whose traced pixel (the top-left
// one) is smooth enough, in a half-size depth target; fs_trace_half, depth-tested against
// it, traces those pixels into a half-size target (the hits' mean light and the fraction
// that hit; 0 elsewhere, its clear value); fs_mark_half marks the pixels that get hits,
// and fs_composite_half gives them the hits of their block's pixel on the same surface,
// each with its own weight and environment term. Unmarked pixels keep the lit frame
// already in the HDR target.
//
// Header constants: RAYS, STEPS, REFLECTION_PROBE_SLOTS (u32), HAS_ENVIRONMENT, ENV_MAP,
// ENERGY_COMPENSATION, SCREEN_AO (bool), as the lighting pass compiles them. Group 3 is the
// lighting pass's (volume_lookup.wgsl declares the volume's bindings, unused here).
#import common
#import brdf
#import color
#import encoding
#import ibl
#import bindings
#import fullscreen
#import ambient_occlusion
#import volume_lookup
#import probe_reflections
#import pyramid_layout

struct SsrParams {
    // Perceptual roughness above which nothing is traced.
    max_roughness: f32,
    // How far (m) behind a surface a ray may pass and still hit it.
    thickness_m: f32,
    pad0: f32,
    pad1: f32,
}

// Group 0 (SSR in reflections.rs).
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: SsrParams;
@group(0) @binding(2) var depth_buffer: texture_2d<f32>;
@group(0) @binding(3) var gbuffer0: texture_2d<f32>;
@group(0) @binding(4) var gbuffer1: texture_2d<f32>;
@group(0) @binding(5) var specular_level: texture_2d<f32>;
@group(0) @binding(6) var<storage, read> pyramid: array<u32>;
@group(0) @binding(7) var scene_color: texture_2d<f32>;
@group(0) @binding(8) var<uniform> pyramid_layout: PyramidLayout;

// Group 1, indirect light, as the lighting pass binds it (lighting::ENVIRONMENT).
@group(1) @binding(0) var<uniform> environment: EnvironmentUniform;
@group(1) @binding(1) var env_cube: texture_cube<f32>;
@group(1) @binding(2) var env_sampler: sampler;
@group(1) @binding(3) var brdf_lut: texture_2d<f32>;
@group(1) @binding(4) var screen_ao: texture_2d<f32>;

// Group 2 of the half-resolution composite (SSR_HALF): the trace step's hits.
@group(2) @binding(0) var half_added: texture_2d<f32>;

fn world_at(px: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(px.x * view.viewport.z * 2.0 - 1.0, 1.0 - px.y * view.viewport.w * 2.0);
    let h = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    return h.xyz / h.w;
}

// Pixel position (xy) and depth (z) of world point `w`.
fn screen_of(w: vec3<f32>) -> vec3<f32> {
    let clip = view.clip_from_world * vec4<f32>(w, 1.0);
    let ndc = clip.xyz / clip.w;
    return vec3<f32>(vec2<f32>(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * view.viewport.xy, ndc.z);
}

// An orthonormal basis with n as its third column (Duff et al. 2017).
fn basis(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(
        vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3<f32>(b, s + n.y * n.y * a, -n.y),
        n,
    );
}

// The environment's prefiltered radiance towards `dir` for perceptual roughness `r`,
// as lighting samples it (0 without an environment).
fn environment_radiance(dir: vec3<f32>, r: f32) -> vec3<f32> {
    if !HAS_ENVIRONMENT {
        return vec3<f32>(0.0);
    }
    if ENV_MAP {
        let d = rotate_y(dir, -environment.params.y);
        return textureSampleLevel(env_cube, env_sampler, d, r * environment.params.z).rgb * environment.params.x;
    }
    return environment.uniform_radiance.rgb;
}

// The nearest depth of texel `cell` of pyramid level `level` (level 0 is the depth
// buffer).
fn pyramid_depth(cell: vec2<i32>, level: i32) -> f32 {
    let l = pyramid_layout.levels[level];
    let c = clamp(cell, vec2<i32>(0), vec2<i32>(i32(l.y), i32(l.z)) - vec2<i32>(1));
    if level == 0 {
        return textureLoad(depth_buffer, c, 0).r;
    }
    return bitcast<f32>(pyramid[l.x + u32(c.y) * l.y + u32(c.x)]);
}

// The pixel a ray from world point `p` along `l` hits, and 1 in z; 0 in z for a miss.
fn trace(p: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let camera = view.position_exposure.xyz;
    let z0 = dot(p - camera, view.forward.xyz);
    let towards = dot(l, view.forward.xyz);
    // Long enough to cross the screen; a ray towards the camera stops at a tenth of the
    // point's depth, in front of the near plane.
    let length_m = select(1.0e3, min(1.0e3, 0.9 * z0 / max(-towards, 1e-6)), towards < 0.0);
    let s0 = screen_of(p);
    let s1 = screen_of(p + l * length_m);
    var d = s1 - s0;
    let span = max(abs(d.x), abs(d.y));
    if !(span >= 1.0) {
        return vec3<f32>(0.0);
    }
    d = d / span;
    // Where the ray leaves the screen, in pixels along it.
    let size = view.viewport.xy;
    let to_edge = select((vec2<f32>(0.0) - s0.xy) / d.xy, (size - s0.xy) / d.xy, d.xy > vec2<f32>(0.0));
    let t_max = min(span, min(select(1e9, to_edge.x, d.x != 0.0), select(1e9, to_edge.y, d.y != 0.0)));
    let top = i32(pyramid_layout.count.x) - 1;
    var level = 0;
    var t = 1.5;
    for (var i = 0u; i < STEPS; i++) {
        if t >= t_max {
            break;
        }
        let pos = s0 + d * t;
        let cell_size = f32(1 << u32(level));
        let cell = floor(pos.xy / cell_size);
        let bound = (cell + select(vec2<f32>(0.0), vec2<f32>(1.0), d.xy > vec2<f32>(0.0))) * cell_size;
        let tb = (bound - s0.xy) / d.xy;
        let t_exit = max(min(select(1e9, tb.x, d.x != 0.0), select(1e9, tb.y, d.y != 0.0)), t + 1e-3);
        let nearest = pyramid_depth(vec2<i32>(cell), level);
        let ray_far = min(s0.z + d.z * t, s0.z + d.z * t_exit);
        let ray_near = max(s0.z + d.z * t, s0.z + d.z * t_exit);
        if ray_far > nearest {
            // In front of everything under this texel: skip it, and look wider.
            t = t_exit + 1e-3;
            level = min(level + 1, top);
        } else if level > 0 {
            level -= 1;
        } else {
            // At one pixel whose surface the ray reaches: a hit if it crosses the surface
            // within the pixel, or is behind it by at most the thickness when it enters.
            // A surface the ray would meet from behind (its normal along the ray) is the
            // far side of something the ray passes behind, not what it sees.
            let px = vec2<i32>(cell);
            let facing = dot(oct_decode(textureLoad(gbuffer1, px, 0).rg), l) < 0.0;
            if facing && ray_near >= nearest {
                return vec3<f32>(vec2<f32>(px), 1.0);
            }
            let surface = world_at(vec2<f32>(px) + vec2<f32>(0.5), nearest);
            let ray = world_at(vec2<f32>(px) + vec2<f32>(0.5), max(ray_near, 1e-7));
            let behind = dot(ray - surface, view.forward.xyz);
            if facing && behind <= params.thickness_m {
                return vec3<f32>(vec2<f32>(px), 1.0);
            }
            t = t_exit + 1e-3;
        }
    }
    return vec3<f32>(0.0);
}

// The surface of a pixel that reflects: its normal n, the direction v to the camera, its
// position p (m) and perceptual roughness r. `traced` is false where the pixel is
// background, too rough, unlit or saturated (a pixel clamped to the f16 maximum no longer
// holds the term to replace): such a pixel keeps the lit frame. It reads no more than the
// depth, the normals' G-buffer texel and the specular level's, so that the trace can tell
// early which pixels it skips.
struct Reflector {
    n: vec3<f32>,
    v: vec3<f32>,
    p: vec3<f32>,
    r: f32,
    traced: bool,
}

fn reflecting_surface(pixel: vec2<i32>, lit: vec3<f32>) -> Reflector {
    var s: Reflector;
    s.traced = false;
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    if depth <= 0.0 {
        return s;
    }
    let g1 = textureLoad(gbuffer1, pixel, 0);
    let level = textureLoad(specular_level, pixel, 0).r;
    s.r = clamp_perceptual_roughness(g1.b);
    if s.r > params.max_roughness || any(lit >= vec3<f32>(65000.0)) || is_unlit(level) {
        return s;
    }
    s.n = oct_decode(g1.rg);
    s.p = world_at(vec2<f32>(pixel) + vec2<f32>(0.5), depth);
    s.v = safe_normalize(view.position_exposure.xyz - s.p, s.n);
    s.traced = true;
    return s;
}

// The terms of the reflection of surface `s` at `pixel` that do not depend on the rays:
// the split-sum weight lighting gave environment light times the roughness fade
// (`weight`, rgb), and the environment radiance E it used (`fallback`).
struct Terms {
    weight: vec3<f32>,
    fallback: vec3<f32>,
}

fn reflection_terms(pixel: vec2<i32>, s: Reflector) -> Terms {
    var t: Terms;
    let g0 = textureLoad(gbuffer0, pixel, 0);
    let g1 = textureLoad(gbuffer1, pixel, 0);
    let level = textureLoad(specular_level, pixel, 0).r;
    // Fades out over the last quarter below the cutoff.
    let fade = clamp((params.max_roughness - s.r) / (0.25 * params.max_roughness), 0.0, 1.0);
    let base = vec3<f32>(srgb_decode(g0.r), srgb_decode(g0.g), srgb_decode(g0.b));
    let n_dot_v = max(dot(s.n, s.v), MIN_N_DOT_V);
    let f0 = compute_f0(base, g1.a, level);
    let dfg = textureSampleLevel(brdf_lut, env_sampler, vec2<f32>(n_dot_v, s.r), 0.0).rg;
    var energy = vec3<f32>(1.0);
    if ENERGY_COMPENSATION {
        energy = energy_compensation(f0, dfg);
    }
    var ao = unpack_occlusion(g0.a);
    if SCREEN_AO {
        ao = combine_occlusion(ao, textureLoad(screen_ao, pixel, 0).r);
    }
    t.weight = (f0 * dfg.x + vec3<f32>(dfg.y)) * energy * specular_occlusion(n_dot_v, ao, s.r) * fade;
    let reflected = 2.0 * dot(s.n, s.v) * s.n - s.v;
    t.fallback = environment_radiance(reflected, s.r);
    if REFLECTION_PROBE_SLOTS > 0u {
        t.fallback = probe_reflection(s.p, reflected, s.r, t.fallback, view.position_exposure.w);
    }
    return t;
}

// The rays of surface `s`: the mean over rays of the lit frame where they hit (rgb;
// blended out near the screen's edges), and the fraction of the rays that hit (a).
// `noise` seeds the per-pixel rotation of the rays.
fn reflection_hits(s: Reflector, noise: vec2<f32>) -> vec4<f32> {
    let frame = basis(s.n);
    let local_v = transpose(frame) * s.v;
    let alpha = perceptual_roughness_to_alpha(s.r);
    let rotation = fract(52.9829189 * fract(dot(noise, vec2<f32>(0.06711056, 0.00583715))));
    var sum = vec4<f32>(0.0);
    for (var k = 0u; k < RAYS; k++) {
        let xi = fract(hammersley(k, RAYS) + vec2<f32>(rotation, 0.5 * rotation));
        let h = frame * sample_ggx_vndf(local_v, alpha, xi);
        let l = reflect(-s.v, h);
        if dot(l, s.n) > 0.0 {
            let hit = trace(s.p + s.n * (1e-3 * length(s.p - view.position_exposure.xyz)), l);
            if hit.z > 0.0 {
                // Hits near the screen's edges blend into the environment.
                let border = min(min(hit.x, hit.y), min(view.viewport.x - hit.x, view.viewport.y - hit.y));
                let keep = clamp(border / (0.05 * view.viewport.y), 0.0, 1.0);
                sum += vec4<f32>(textureLoad(scene_color, vec2<i32>(hit.xy), 0).rgb, 1.0) * keep;
            }
        }
    }
    return sum / f32(RAYS);
}

// The lit frame plus W · (L̄ − E), where L̄ takes the hits' light and E for the rest:
// W · (hits − fraction · E). Kept finite and inside the f16 range.
fn with_reflection(lit: vec4<f32>, t: Terms, hits: vec4<f32>) -> vec4<f32> {
    let added = t.weight * (hits.rgb - hits.a * t.fallback);
    let safe = select(added, vec3<f32>(0.0), added != added);
    return vec4<f32>(min(max(lit.rgb + safe, vec3<f32>(0.0)), vec3<f32>(65504.0)), lit.a);
}

// The mark steps write depth 1 into a depth target cleared to 0 where the next step has
// something to add; that step is depth-tested against it (its triangle lies at depth 0,
// compared with Less), so the rasterizer shades no other pixel, and those keep the lit
// frame the HDR target already holds. A branch alone would not spare them on a SIMD
// rasterizer such as llvmpipe, which runs both sides under a lane mask.

// Whether `pixel` traces: what the mark steps test.
fn traces(pixel: vec2<i32>) -> bool {
    return reflecting_surface(pixel, textureLoad(scene_color, pixel, 0).rgb).traced;
}

// Full resolution, step 1: marks the pixels that trace.
@fragment
fn fs_mark_full(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    if !traces(vec2<i32>(frag.xy)) {
        discard;
    }
    return 1.0;
}

// Full resolution, step 2, on the marked pixels: each traces its own rays.
@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let lit = textureLoad(scene_color, pixel, 0);
    let s = reflecting_surface(pixel, lit.rgb);
    var t: Terms;
    var hits = vec4<f32>(0.0);
    if s.traced {
        t = reflection_terms(pixel, s);
        hits = reflection_hits(s, frag.xy);
    }
    return with_reflection(lit, t, hits);
}

// The pixel that traces for the 2×2 block at half-resolution fragment `frag`: its
// top-left one.
fn block_pixel(frag: vec2<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(depth_buffer));
    return min(vec2<i32>(frag) * 2, size - vec2<i32>(1));
}

// Half resolution, step 1: marks the blocks whose pixel traces. Without it, every SIMD
// group of the trace that holds one such block would run the rays for all of its blocks
// (masked), and the many that hold none would still pay for a pass through the loops.
@fragment
fn fs_mark_trace_half(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    if !traces(block_pixel(frag.xy)) {
        discard;
    }
    return 1.0;
}

// Half resolution, step 2, on the marked blocks: the hits of the block's pixel.
@fragment
fn fs_trace_half(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = block_pixel(frag.xy);
    let s = reflecting_surface(pixel, textureLoad(scene_color, pixel, 0).rgb);
    if !s.traced {
        return vec4<f32>(0.0);
    }
    return reflection_hits(s, frag.xy);
}

// The hits pixel `pixel` takes from its block: those of the block's traced pixel when
// both lie on one surface (depths within 1 %; reversed-Z depth is 1/distance up to a
// factor); none otherwise.
fn block_hits(pixel: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(depth_buffer));
    let cell = min(pixel / 2, vec2<i32>(textureDimensions(half_added)) - vec2<i32>(1));
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    let source = textureLoad(depth_buffer, min(cell * 2, size - vec2<i32>(1)), 0).r;
    if depth <= 0.0 || abs(depth - source) > 0.01 * depth {
        return vec4<f32>(0.0);
    }
    return textureLoad(half_added, cell, 0);
}

// Half resolution, step 3: marks the pixels whose block has a hit to give them (a pixel
// with no hit would add W · (0 − 0 · E) = 0).
@fragment
fn fs_mark_half(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    if !(block_hits(vec2<i32>(frag.xy)).a > 0.0) {
        discard;
    }
    return 1.0;
}

// Half resolution, step 4, on the marked pixels only: each takes its block's hits, with
// its own weight and environment term.
@fragment
fn fs_composite_half(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let lit = textureLoad(scene_color, pixel, 0);
    let s = reflecting_surface(pixel, lit.rgb);
    var t: Terms;
    if s.traced {
        t = reflection_terms(pixel, s);
    }
    return with_reflection(lit, t, block_hits(pixel));
}

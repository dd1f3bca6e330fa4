// Screen-space ambient occlusion: ground-truth ambient occlusion (GTAO, Jimenez et al.
// 2016) from the depth buffer and the G-buffer's normals
// (engine/src/render/indirect/gtao.rs; the formulas are in
// ambient_occlusion.wgsl and docs/src/indirect.md).
//
// fs_trace runs at AO resolution (one texel per `scale` × `scale` pixels). For SLICES
// screen directions it marches STEPS depth samples on each side, out to the AO radius
// projected to pixels, keeps the highest horizon (each sample weighted by the falloff),
// and integrates the visible arc against the projected normal. Slice angles and step
// offsets are rotated per texel by a 4×4 ordered pattern, so 16 neighbouring texels
// together cover 16 rotations.
//
// fs_trace writes (AO, the texel's position relative to the camera in metres), or
// (-1, 0, 0, 0) on the background, so that the resolve compares positions without
// reconstructing them.
//
// fs_resolve runs at full resolution: with DENOISE, the mean of the 4×4 AO texels around
// the pixel whose surface lies on the pixel's tangent plane (which averages the 16
// rotations and upsamples without bleeding across depth edges); without it, the nearest
// texel.
//
// Header constants: SLICES, STEPS (u32), DENOISE (bool).
#import common
#import encoding
#import bindings
#import fullscreen
#import ambient_occlusion

struct AoParams {
    // AO radius in metres.
    radius_m: f32,
    // Pixels per metre of a surface 1 m in front of the camera (½ height × P[1][1]).
    pixels_per_m: f32,
    // Largest radius in pixels that a slice marches.
    max_radius_px: f32,
    // Full-resolution pixels per AO texel along each axis (1 or 2).
    scale: f32,
}

// Group 0 of fs_trace (TRACE in ambient_occlusion.rs) and of fs_resolve (RESOLVE): the
// same bindings, except the last.
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: AoParams;
@group(0) @binding(2) var depth_buffer: texture_2d<f32>;
@group(0) @binding(3) var gbuffer1: texture_2d<f32>;
@group(0) @binding(4) var raw_ao: texture_2d<f32>;

// World position (m) of full-resolution pixel position `px` at depth `depth`.
fn world_at(px: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(px.x * view.viewport.z * 2.0 - 1.0, 1.0 - px.y * view.viewport.w * 2.0);
    let h = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    return h.xyz / h.w;
}

// Full-resolution pixel position of world point `w`.
fn pixel_of(w: vec3<f32>) -> vec2<f32> {
    let clip = view.clip_from_world * vec4<f32>(w, 1.0);
    let ndc = clip.xy / clip.w;
    return vec2<f32>(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * view.viewport.xy;
}

// The 4×4 ordered-dither index (0..15) of a texel.
fn bayer4(p: vec2<u32>) -> u32 {
    var m = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return m[(p.y & 3u) * 4u + (p.x & 3u)];
}

// The highest horizon cosine so far on one side, updated with the depth sample at pixel
// `q` (skipped off screen and on the background). A pixel centre lies up to half a pixel
// off the slice's line, and on a tilted plane that offset alone would raise the horizon:
// the sample is slid parallel to the pixel's tangent plane (along `slide`, the slice
// plane's normal `axis` made tangent) into the slice plane, which keeps its height above
// the tangent plane, so an open plane stays exactly at the tangent horizon. A sample that
// lands on the other side of p in the slice (`toward` is the side's direction: at grazing
// angles a pixel ahead on the screen can lie behind p on the surface) says nothing about
// this side's horizon and is skipped.
fn horizon_step(best: f32, low: f32, q: vec2<i32>, p: vec3<f32>, v: vec3<f32>, toward: vec3<f32>, axis: vec3<f32>, slide: vec3<f32>) -> f32 {
    let size = vec2<i32>(textureDimensions(depth_buffer));
    if any(q < vec2<i32>(0)) || any(q >= size) {
        return best;
    }
    let d = textureLoad(depth_buffer, q, 0).r;
    if d <= 0.0 {
        return best;
    }
    let delta = world_at(vec2<f32>(q) + vec2<f32>(0.5), d) - p;
    let in_slice = delta - slide * dot(delta, axis);
    if dot(in_slice, toward) <= 0.0 {
        return best;
    }
    let c = dot(in_slice, v) / length(in_slice);
    return max(best, mix(low, c, ao_falloff(length(delta), params.radius_m)));
}

@fragment
fn fs_trace(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let cell = vec2<u32>(frag.xy);
    let size = vec2<i32>(textureDimensions(depth_buffer));
    let pixel = min(vec2<i32>(cell * u32(params.scale)), size - vec2<i32>(1));
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    if depth <= 0.0 {
        return vec4<f32>(-1.0, 0.0, 0.0, 0.0);
    }
    let center = vec2<f32>(pixel) + vec2<f32>(0.5);
    let p = world_at(center, depth);
    let camera = view.position_exposure.xyz;
    let n = oct_decode(textureLoad(gbuffer1, pixel, 0).rg);
    let v = safe_normalize(camera - p, n);
    let z = max(dot(p - camera, view.forward.xyz), 1e-4);
    let radius_px = min(params.radius_m * params.pixels_per_m / z, params.max_radius_px);
    if radius_px < 1.0 {
        return vec4<f32>(1.0, p - camera);
    }
    let b = bayer4(cell);
    let slice_noise = (f32(b) + 0.5) / 16.0;
    let step_noise = (f32((b * 7u) % 16u) + 0.5) / 16.0;
    // Slices are spread evenly in angle about v (not on the screen, where perspective
    // bunches them off the image's centre and an open plane would lose up to 2 %): the
    // slice's world direction `dir` ⟂ v, and the screen direction `d` it projects to.
    let right = world_at(center + vec2<f32>(1.0, 0.0), depth) - p;
    let b1 = safe_normalize(right - v * dot(right, v), vec3<f32>(1.0, 0.0, 0.0));
    let b2 = cross(v, b1);
    var visibility = 0.0;
    for (var s = 0u; s < SLICES; s++) {
        let phi = (f32(s) + slice_noise) / f32(SLICES) * PI;
        let dir = cos(phi) * b1 + sin(phi) * b2;
        let axis = cross(dir, v);
        // The tangent direction that crosses the slice plane, scaled so that moving
        // along it by dot(delta, axis) × slide reaches the plane; the plain projection
        // where the slice plane nearly contains the normal (that slice weighs ~0).
        let tangent_axis = axis - n * dot(axis, n);
        let crossing = dot(tangent_axis, axis);
        let slide = select(axis, tangent_axis / crossing, crossing > 1e-4);
        let d = safe_normalize(vec3<f32>(pixel_of(p + dir * (0.01 * z)) - center, 0.0), vec3<f32>(1.0, 0.0, 0.0)).xy;
        let projected = gtao_projected_normal(n, v, dir);
        let low = gtao_open_horizons(projected.y);
        var horizon = low;
        for (var k = 0u; k < STEPS; k++) {
            let t = (f32(k) + step_noise) / f32(STEPS);
            let offset = d * (1.0 + (radius_px - 1.0) * t * t);
            horizon.x = horizon_step(horizon.x, low.x, vec2<i32>(floor(center - offset)), p, v, -dir, axis, slide);
            horizon.y = horizon_step(horizon.y, low.y, vec2<i32>(floor(center + offset)), p, v, dir, axis, slide);
        }
        visibility += gtao_slice(projected, horizon);
    }
    return vec4<f32>(clamp(visibility / f32(SLICES), 0.0, 1.0), p - camera);
}

@fragment
fn fs_resolve(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    if depth <= 0.0 {
        return vec4<f32>(1.0);
    }
    let scale = i32(params.scale);
    let last = vec2<i32>(textureDimensions(raw_ao)) - vec2<i32>(1);
    let cell = min(pixel / scale, last);
    // The nearest texel's AO (1 where it saw the background).
    let nearest = textureLoad(raw_ao, cell, 0).r;
    if !DENOISE {
        return vec4<f32>(select(nearest, 1.0, nearest < 0.0));
    }
    let camera = view.position_exposure.xyz;
    let p = world_at(vec2<f32>(pixel) + vec2<f32>(0.5), depth) - camera;
    let n = oct_decode(textureLoad(gbuffer1, pixel, 0).rg);
    let z = max(dot(p, view.forward.xyz), 1e-4);
    // A texel counts in full when its surface lies within 1 % of the view depth of the
    // pixel's tangent plane, not at all beyond 3 %.
    let tolerance = 0.01 * z;
    var sum = 0.0;
    var weight = 0.0;
    for (var dy = -1; dy <= 2; dy++) {
        for (var dx = -1; dx <= 2; dx++) {
            let texel = textureLoad(raw_ao, clamp(cell + vec2<i32>(dx, dy), vec2<i32>(0), last), 0);
            let off_plane = abs(dot(texel.yzw - p, n));
            let w = select(0.0, clamp(1.5 - 0.5 * off_plane / tolerance, 0.0, 1.0), texel.x >= 0.0);
            sum += w * texel.x;
            weight += w;
        }
    }
    return vec4<f32>(select(select(nearest, 1.0, nearest < 0.0), sum / weight, weight > 1e-3));
}

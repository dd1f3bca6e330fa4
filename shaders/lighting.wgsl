// Deferred lighting pass: one full-screen triangle (depth-tested where the adapter allows:
// background pixels are not shaded); per pixel with geometry, the surface the G-buffer
// holds, lit by surface_light.wgsl (its header constants select the lights and indirect
// terms), plus emissive. Output: pre-exposed HDR luminance (rgb) and coverage (a = 1; the
// background keeps the pass's clear colour with a = 0).
#import common
#import brdf
#import color
#import encoding
#import bindings
#import fullscreen
#import surface_light
#import shadow_kernel
#import irradiance_volume

// Group 0, the view and the G-buffer (engine/src/render/lighting.rs, VIEW_AND_GBUFFER).
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var gbuffer0: texture_2d<f32>;
@group(0) @binding(2) var gbuffer1: texture_2d<f32>;
@group(0) @binding(3) var gbuffer2: texture_2d<f32>;
// Depth bound as an unfilterable float texture: GLSL backends cannot textureLoad a
// depth texture.
@group(0) @binding(4) var depth_buffer: texture_2d<f32>;
// The shadow-mask pass's output (shadow_mask.wgsl), read where SHADOW_MASK_SCALE > 0, and a
// sampler that clamps to its edge (for textureGather; it does not filter).
@group(0) @binding(5) var shadow_mask: texture_2d<f32>;
@group(0) @binding(6) var shadow_mask_sampler: sampler;

const F16_MAX: f32 = 65504.0;

// The irradiance volume pass's output (volume_irradiance.wgsl), read where
// HALF_VOLUME (gathered with the shadow mask's sampler).
@group(0) @binding(7) var volume_half: texture_2d<f32>;

// The four half-resolution texels around full-resolution `pixel`, whose view depth is
// `depth` (m): the texel with the smallest coordinates (`base`), where to gather them
// (`uv`) and each one's shadow_mask_weight, bilinear × depth (`w`). Texel (x, y) was
// shaded at pixel (2x, 2y), and the texture holds each texel's view depth in its alpha.
// The four texels come in one textureGather per channel, x y z w = (0, 1) (1, 1) (1, 0)
// (0, 0) from `base`, at the corner the four share; the sampler clamps at the texture's
// edge.
struct HalfResolution {
    base: vec2<i32>,
    uv: vec2<f32>,
    w: vec4<f32>,
    texel_depth: vec4<f32>,
}

fn half_resolution_weights(half: texture_2d<f32>, pixel: vec2<i32>, depth: f32) -> HalfResolution {
    // The pixel lies at pixel / 2 in texels.
    let t = vec2<f32>(pixel) * 0.5;
    let base = floor(t);
    let f = t - base;
    var out: HalfResolution;
    out.base = vec2<i32>(base);
    // The corner shared by texels base and base + 1: the gather's footprint, unambiguous.
    out.uv = (base + 1.0) / vec2<f32>(textureDimensions(half));
    let g = vec2<f32>(1.0) - f;
    let bilinear = vec4<f32>(g.x * f.y, f.x * f.y, f.x * g.y, g.x * g.y);
    out.texel_depth = textureGather(3, half, shadow_mask_sampler, out.uv);
    out.w = vec4<f32>(
        shadow_mask_weight(bilinear.x, out.texel_depth.x, depth),
        shadow_mask_weight(bilinear.y, out.texel_depth.y, depth),
        shadow_mask_weight(bilinear.z, out.texel_depth.z, depth),
        shadow_mask_weight(bilinear.w, out.texel_depth.w, depth),
    );
    return out;
}

// The weights, summing to 1, of the four texels whose upsample weights are `w` and whose
// view depths differ from the pixel's by `gap` (m): w normalised, or, where all four are
// about 0 (every texel across a depth edge), the texel nearest in depth alone, first of
// (0, 0) (1, 0) (0, 1) (1, 1) on a tie. A texel left out for another reason than depth
// is kept out of the choice by adding to its gap.
fn upsample_weights(w: vec4<f32>, gap: vec4<f32>) -> vec4<f32> {
    let total = dot(w, vec4<f32>(1.0));
    let least = min(min(gap.x, gap.y), min(gap.z, gap.w));
    var nearest = vec4<f32>(0.0, 1.0, 0.0, 0.0);
    nearest = select(nearest, vec4<f32>(1.0, 0.0, 0.0, 0.0), gap.x == least);
    nearest = select(nearest, vec4<f32>(0.0, 0.0, 1.0, 0.0), gap.z == least);
    nearest = select(nearest, vec4<f32>(0.0, 0.0, 0.0, 1.0), gap.w == least);
    return select(nearest, w / max(total, 1e-6), total > 1e-3);
}

// The visibility of shadowed directional lights 0 to SHADOW_MASK_LIGHTS − 1 at `pixel`,
// whose view depth is `depth` (m), from the shadow mask: at full resolution its texel; at
// half resolution its 2 × 2 texels around the pixel, weighted by half_resolution_weights,
// or, where all four lie across a depth edge, the texel nearest in depth.
fn shadow_mask_visibility(pixel: vec2<i32>, depth: f32) -> vec3<f32> {
    if SHADOW_MASK_SCALE == 1u {
        return textureLoad(shadow_mask, pixel, 0).rgb;
    }
    let up = half_resolution_weights(shadow_mask, pixel, depth);
    let weights = upsample_weights(up.w, abs(up.texel_depth - depth));
    var lit = vec3<f32>(1.0);
    lit.x = dot(weights, textureGather(0, shadow_mask, shadow_mask_sampler, up.uv));
    if SHADOW_MASK_LIGHTS > 1u {
        lit.y = dot(weights, textureGather(1, shadow_mask, shadow_mask_sampler, up.uv));
    }
    if SHADOW_MASK_LIGHTS > 2u {
        lit.z = dot(weights, textureGather(2, shadow_mask, shadow_mask_sampler, up.uv));
    }
    return lit;
}

// The irradiance volume's pre-exposed irradiance at `pixel` (view depth `depth`, m, unit
// normal `n`), from the half-resolution volume pass: its 2 × 2 texels around the pixel,
// weighted by half_resolution_weights times upsample_normal_weight of the normal at each
// texel's pixel (so that light does not cross a crease, where two faces meet at one
// depth). Where every weight is 0 it takes the texel nearest in depth among those facing
// the pixel's way (upsample_weights), as the shadow mask does: looking the volume up here
// instead costs every pixel of a SIMD group that holds one such pixel the full lookup
// (measured: 5 ms of the lighting pass at 1280×720 on llvmpipe).
fn half_volume_irradiance(pixel: vec2<i32>, depth: f32, n: vec3<f32>) -> vec3<f32> {
    var up = half_resolution_weights(volume_half, pixel, depth);
    let last_texel = vec2<i32>(textureDimensions(volume_half)) - vec2<i32>(1);
    let last_pixel = vec2<i32>(textureDimensions(gbuffer1)) - vec2<i32>(1);
    let corners = array<vec2<i32>, 4>(vec2<i32>(0, 1), vec2<i32>(1, 1), vec2<i32>(1, 0), vec2<i32>(0, 0));
    var gap = abs(up.texel_depth - depth);
    for (var k = 0; k < 4; k++) {
        let texel = min(up.base + corners[k], last_texel);
        let texel_n = oct_decode(textureLoad(gbuffer1, min(texel * 2, last_pixel), 0).rg);
        let facing = upsample_normal_weight(texel_n, n);
        up.w[k] *= facing;
        gap[k] += select(0.0, F16_MAX, facing <= 0.0);
    }
    let weights = upsample_weights(up.w, gap);
    return vec3<f32>(
        dot(weights, textureGather(0, volume_half, shadow_mask_sampler, up.uv)),
        dot(weights, textureGather(1, volume_half, shadow_mask_sampler, up.uv)),
        dot(weights, textureGather(2, volume_half, shadow_mask_sampler, up.uv)),
    );
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    // Where the adapter can depth-test against a depth buffer it also reads, the depth
    // test already rejected the background (the pass's clear colour); elsewhere (GL) it
    // is written here.
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    if depth <= 0.0 {
        return vec4<f32>(view.background.rgb, 0.0);
    }
    let g0 = textureLoad(gbuffer0, pixel, 0);
    let g1 = textureLoad(gbuffer1, pixel, 0);
    let g2 = textureLoad(gbuffer2, pixel, 0);

    var surface: Surface;
    surface.base_color = vec3<f32>(srgb_decode(g0.r), srgb_decode(g0.g), srgb_decode(g0.b));
    // An unlit surface (KHR_materials_unlit) shows its base colour, pre-exposed as it is.
    if is_unlit(g2.a) {
        return vec4<f32>(surface.base_color, 1.0);
    }
    surface.perceptual_roughness = g1.b;
    surface.metallic = g1.a;
    surface.specular_level = g2.a;
    let n = oct_decode(g1.rg);

    // World position from depth.
    let ndc = vec2<f32>(frag.x * view.viewport.z * 2.0 - 1.0, 1.0 - frag.y * view.viewport.w * 2.0);
    let world_h = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    let world = world_h.xyz / world_h.w;
    let v = safe_normalize(view.position_exposure.xyz - world, n);

    var point: ShadingPoint;
    point.world = world;
    point.n = n;
    point.v = v;
    point.frag = frag.xy;
    point.occlusion = unpack_occlusion(g0.a);
    point.receives = unpack_receives_shadows(g0.a);
    let view_depth = dot(world - view.position_exposure.xyz, view.forward.xyz);
    if SHADOW_MASK_SCALE > 0u {
        point.directional_lit = shadow_mask_visibility(pixel, view_depth);
    }
    if HALF_VOLUME {
        point.volume_irradiance = half_volume_irradiance(pixel, view_depth, n);
    }
    var color = g2.rgb + surface_light(point, surface);
    // Keep the value finite in the f16 target (docs/src/formulas.md#numerical-guards); NaN becomes 0.
    color = select(color, vec3<f32>(0.0), color != color);
    return vec4<f32>(min(color, vec3<f32>(F16_MAX)), 1.0);
}

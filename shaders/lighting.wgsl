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

// The visibility of shadowed directional lights 0 to SHADOW_MASK_LIGHTS − 1 at `pixel`,
// whose view depth is `depth` (m), from the shadow mask: at full resolution its texel; at
// half resolution the 2 × 2 texels around the pixel centre, each weighted by
// shadow_mask_weight (bilinear × depth), or, where all four lie across a depth edge, the
// texel nearest in depth. The four texels come in one textureGather per channel (depth
// and each light), x y z w = (0, 1) (1, 1) (1, 0) (0, 0) from the footprint's top-left
// texel; the sampler clamps at the mask's edge.
fn shadow_mask_visibility(pixel: vec2<i32>, depth: f32) -> vec3<f32> {
    if SHADOW_MASK_SCALE == 1u {
        return textureLoad(shadow_mask, pixel, 0).rgb;
    }
    // Texel (x, y) was shaded at pixel (2x, 2y): the pixel lies at pixel / 2 in texels.
    let t = vec2<f32>(pixel) * 0.5;
    let base = floor(t);
    let f = t - base;
    // The corner shared by texels base and base + 1: the gather's footprint, unambiguous.
    let uv = (base + 1.0) / vec2<f32>(textureDimensions(shadow_mask));
    let g = vec2<f32>(1.0) - f;
    let bilinear = vec4<f32>(g.x * f.y, f.x * f.y, f.x * g.y, g.x * g.y);
    let texel_depth = textureGather(3, shadow_mask, shadow_mask_sampler, uv);
    let w = vec4<f32>(
        shadow_mask_weight(bilinear.x, texel_depth.x, depth),
        shadow_mask_weight(bilinear.y, texel_depth.y, depth),
        shadow_mask_weight(bilinear.z, texel_depth.z, depth),
        shadow_mask_weight(bilinear.w, texel_depth.w, depth),
    );
    let total = dot(w, vec4<f32>(1.0));
    // The texel nearest in depth, first of (0, 0) (1, 0) (0, 1) (1, 1) on a tie.
    let gap = abs(texel_depth - depth);
    let least = min(min(gap.x, gap.y), min(gap.z, gap.w));
    var nearest = vec4<f32>(0.0, 1.0, 0.0, 0.0);
    nearest = select(nearest, vec4<f32>(1.0, 0.0, 0.0, 0.0), gap.x == least);
    nearest = select(nearest, vec4<f32>(0.0, 0.0, 1.0, 0.0), gap.z == least);
    nearest = select(nearest, vec4<f32>(0.0, 0.0, 0.0, 1.0), gap.w == least);
    let weights = select(nearest, w / max(total, 1e-6), total > 1e-3);
    var lit = vec3<f32>(1.0);
    lit.x = dot(weights, textureGather(0, shadow_mask, shadow_mask_sampler, uv));
    if SHADOW_MASK_LIGHTS > 1u {
        lit.y = dot(weights, textureGather(1, shadow_mask, shadow_mask_sampler, uv));
    }
    if SHADOW_MASK_LIGHTS > 2u {
        lit.z = dot(weights, textureGather(2, shadow_mask, shadow_mask_sampler, uv));
    }
    return lit;
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
    if SHADOW_MASK_SCALE > 0u {
        let view_depth = dot(world - view.position_exposure.xyz, view.forward.xyz);
        point.directional_lit = shadow_mask_visibility(pixel, view_depth);
    }
    var color = g2.rgb + surface_light(point, surface);
    // Keep the value finite in the f16 target (docs/src/formulas.md#numerical-guards); NaN becomes 0.
    color = select(color, vec3<f32>(0.0), color != color);
    return vec4<f32>(min(color, vec3<f32>(F16_MAX)), 1.0);
}

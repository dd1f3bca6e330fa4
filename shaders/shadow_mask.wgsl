// Screen-space shadow mask (engine/src/render/shadow/mask.rs): the visibility of each
// shadowed directional light, resolved once per mask texel in its own pass, so that the
// lighting pass reads one value per light instead of filtering the shadow map in its
// light loop. At half resolution one texel stands for 2 × 2 pixels (the top-left one is
// shaded) and the lighting pass upsamples with the depth-aware weights of
// shadow_kernel.wgsl (shadow_mask_visibility in lighting.wgsl).
//
// fs_depth copies the depth of each texel's pixel into a depth target at mask resolution;
// fs_main is depth-tested against it, so it shades only texels whose pixel holds geometry
// (a software rasterizer such as llvmpipe runs both sides of a branch, so an early return
// would not spare the background the lookups; the depth test does). fs_main writes
// (visibility of shadowed directional light 0, 1, 2; the view depth of the shaded pixel
// in m); the background keeps the pass's clear value (1, 1, 1, −1). A pixel whose
// material does not receive shadows gets 1.
//
// Header constants: SHADOW_MASK_SCALE (pixels per texel along each axis, 1 or 2),
// SHADOW_MASK_LIGHTS (the shadowed directional lights it holds, 1 to 3, one per colour
// channel: a constant, so the loop over them unrolls), and those of lights.wgsl and
// shadows.wgsl.
#import common
#import encoding
#import bindings
#import fullscreen
#import lights
#import shadows

// Group 0 (VIEW_AND_GBUFFER in mask.rs); group 1 is the lighting pass's lights and shadows.
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var depth_buffer: texture_2d<f32>;
@group(0) @binding(2) var gbuffer0: texture_2d<f32>;
@group(0) @binding(3) var gbuffer1: texture_2d<f32>;

// The depth of each texel's pixel, at mask resolution.
@fragment
fn fs_depth(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(depth_buffer, vec2<i32>(frag.xy) * i32(SHADOW_MASK_SCALE), 0).r;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy) * i32(SHADOW_MASK_SCALE);
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    let n = oct_decode(textureLoad(gbuffer1, pixel, 0).rg);
    let receives = unpack_receives_shadows(textureLoad(gbuffer0, pixel, 0).a);
    // The shaded pixel's centre, as the lighting pass sees it (its noise too).
    let centre = vec2<f32>(pixel) + 0.5;
    let ndc = vec2<f32>(centre.x * view.viewport.z * 2.0 - 1.0, 1.0 - centre.y * view.viewport.w * 2.0);
    let world_h = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    let world = world_h.xyz / world_h.w;
    let view_depth = dot(world - view.position_exposure.xyz, view.forward.xyz);
    var lit = vec3<f32>(1.0);
    for (var i = 0u; i < SHADOW_MASK_LIGHTS; i++) {
        lit[i] = mix(1.0, directional_shadow(shadowed_light(i, i), world, n, centre, view_depth), receives);
    }
    return vec4<f32>(lit, view_depth);
}

// The irradiance volume at half resolution (engine/src/render/indirect/volume_irradiance.rs):
// the volume's irradiance (volume_lookup.wgsl) once per 2 × 2 pixels, at the top-left pixel
// of each block, so that the lighting pass reads four texels instead of sixteen bilinear
// samples per pixel and upsamples them with the shadow mask's depth-aware weights and a
// normal term (half_volume_irradiance in lighting.wgsl).
//
// fs_depth copies the depth of each texel's pixel into a depth target at half resolution;
// fs_main is depth-tested against it, so it shades only texels whose pixel holds geometry
// (a software rasterizer runs both sides of a branch: the depth test is what spares the
// background). fs_main writes (pre-exposed irradiance, the view depth of the shaded pixel
// in m); the background keeps the pass's clear value (0, 0, 0, −1).
#import common
#import encoding
#import bindings
#import fullscreen
#import volume_lookup

// Group 0 (VIEW_AND_GBUFFER in volume_irradiance.rs); group 3 is the lighting pass's probes.
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var depth_buffer: texture_2d<f32>;
@group(0) @binding(2) var gbuffer1: texture_2d<f32>;

const F16_MAX: f32 = 65504.0;

// The depth of each texel's pixel, at half resolution.
@fragment
fn fs_depth(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(depth_buffer, vec2<i32>(frag.xy) * 2, 0).r;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy) * 2;
    let depth = textureLoad(depth_buffer, pixel, 0).r;
    let n = oct_decode(textureLoad(gbuffer1, pixel, 0).rg);
    // The shaded pixel's centre and world position, as the lighting pass finds them.
    let centre = vec2<f32>(pixel) + 0.5;
    let ndc = vec2<f32>(centre.x * view.viewport.z * 2.0 - 1.0, 1.0 - centre.y * view.viewport.w * 2.0);
    let world_h = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    let world = world_h.xyz / world_h.w;
    let camera = view.position_exposure.xyz;
    let v = safe_normalize(camera - world, n);
    let view_depth = dot(world - camera, view.forward.xyz);
    let e = exposed_volume_irradiance(world, n, v, view.position_exposure.w);
    return vec4<f32>(min(e, vec3<f32>(F16_MAX)), view_depth);
}

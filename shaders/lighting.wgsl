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

// Group 0, the view and the G-buffer (engine/src/render/lighting.rs, VIEW_AND_GBUFFER).
@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var gbuffer0: texture_2d<f32>;
@group(0) @binding(2) var gbuffer1: texture_2d<f32>;
@group(0) @binding(3) var gbuffer2: texture_2d<f32>;
// Depth bound as an unfilterable float texture: GLSL backends cannot textureLoad a
// depth texture.
@group(0) @binding(4) var depth_buffer: texture_2d<f32>;

const F16_MAX: f32 = 65504.0;

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
    var color = g2.rgb + surface_light(point, surface);
    // Keep the value finite in the f16 target (docs/src/formulas.md#numerical-guards); NaN becomes 0.
    color = select(color, vec3<f32>(0.0), color != color);
    return vec4<f32>(min(color, vec3<f32>(F16_MAX)), 1.0);
}

// Debug views: one channel of the frame instead of the tone-mapped image
// (engine/src/render/debug_view.rs documents each view's encoding).
// Header constants: DEBUG_VIEW (DebugView as u32), ENCODE_SRGB (true when the target
// format is not an *Srgb format) and SCREEN_AO (the AO pass ran: the occlusion view
// combines its result). Needs common, color, camera, encoding, bindings,
// fullscreen, validate.
#import color
#import camera
#import encoding
#import bindings
#import fullscreen
#import validate
#import ambient_occlusion

struct DebugParams {
    focus_m: f32,
    focal_length_m: f32,
    aperture_diameter_m: f32,
    // Full-resolution pixels per metre on the sensor.
    pixels_per_m: f32,
    // CoC radius (px) shown as full intensity.
    max_radius_px: f32,
    // Side of the shadow atlas in texels (1 when no light casts shadows).
    atlas_side: f32,
    pad0: f32,
    pad1: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: DebugParams;
@group(0) @binding(2) var gbuffer0: texture_2d<f32>;
@group(0) @binding(3) var gbuffer1: texture_2d<f32>;
@group(0) @binding(4) var depth_buffer: texture_2d<f32>;
@group(0) @binding(5) var shadow_atlas: texture_2d<f32>;
@group(0) @binding(6) var screen_ao: texture_2d<f32>;

const VIEW_ALBEDO: u32 = 1u;
const VIEW_NORMAL: u32 = 2u;
const VIEW_METALLIC: u32 = 3u;
const VIEW_ROUGHNESS: u32 = 4u;
const VIEW_OCCLUSION: u32 = 5u;
const VIEW_DEPTH: u32 = 6u;
const VIEW_SHADOW_ATLAS: u32 = 7u;
const VIEW_COC: u32 = 8u;
const VIEW_VALIDATION: u32 = 9u;
const VIEW_VALIDATION_STRICT: u32 = 10u;

// View depth (m) as a grey level: 1 at 0.1 m, 0 at 100 m, logarithmic between.
fn depth_grey(depth_m: f32) -> f32 {
    return clamp(1.0 - log2(max(depth_m, 1e-6) / 0.1) / log2(1000.0), 0.0, 1.0);
}

// Distance (m) along the camera's forward axis of the surface at pixel `p`, or a
// negative number for the background.
fn view_depth(p: vec2<i32>) -> f32 {
    let depth = textureLoad(depth_buffer, p, 0).r;
    if depth <= 0.0 {
        return -1.0;
    }
    let ndc = vec2<f32>((f32(p.x) + 0.5) * view.viewport.z * 2.0 - 1.0, 1.0 - (f32(p.y) + 0.5) * view.viewport.w * 2.0);
    let w = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    return dot(w.xyz / w.w - view.position_exposure.xyz, view.forward.xyz);
}

// The view's colour as display values (before the output encoding).
fn debug_color(p: vec2<i32>) -> vec3<f32> {
    let background = textureLoad(depth_buffer, p, 0).r <= 0.0;
    let g0 = textureLoad(gbuffer0, p, 0);
    let g1 = textureLoad(gbuffer1, p, 0);
    switch DEBUG_VIEW {
        case VIEW_ALBEDO: {
            // Stored sRGB-encoded: decode, so that the output encoding restores it.
            return vec3<f32>(srgb_decode(g0.r), srgb_decode(g0.g), srgb_decode(g0.b));
        }
        case VIEW_NORMAL: {
            if background {
                return vec3<f32>(0.0);
            }
            return oct_decode(g1.rg) * 0.5 + vec3<f32>(0.5);
        }
        case VIEW_METALLIC: {
            return vec3<f32>(g1.a);
        }
        case VIEW_ROUGHNESS: {
            return vec3<f32>(g1.b);
        }
        case VIEW_OCCLUSION: {
            if background {
                return vec3<f32>(0.0);
            }
            var ao = unpack_occlusion(g0.a);
            if SCREEN_AO {
                ao = combine_occlusion(ao, textureLoad(screen_ao, p, 0).r);
            }
            return vec3<f32>(ao);
        }
        case VIEW_DEPTH: {
            let z = view_depth(p);
            return vec3<f32>(select(depth_grey(z), 0.0, z < 0.0));
        }
        case VIEW_SHADOW_ATLAS: {
            // The square atlas fills the frame's height from the left edge.
            let side = params.atlas_side;
            let t = (vec2<f32>(p) + vec2<f32>(0.5)) * side * view.viewport.w;
            if t.x >= side {
                return vec3<f32>(0.0);
            }
            return vec3<f32>(textureLoad(shadow_atlas, vec2<i32>(t), 0).r);
        }
        case VIEW_COC: {
            var z = view_depth(p);
            if z < 0.0 {
                z = 3.0e38;
            }
            let r = circle_of_confusion(z, params.focus_m, params.focal_length_m, params.aperture_diameter_m) * params.pixels_per_m * 0.5;
            let v = clamp(abs(r) / params.max_radius_px, 0.0, 1.0);
            return select(vec3<f32>(0.0, v, 0.0), vec3<f32>(v, 0.0, 0.0), r < 0.0);
        }
        case VIEW_VALIDATION, VIEW_VALIDATION_STRICT: {
            if background {
                return vec3<f32>(0.0);
            }
            let base = vec3<f32>(srgb_decode(g0.r), srgb_decode(g0.g), srgb_decode(g0.b));
            return verdict_color(metal_rough_verdict(base, g1.a, DEBUG_VIEW == VIEW_VALIDATION_STRICT));
        }
        default: {
            return vec3<f32>(1.0, 0.0, 1.0);
        }
    }
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    var c = debug_color(p);
    // Data channels are shown as stored: the output encoding must not change them, so
    // they are decoded here and encoded again below. Albedo is already linear.
    if DEBUG_VIEW != VIEW_ALBEDO {
        c = vec3<f32>(srgb_decode(c.r), srgb_decode(c.g), srgb_decode(c.b));
    }
    if ENCODE_SRGB {
        c = vec3<f32>(srgb_encode(c.r), srgb_encode(c.g), srgb_encode(c.b));
    }
    return vec4<f32>(c, 1.0);
}

// The one-frame filters' first step (engine/src/render/antialias/prepare.rs): the HDR
// image copied as it is (rgb, linear, so that a blend of neighbours is the mean the
// reference's pixel filter takes), with the perceptual luma the filters compare in a:
// √Y of the compressed colour (compress_hdr, perceptual_luma), so an edge's contrast is
// judged as the display shows it. Non-finite colour becomes black; colour beyond f16's
// range is clamped to it.
#import color
#import antialiasing
#import fullscreen

@group(0) @binding(0) var hdr: texture_2d<f32>;

// The largest finite f16.
const F16_MAX: f32 = 65504.0;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let raw = textureLoad(hdr, vec2<i32>(frag.xy), 0);
    let c = select(vec3<f32>(0.0), clamp(raw.rgb, vec3<f32>(-F16_MAX), vec3<f32>(F16_MAX)), is_finite4(raw));
    return vec4<f32>(c, perceptual_luma(compress_hdr(c)));
}

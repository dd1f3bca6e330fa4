// Tone mapping pass: exposed HDR luminance → display colour, after the lens's vignetting.
// Header constants: TONEMAPPER (see color.wgsl) and ENCODE_SRGB (true when the target
// format is not an *Srgb format, so the exact sRGB curve is applied here).
// Needs color.wgsl and camera.wgsl.
#import color
#import camera
#import fullscreen

struct PostParams {
    // Vignetting strength, tan of the half field of view horizontally and vertically.
    vignette: f32,
    tan_half_fov_x: f32,
    tan_half_fov_y: f32,
    pad: f32,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var<uniform> post: PostParams;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    var c = textureLoad(hdr, vec2<i32>(frag.xy), 0).rgb;
    if post.vignette > 0.0 {
        let size = vec2<f32>(textureDimensions(hdr));
        let ndc = frag.xy / size * 2.0 - vec2<f32>(1.0);
        let t = ndc * vec2<f32>(post.tan_half_fov_x, post.tan_half_fov_y);
        c *= vignetting(dot(t, t), post.vignette);
    }
    var mapped = tonemap(TONEMAPPER, select(c, vec3<f32>(0.0), c != c));
    if ENCODE_SRGB {
        mapped = vec3<f32>(srgb_encode(mapped.r), srgb_encode(mapped.g), srgb_encode(mapped.b));
    }
    return vec4<f32>(mapped, 1.0);
}

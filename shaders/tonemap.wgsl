// Tone mapping pass: exposed HDR luminance → display colour.
// Header constants: TONEMAPPER (see color.wgsl) and ENCODE_SRGB (true when the target
// format is not an *Srgb format, so the exact sRGB curve is applied here).

@group(0) @binding(0) var hdr: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(frag.xy), 0).rgb;
    var mapped = tonemap(TONEMAPPER, select(c, vec3<f32>(0.0), c != c));
    if ENCODE_SRGB {
        mapped = vec3<f32>(srgb_encode(mapped.r), srgb_encode(mapped.g), srgb_encode(mapped.b));
    }
    return vec4<f32>(mapped, 1.0);
}

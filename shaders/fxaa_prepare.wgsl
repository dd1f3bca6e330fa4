// FXAA's first step (engine/src/render/antialiasing/fxaa.rs): the HDR image compressed
// into [0, 1) luminance (compress_hdr), so the filter blends what the display shows;
// coverage (a) is kept. Non-finite colour becomes black.
#import color
#import antialiasing
#import fullscreen

@group(0) @binding(0) var hdr: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(frag.xy), 0);
    return select(vec4<f32>(0.0), vec4<f32>(compress_hdr(c.rgb), c.a), is_finite4(c));
}

// Copies a texture of the frame's size into a target of another format, texel for texel.
#import fullscreen

@group(0) @binding(0) var source: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(source, vec2<i32>(frag.xy), 0);
}

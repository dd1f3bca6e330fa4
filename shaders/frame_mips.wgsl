// One level of the transmission source's mip chain
// (engine/src/render/transparent/transmission_source.rs): each texel is the mean of the
// 2 × 2 texels below it, one bilinear tap at their shared corner (for an odd size below,
// the tap covers the nearest 2 × 2).
#import fullscreen

@group(0) @binding(0) var below: texture_2d<f32>;
@group(0) @binding(1) var bilinear: sampler;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let size = max(vec2<f32>(textureDimensions(below)) * 0.5, vec2<f32>(1.0));
    return textureSampleLevel(below, bilinear, frag.xy / floor(size), 0.0);
}

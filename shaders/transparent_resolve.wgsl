// The transparent pass's weighted-OIT resolve (engine/src/render/transparent/weighted.rs):
// per pixel, the accumulation and revealage become one premultiplied layer (oit_resolve),
// which the pipeline composites over the HDR target with "over". A pixel no blended
// fragment reached (revealage 1) is discarded and keeps the frame.
#import transparency
#import fullscreen

@group(0) @binding(0) var oit_accum: texture_2d<f32>;
@group(0) @binding(1) var oit_reveal: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let reveal = textureLoad(oit_reveal, p, 0).r;
    if reveal >= 1.0 {
        discard;
    }
    return oit_resolve(textureLoad(oit_accum, p, 0), reveal);
}

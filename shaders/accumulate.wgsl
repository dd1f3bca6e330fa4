// Accumulation: the running mean of jittered renders (engine/src/render/antialias/
// accumulate.rs). Writes the new mean into an f32 target; copy.wgsl puts it back into
// the HDR target.
#import color
#import antialiasing
#import fullscreen

struct AccumulateParams {
    // 1 / (index of this render + 1): 1 starts a new mean.
    weight: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}

@group(0) @binding(0) var hdr: texture_2d<f32>;
@group(0) @binding(1) var previous: texture_2d<f32>;
@group(0) @binding(2) var<uniform> params: AccumulateParams;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    return running_mean(textureLoad(previous, p, 0), textureLoad(hdr, p, 0), params.weight);
}

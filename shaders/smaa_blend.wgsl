// SMAA's blend (engine/src/render/antialias/smaa.rs; Jimenez et al. 2012, §3.3): each
// pixel gathers the coverages of its four edges (its own top and left from its weights,
// its bottom and right from the neighbours' below and to the right), and mixes in the
// neighbours' linear colours (the mean a pixel filter takes) along the axis with the
// larger coverage, into the HDR target; pixels no edge reaches are discarded and keep it.
#import fullscreen

@group(0) @binding(0) var prepared: texture_2d<f32>;
@group(0) @binding(1) var weights: texture_2d<f32>;

fn weights_at(q: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(weights));
    if any(q < vec2<i32>(0)) || any(q >= size) {
        return vec4<f32>(0.0);
    }
    return textureLoad(weights, q, 0);
}

fn colour_at(q: vec2<i32>) -> vec3<f32> {
    let last = vec2<i32>(textureDimensions(prepared)) - vec2<i32>(1);
    return textureLoad(prepared, clamp(q, vec2<i32>(0), last), 0).rgb;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let own = weights_at(p);
    // How much of the pixel each neighbour's colour covers: above, below, left, right.
    let vertical = vec2<f32>(own.x, weights_at(p + vec2<i32>(0, 1)).y);
    let horizontal = vec2<f32>(own.z, weights_at(p + vec2<i32>(1, 0)).w);
    let strongest_v = max(vertical.x, vertical.y);
    let strongest_h = max(horizontal.x, horizontal.y);
    if max(strongest_v, strongest_h) <= 0.0 {
        discard;
    }
    let c = colour_at(p);
    var mixed: vec3<f32>;
    if strongest_h > strongest_v {
        mixed = c + horizontal.x * (colour_at(p + vec2<i32>(-1, 0)) - c)
            + horizontal.y * (colour_at(p + vec2<i32>(1, 0)) - c);
    } else {
        mixed = c + vertical.x * (colour_at(p + vec2<i32>(0, -1)) - c)
            + vertical.y * (colour_at(p + vec2<i32>(0, 1)) - c);
    }
    return vec4<f32>(mixed, 1.0);
}

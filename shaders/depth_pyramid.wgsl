// The depth pyramid (engine/src/render/indirect/depth_pyramid.rs): level 0 is the depth
// buffer, each level above holds, per texel, the largest depth (reversed Z: the nearest
// surface) of the texels it covers in the level below, so a ray that stays in front of
// a level-k texel's value passes in front of everything under it.
//
// fs_copy reads the depth buffer; fs_reduce reads the level below (its only mip).
#import fullscreen

@group(0) @binding(0) var source: texture_2d<f32>;

@fragment
fn fs_copy(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureLoad(source, vec2<i32>(frag.xy), 0).r, 0.0, 0.0, 0.0);
}

// The texels (2x, 2y) to (2x + 1, 2y + 1) of the level below, and its last row and column
// too where that level's size is odd and this texel is the last one, so nothing is lost.
@fragment
fn fs_reduce(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let below = vec2<i32>(textureDimensions(source));
    let base = vec2<i32>(frag.xy) * 2;
    let extra = select(vec2<i32>(1), vec2<i32>(2), ((below & vec2<i32>(1)) == vec2<i32>(1)) & (base + vec2<i32>(3) > below));
    var nearest = 0.0;
    for (var dy = 0; dy <= extra.y; dy++) {
        for (var dx = 0; dx <= extra.x; dx++) {
            let q = min(base + vec2<i32>(dx, dy), below - vec2<i32>(1));
            nearest = max(nearest, textureLoad(source, q, 0).r);
        }
    }
    return vec4<f32>(nearest, 0.0, 0.0, 0.0);
}

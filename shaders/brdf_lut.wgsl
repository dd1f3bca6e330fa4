// The split-sum BRDF table: texel (i, j) of an N×N Rg16Float target holds (A, B) of
// dfg_integrate for n·v = (i + 0.5)/N and perceptual roughness (j + 0.5)/N, so that a
// bilinear lookup at (n·v, r) is exact at texel centres. Needs common, brdf, ibl.
// Header constants LUT_SIZE and LUT_SAMPLES.
#import common
#import brdf
#import ibl
#import fullscreen

@fragment
fn fs_brdf_lut(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<f32>(f32(LUT_SIZE));
    let uv = frag.xy / size;
    return vec4<f32>(dfg_integrate(uv.x, uv.y, LUT_SAMPLES), 0.0, 1.0);
}

// TAA's last step (engine/src/render/antialias/resolve.rs): the new history copied into
// the HDR target, sharpened when asked (--taa-sharpen): contrast-adaptive sharpening
// (Lottes 2019, "FidelityFX Contrast Adaptive Sharpening") of the compressed colour over
// the centre and its four neighbours (cas_weight, cas_apply), expanded back. The history
// itself stays unsharpened, so sharpening never feeds back into later frames.
#import color
#import antialiasing
#import fullscreen

struct ResolveParams {
    // x: sharpening strength, 0 (an exact copy) to 1.
    settings: vec4<f32>,
}

@group(0) @binding(0) var history: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: ResolveParams;

fn compressed_at(p: vec2<i32>) -> vec3<f32> {
    let last = vec2<i32>(textureDimensions(history)) - vec2<i32>(1);
    return compress_hdr(textureLoad(history, clamp(p, vec2<i32>(0), last), 0).rgb);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let centre = textureLoad(history, p, 0);
    if params.settings.x <= 0.0 {
        return centre;
    }
    let c = compress_hdr(centre.rgb);
    let n = compressed_at(p + vec2<i32>(0, -1));
    let s = compressed_at(p + vec2<i32>(0, 1));
    let w = compressed_at(p + vec2<i32>(-1, 0));
    let e = compressed_at(p + vec2<i32>(1, 0));
    let lo = min(c, min(min(n, s), min(w, e)));
    let hi = max(c, max(max(n, s), max(w, e)));
    let cap = max(max(luminance(c), luminance(n)), max(max(luminance(s), luminance(w)), luminance(e)));
    let weight = cas_weight(lo, hi, params.settings.x);
    let sharpened = cas_apply(c, n + s + w + e, weight, cap);
    return vec4<f32>(expand_hdr(sharpened), centre.a);
}

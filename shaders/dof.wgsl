// Depth of field (docs/src/formulas.md#thin-lens-depth-of-field): thin-lens circle of confusion, a gather blur at half
// resolution with separate far and near fields, composited at full resolution.
//   fs_dof_prepare   (half res): colour (2×2 average) and signed CoC radius (half-res px)
//   fs_dof_tiles     (1/16 res): per 8×8 tile of half-res pixels, the largest near-field
//                    CoC radius of any pixel that can reach the tile (the near field's
//                    gather radius; Jimenez 2014, "Next Generation Post Processing in
//                    Call of Duty: Advanced Warfare")
//   fs_dof_blur      (half res): rings over the larger of the pixel's own far CoC and its
//                    tile's near CoC (nothing to gather → the pixel as is); far field (only samples inside the pixel's own CoC that
//                    themselves reach it: in-focus pixels stay sharp, sharp foreground does
//                    not smear into the blurred background) and near field (every
//                    foreground sample whose CoC covers the pixel, weighted by 1/area:
//                    foreground blur spills over in-focus objects), with coverage alpha
//   fs_dof_composite (full res): sharp → far layer by the pixel's |CoC| (for a foreground
//                    pixel, what shows around it), then the near field over it by its
//                    coverage.
// Needs common, camera, bindings, fullscreen.
#import common
#import camera
#import bindings
#import fullscreen

struct DofParams {
    focus_m: f32,
    focal_length_m: f32,
    aperture_diameter_m: f32,
    // Full-resolution pixels per metre on the sensor.
    pixels_per_m: f32,
    // Largest CoC radius (full-resolution pixels).
    max_radius_px: f32,
    rings: u32,
    pad0: f32,
    pad1: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> dof: DofParams;
@group(0) @binding(2) var full_color: texture_2d<f32>;
@group(0) @binding(3) var full_depth: texture_2d<f32>;
@group(0) @binding(4) var half_input: texture_2d<f32>;
@group(0) @binding(5) var far_field: texture_2d<f32>;
@group(0) @binding(6) var near_field: texture_2d<f32>;
@group(0) @binding(7) var linear_sampler: sampler;
@group(0) @binding(8) var near_tiles: texture_2d<f32>;

// Half-resolution pixels per side of a near-field tile.
const TILE: i32 = 8;

// Signed CoC radius in full-resolution pixels of the full-res pixel `p` (depth from the
// G-buffer; the background is at infinity), clamped to the largest radius.
fn coc_radius(p: vec2<i32>) -> f32 {
    let depth = textureLoad(full_depth, p, 0).r;
    var z = 1e9;
    if depth > 0.0 {
        let ndc = vec2<f32>((f32(p.x) + 0.5) * view.viewport.z * 2.0 - 1.0, 1.0 - (f32(p.y) + 0.5) * view.viewport.w * 2.0);
        let w = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
        z = dot(w.xyz / w.w - view.position_exposure.xyz, view.forward.xyz);
    }
    let c = circle_of_confusion(z, dof.focus_m, dof.focal_length_m, dof.aperture_diameter_m) * dof.pixels_per_m * 0.5;
    return clamp(c, -dof.max_radius_px, dof.max_radius_px);
}

@fragment
fn fs_dof_prepare(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let full = vec2<i32>(textureDimensions(full_color));
    let base = vec2<i32>(frag.xy) * 2;
    var color = vec3<f32>(0.0);
    var nearest = 1e9;
    var least = 1e9;
    for (var k = 0; k < 4; k++) {
        let p = min(base + vec2<i32>(k & 1, k >> 1), full - vec2<i32>(1));
        color += textureLoad(full_color, p, 0).rgb;
        let c = coc_radius(p);
        nearest = min(nearest, c);
        if abs(c) < abs(least) {
            least = c;
        }
    }
    // A foreground texel in the block makes it foreground (its blur must spread); else the
    // least blurred texel keeps in-focus edges sharp.
    let coc = select(least, nearest, nearest < -0.5);
    return vec4<f32>(color * 0.25, coc * 0.5);
}

struct BlurOutput {
    @location(0) far: vec4<f32>,
    @location(1) near: vec4<f32>,
}

@fragment
fn fs_dof_tiles(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(half_input));
    let reach = i32(ceil(dof.max_radius_px * 0.5));
    let lo = max(vec2<i32>(frag.xy) * TILE - vec2<i32>(reach), vec2<i32>(0));
    let hi = min(vec2<i32>(frag.xy) * TILE + vec2<i32>(TILE + reach), size);
    var near = 0.0;
    for (var y = lo.y; y < hi.y; y++) {
        for (var x = lo.x; x < hi.x; x++) {
            near = max(near, -textureLoad(half_input, vec2<i32>(x, y), 0).a);
        }
    }
    return vec4<f32>(near, 0.0, 0.0, 1.0);
}

@fragment
fn fs_dof_blur(@builtin(position) frag: vec4<f32>) -> BlurOutput {
    let size = vec2<i32>(textureDimensions(half_input));
    let p = vec2<i32>(frag.xy);
    let center = textureLoad(half_input, p, 0);
    let radius = max(textureLoad(near_tiles, p / TILE, 0).r, center.a);
    var out: BlurOutput;
    if radius < 0.5 {
        out.far = vec4<f32>(center.rgb, 1.0);
        out.near = vec4<f32>(0.0);
        return out;
    }
    let rings = max(dof.rings, 1u);
    let samples = f32(1u + 4u * rings * (rings + 1u));
    // Each sample stands for this much area (half-res pixels²).
    let sample_area = PI * radius * radius / samples;
    // Behind a foreground pixel the far layer is what shows around it (non-foreground
    // samples within its own CoC), so that its blurred edge turns translucent.
    let center_near = center.a < -0.5;
    var far_sum = select(center.rgb, vec3<f32>(0.0), center_near);
    var far_weight = select(1.0, 0.0, center_near);
    var near_sum = vec3<f32>(0.0);
    var near_weight = 0.0;
    var coverage = 0.0;
    if center.a < -0.5 {
        let w = 1.0 / max(center.a * center.a, 1.0);
        near_sum = center.rgb * w;
        near_weight = w;
        coverage = sample_area * w / PI;
    }
    for (var k = 1u; k <= rings; k++) {
        let r = radius * f32(k) / f32(rings);
        let n = 8u * k;
        for (var j = 0u; j < n; j++) {
            let angle = 6.28318531 * (f32(j) + 0.5 * f32(k & 1u)) / f32(n);
            let q = clamp(p + vec2<i32>(round(vec2<f32>(cos(angle), sin(angle)) * r)), vec2<i32>(0), size - vec2<i32>(1));
            let s = textureLoad(half_input, q, 0);
            if center_near {
                if s.a >= -0.5 && r <= -center.a + 0.5 {
                    far_sum += s.rgb;
                    far_weight += 1.0;
                }
            } else if s.a > 0.0 && r <= center.a + 0.5 && r <= s.a + 0.5 {
                far_sum += s.rgb;
                far_weight += 1.0;
            }
            if s.a < -0.5 && r <= -s.a + 0.5 {
                let w = 1.0 / max(s.a * s.a, 1.0);
                near_sum += s.rgb * w;
                near_weight += w;
                coverage += sample_area * w / PI;
            }
        }
    }
    out.far = vec4<f32>(select(center.rgb, far_sum / far_weight, far_weight > 0.0), 1.0);
    out.near = vec4<f32>(near_sum / max(near_weight, 1e-6), clamp(coverage, 0.0, 1.0));
    return out;
}

@fragment
fn fs_dof_composite(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let sharp = textureLoad(full_color, p, 0);
    let uv = frag.xy * view.viewport.zw;
    let far = textureSampleLevel(far_field, linear_sampler, uv, 0.0).rgb;
    let near = textureSampleLevel(near_field, linear_sampler, uv, 0.0);
    let t_far = clamp(abs(coc_radius(p)) - 0.5, 0.0, 1.0);
    var c = mix(sharp.rgb, far, t_far);
    c = mix(c, near.rgb, near.a);
    return vec4<f32>(c, sharp.a);
}

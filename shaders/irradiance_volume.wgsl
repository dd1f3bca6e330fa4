// Irradiance-volume formulas, the same as engine/src/shading/irradiance_volume.rs (same names):
// DDGI's probe weights (Majercik et al. 2019) and the cube and octahedral bookkeeping of
// probe captures.
#import encoding

const OCT_SIDE: u32 = 8u;
const IRRADIANCE_SIDE: u32 = 6u;
const IRRADIANCE_TEXELS: u32 = IRRADIANCE_SIDE * IRRADIANCE_SIDE;
const MOMENT_SHARPNESS: f32 = 50.0;
const BACKFACE_FLOOR: f32 = 0.2;
const SELF_SHADOW_BIAS: f32 = 0.3;

// ((1 + n·d)/2)² + BACKFACE_FLOOR, for a probe in unit direction `to_probe`.
fn backface_weight(to_probe: vec3<f32>, n: vec3<f32>) -> f32 {
    let t = (1.0 + dot(to_probe, n)) * 0.5;
    return t * t + BACKFACE_FLOOR;
}

// Chebyshev's bound on the visibility of a point at `distance` (m) from a probe whose
// distances in that direction have mean `mean` (m) and mean square `mean_sq` (m²), cubed.
fn chebyshev_visibility(mean: f32, mean_sq: f32, distance: f32) -> f32 {
    if !(distance > mean) {
        return 1.0;
    }
    let variance = max(abs(mean_sq - mean * mean), 1e-6);
    let d = distance - mean;
    let p = variance / (variance + d * d);
    return max(p * p * p, 0.0);
}

// Solid angle (sr) of a cube-face texel centred at face coordinates xy in [−1, 1]².
fn cube_texel_solid_angle(xy: vec2<f32>, size: f32) -> f32 {
    let texel = 2.0 / size;
    let r2 = 1.0 + xy.x * xy.x + xy.y * xy.y;
    return texel * texel / (r2 * sqrt(r2));
}

// Weight of a distance captured along `ray` in the moment texel of direction `texel`.
fn moment_weight(texel: vec3<f32>, ray: vec3<f32>) -> f32 {
    return pow(max(dot(texel, ray), 0.0), MOMENT_SHARPNESS);
}

// The normal term of the half-resolution volume's upsample: the weight of a texel looked
// up at a pixel with normal `texel_n` for a pixel with normal `n`, max(0, n·n_t)⁸, as
// three squarings.
fn upsample_normal_weight(texel_n: vec3<f32>, n: vec3<f32>) -> f32 {
    let c = max(dot(texel_n, n), 0.0);
    let c2 = c * c;
    let c4 = c2 * c2;
    return c4 * c4;
}

// Cosine weight of radiance captured along unit `ray` in the irradiance of a surface with
// unit normal `normal`: max(0, normal·ray).
fn irradiance_weight(normal: vec3<f32>, ray: vec3<f32>) -> f32 {
    return max(dot(normal, ray), 0.0);
}

// The share of a volume's light at `p`: 1 inside the box low..high (m), falling linearly
// with the distance outside it, in probe spacings per axis, to 0 one spacing away.
fn volume_fade(p: vec3<f32>, low: vec3<f32>, high: vec3<f32>, spacing: vec3<f32>) -> f32 {
    let outside = max(max(low - p, p - high), vec3<f32>(0.0)) / spacing;
    return clamp(1.0 - length(outside), 0.0, 1.0);
}

// Atlas position (texels) at which a bilinear read of direction d reads the probe tile
// whose first texel is tile_origin: a side² octahedral map inside a one-texel border.
fn atlas_position(tile_origin: vec2<f32>, side: f32, d: vec3<f32>) -> vec2<f32> {
    return tile_origin + vec2<f32>(1.0) + (oct_encode(d) * 0.5 + vec2<f32>(0.5)) * side;
}

// The direction of the centre of texel (x, y) of a side² octahedral map.
fn oct_texel_direction(texel: vec2<u32>, side: u32) -> vec3<f32> {
    let uv = (vec2<f32>(texel) + vec2<f32>(0.5)) / f32(side);
    return oct_decode(uv * 2.0 - vec2<f32>(1.0));
}

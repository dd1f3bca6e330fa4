// The sheen layer (KHR_materials_sheen): the WGSL twins of engine/src/shading/sheen.rs, with the
// same names. f_sheen = colour · D_Charlie · V_Neubelt; L = L_sheen + (1 − max(colour) ·
// E_sheen(n·v, r)) · L_base. The albedo table E_sheen is bound by the layers pass
// (layers.wgsl), which looks it up.
#import common

// The smallest sheen perceptual roughness used (α = 0.0049).
const MIN_SHEEN_ROUGHNESS: f32 = 0.07;

// NaN: 1.
fn clamp_sheen_roughness(perceptual_roughness: f32) -> f32 {
    if !(perceptual_roughness == perceptual_roughness) {
        return 1.0;
    }
    return clamp(perceptual_roughness, MIN_SHEEN_ROUGHNESS, 1.0);
}

// Conty Estevez & Kulla 2017: (2 + 1/α) (1 − (n·h)²)^(1/(2α)) / (2π), α = r².
fn d_charlie(perceptual_roughness: f32, n_dot_h: f32) -> f32 {
    let r = clamp_sheen_roughness(perceptual_roughness);
    let inv_alpha = 1.0 / (r * r);
    let sin2 = max(1.0 - n_dot_h * n_dot_h, 0.0);
    return (2.0 + inv_alpha) * pow(sin2, 0.5 * inv_alpha) / (2.0 * PI);
}

// Neubelt & Pettineo 2013: 1 / (4 (n·l + n·v − (n·l)(n·v))), clamped to 0..1.
fn v_neubelt(n_dot_v: f32, n_dot_l: f32) -> f32 {
    let v = clamp(n_dot_v, 0.0, 1.0);
    let l = clamp(n_dot_l, 0.0, 1.0);
    return min(1.0 / max(4.0 * (l + v - l * v), 1e-6), 1.0);
}

fn sheen_brdf(color: vec3<f32>, perceptual_roughness: f32, n_dot_v: f32, n_dot_l: f32, n_dot_h: f32) -> vec3<f32> {
    if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
        return vec3<f32>(0.0);
    }
    return color * (d_charlie(perceptual_roughness, n_dot_h) * v_neubelt(n_dot_v, n_dot_l));
}

// 1 − max(colour) · albedo (NaN colour: 1).
fn sheen_base_weight(color: vec3<f32>, albedo: f32) -> f32 {
    let m = max(color.r, max(color.g, color.b));
    var c = clamp(m, 0.0, 1.0);
    if !(m == m) {
        c = 0.0;
    }
    return 1.0 - c * clamp(albedo, 0.0, 1.0);
}

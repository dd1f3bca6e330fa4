// The Cook-Torrance BRDF, term for term the same as engine/src/shading/brdf.rs (same names).
// Units: BRDF values in 1/sr; cosines dimensionless. Formulas and sources: see brdf.rs
// and docs/src/formulas.md#the-brdf, guards in #numerical-guards.
#import common

const MIN_PERCEPTUAL_ROUGHNESS: f32 = 0.045;
const MIN_N_DOT_V: f32 = 1e-4;

const VISIBILITY_SCHLICK_GGX: u32 = 0u;
const VISIBILITY_SMITH_GGX_CORRELATED: u32 = 1u;
const VISIBILITY_SMITH_GGX_CORRELATED_FAST: u32 = 2u;

struct Surface {
    base_color: vec3<f32>,
    metallic: f32,
    perceptual_roughness: f32,
    specular_level: f32,
}

fn clamp_perceptual_roughness(perceptual_roughness: f32) -> f32 {
    // NaN fails both comparisons of clamp on some drivers; test it explicitly.
    if !(perceptual_roughness == perceptual_roughness) {
        return 1.0;
    }
    return clamp(perceptual_roughness, MIN_PERCEPTUAL_ROUGHNESS, 1.0);
}

fn perceptual_roughness_to_alpha(perceptual_roughness: f32) -> f32 {
    let r = clamp_perceptual_roughness(perceptual_roughness);
    return r * r;
}

// Largest shortfall of a unit normal's length that 8-bit storage alone causes (√3/255).
const NORMAL_QUANTIZATION: f32 = 0.0068;

// Toksvig's variance of the normals averaged into one filtered normal-map texel
// (Toksvig 2005): σ² = (1 − |n̄|)/|n̄|, 0 within NORMAL_QUANTIZATION of unit length.
fn toksvig_variance(normal_length: f32) -> f32 {
    if !(normal_length == normal_length) {
        return 0.0;
    }
    return max(1.0 - normal_length - NORMAL_QUANTIZATION, 0.0) / max(normal_length, 1e-4);
}

// Geometric specular anti-aliasing, isotropic (Tokuyoshi & Kaplanyan 2019 in slope space,
// 2021 in projected space, eq. 14): α'² = min(α² + min(s |∂n|² + 2 σ²_Toksvig, κ), 1), with
// |∂n|² = |∂n/∂x|² + |∂n/∂y|² and s = c σ² the screen scale (c = 2 for 2019, 1 for 2021).
// The roughness comes back exactly as given where nothing widens.
fn specular_aa_roughness(perceptual_roughness: f32, normal_variation: f32, normal_length: f32,
                         screen_scale: f32, threshold: f32) -> f32 {
    let alpha = perceptual_roughness_to_alpha(perceptual_roughness);
    let alpha2 = alpha * alpha;
    let kernel = max(min(screen_scale * normal_variation + 2.0 * toksvig_variance(normal_length), threshold), 0.0);
    let widened = min(alpha2 + kernel, 1.0);
    if !(widened == widened) || widened <= alpha2 {
        return perceptual_roughness;
    }
    return sqrt(sqrt(widened));
}

// GGX / Trowbridge-Reitz, D = α² / (π ((n·h)²(α² − 1) + 1)²) (Walter et al. 2007),
// with the denominator as (n·h)² α² + |n × h|² to avoid cancellation (Filament).
fn d_ggx(alpha: f32, n_dot_h: f32, n_cross_h_length_squared: f32) -> f32 {
    let a = clamp(n_dot_h, 0.0, 1.0) * alpha;
    let k = alpha / (max(n_cross_h_length_squared, 0.0) + a * a);
    return k * k / PI;
}

// k_direct = (r + 1)² / 8 (Karis 2013).
fn k_direct(perceptual_roughness: f32) -> f32 {
    let r = clamp_perceptual_roughness(perceptual_roughness);
    return (r + 1.0) * (r + 1.0) / 8.0;
}

// k_IBL = r² / 2 (Karis 2013).
fn k_ibl(perceptual_roughness: f32) -> f32 {
    return perceptual_roughness_to_alpha(perceptual_roughness) / 2.0;
}

// G1(x) = x / (x (1 − k) + k).
fn g1_schlick_ggx(n_dot_x: f32, k: f32) -> f32 {
    let x = max(n_dot_x, 0.0);
    return x / (x * (1.0 - k) + k);
}

fn g_smith_schlick_ggx(n_dot_v: f32, n_dot_l: f32, k: f32) -> f32 {
    return g1_schlick_ggx(n_dot_v, k) * g1_schlick_ggx(n_dot_l, k);
}

// V = G / (4 (n·v)(n·l)) with the cosines cancelled.
fn v_schlick_ggx(n_dot_v: f32, n_dot_l: f32, k: f32) -> f32 {
    let v = max(n_dot_v, 0.0) * (1.0 - k) + k;
    let l = max(n_dot_l, 0.0) * (1.0 - k) + k;
    return 0.25 / (v * l);
}

// Height-correlated Smith GGX (Heitz 2014).
fn v_smith_ggx_correlated(n_dot_v: f32, n_dot_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let nv = max(n_dot_v, 0.0);
    let nl = max(n_dot_l, 0.0);
    let ggx_v = nl * sqrt(nv * nv * (1.0 - a2) + a2);
    let ggx_l = nv * sqrt(nl * nl * (1.0 - a2) + a2);
    return 0.5 / max(ggx_v + ggx_l, 1e-8);
}

// Hammon 2017: V = 0.5 / mix(2 (n·l)(n·v), n·l + n·v, α).
fn v_smith_ggx_correlated_fast(n_dot_v: f32, n_dot_l: f32, alpha: f32) -> f32 {
    let nv = max(n_dot_v, 0.0);
    let nl = max(n_dot_l, 0.0);
    let denom = 2.0 * nl * nv + (nl + nv - 2.0 * nl * nv) * alpha;
    return 0.5 / max(denom, 1e-8);
}

fn visibility(model: u32, n_dot_v: f32, n_dot_l: f32, perceptual_roughness: f32) -> f32 {
    if model == VISIBILITY_SMITH_GGX_CORRELATED {
        return v_smith_ggx_correlated(n_dot_v, n_dot_l, perceptual_roughness_to_alpha(perceptual_roughness));
    }
    if model == VISIBILITY_SMITH_GGX_CORRELATED_FAST {
        return v_smith_ggx_correlated_fast(n_dot_v, n_dot_l, perceptual_roughness_to_alpha(perceptual_roughness));
    }
    return v_schlick_ggx(n_dot_v, n_dot_l, k_direct(perceptual_roughness));
}

// (1 − u)⁵ with u clamped to [0, 1], power by multiplication (docs/src/formulas.md#numerical-guards).
fn pow5_one_minus(u: f32) -> f32 {
    let x = 1.0 - clamp(u, 0.0, 1.0);
    let x2 = x * x;
    return x2 * x2 * x;
}

// Fresnel-Schlick with the h·v cosine (Schlick 1994).
fn f_schlick(f0: vec3<f32>, v_dot_h: f32) -> vec3<f32> {
    return f0 + (vec3<f32>(1.0) - f0) * pow5_one_minus(v_dot_h);
}

fn fd_lambert() -> f32 {
    return 1.0 / PI;
}

// F0 = 0.08 · specular level (0.5 → 0.04).
fn dielectric_f0(specular_level: f32) -> f32 {
    return 0.08 * clamp(specular_level, 0.0, 1.0);
}

fn compute_f0(base_color: vec3<f32>, metallic: f32, specular_level: f32) -> vec3<f32> {
    let m = clamp(metallic, 0.0, 1.0);
    return vec3<f32>(dielectric_f0(specular_level)) * (1.0 - m) + base_color * m;
}

// compute_f0 with the dielectric F0 tinted by `tint` (each channel clamped to 0..1, NaN:
// 1), KHR_materials_specular's colour: mix(0.08 · level · tint, base colour, metallic).
fn tinted_f0(base_color: vec3<f32>, metallic: f32, specular_level: f32, tint: vec3<f32>) -> vec3<f32> {
    let m = clamp(metallic, 0.0, 1.0);
    let t = select(clamp(tint, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(1.0), tint != tint);
    return t * (dielectric_f0(specular_level) * (1.0 - m)) + base_color * m;
}

// The two lobes of the BRDF (1/sr): kD c/π and D F V.
struct BrdfLobes {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

// f_r = kD c/π + D F V, kD = (1 − F)(1 − metallic), as two lobes. Zero below the horizon.
fn surface_brdf_lobes(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, surface: Surface, model: u32) -> BrdfLobes {
    var lobes: BrdfLobes;
    lobes.diffuse = vec3<f32>(0.0);
    lobes.specular = vec3<f32>(0.0);
    let n_dot_l = dot(n, l);
    if !(n_dot_l > 0.0) {
        return lobes;
    }
    let n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    let h = safe_normalize(v + l, n);
    let n_dot_h = clamp(dot(n, h), 0.0, 1.0);
    let v_dot_h = clamp(dot(v, h), 0.0, 1.0);

    let r = clamp_perceptual_roughness(surface.perceptual_roughness);
    let alpha = r * r;
    let metallic = clamp(surface.metallic, 0.0, 1.0);
    let f0 = compute_f0(surface.base_color, metallic, surface.specular_level);

    let n_cross_h = cross(n, h);
    let d = d_ggx(alpha, n_dot_h, dot(n_cross_h, n_cross_h));
    let f = f_schlick(f0, v_dot_h);
    let vis = visibility(model, n_dot_v, n_dot_l, r);

    let k_d = (vec3<f32>(1.0) - f) * (1.0 - metallic);
    lobes.diffuse = k_d * surface.base_color * fd_lambert();
    lobes.specular = f * (d * vis);
    return lobes;
}

// f_r = kD c/π + D F V (1/sr). Zero below the horizon.
fn surface_brdf(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, surface: Surface, model: u32) -> vec3<f32> {
    let lobes = surface_brdf_lobes(n, v, l, surface, model);
    return lobes.diffuse + lobes.specular;
}

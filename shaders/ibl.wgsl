// Image-based lighting, the same as engine/src/shading/ibl.rs (same names). Needs common.wgsl and
// brdf.wgsl.
#import common
#import brdf

fn equirect_uv(d_in: vec3<f32>) -> vec2<f32> {
    let d = safe_normalize(d_in, vec3<f32>(0.0, 0.0, -1.0));
    return vec2<f32>(0.5 + atan2(d.x, -d.z) / (2.0 * PI), acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// The direction of equirectangular texture coordinates uv (inverse of equirect_uv).
fn equirect_direction(uv: vec2<f32>) -> vec3<f32> {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

fn rotate_y(d: vec3<f32>, angle: f32) -> vec3<f32> {
    let s = sin(angle);
    let c = cos(angle);
    return vec3<f32>(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// The nine real SH basis functions of bands 0–2 at unit direction d (the order sh_irradiance
// expects).
fn sh_basis(d: vec3<f32>) -> array<f32, 9> {
    return array<f32, 9>(
        0.282095,
        0.488603 * d.y,
        0.488603 * d.z,
        0.488603 * d.x,
        1.092548 * d.x * d.y,
        1.092548 * d.y * d.z,
        0.315392 * (3.0 * d.z * d.z - 1.0),
        1.092548 * d.x * d.z,
        0.546274 * (d.x * d.x - d.y * d.y),
    );
}

// Irradiance from 9 SH coefficients (rgb in xyz), clamped ≥ 0 (Ramamoorthi & Hanrahan 2001).
fn sh_irradiance(sh: array<vec4<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    let a0 = PI;
    let a1 = 2.0 * PI / 3.0;
    let a2 = PI / 4.0;
    var e = sh[0].xyz * (a0 * 0.282095);
    e += sh[1].xyz * (a1 * 0.488603 * n.y);
    e += sh[2].xyz * (a1 * 0.488603 * n.z);
    e += sh[3].xyz * (a1 * 0.488603 * n.x);
    e += sh[4].xyz * (a2 * 1.092548 * n.x * n.y);
    e += sh[5].xyz * (a2 * 1.092548 * n.y * n.z);
    e += sh[6].xyz * (a2 * 0.315392 * (3.0 * n.z * n.z - 1.0));
    e += sh[7].xyz * (a2 * 1.092548 * n.x * n.z);
    e += sh[8].xyz * (a2 * 0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3<f32>(0.0));
}

fn radical_inverse(i: u32) -> f32 {
    return f32(reverseBits(i)) * 2.3283064e-10;
}

fn hammersley(i: u32, n: u32) -> vec2<f32> {
    return vec2<f32>(f32(i) / f32(max(n, 1u)), radical_inverse(i));
}

// A GGX-distributed half vector around +Z (Walter et al. 2007).
fn importance_sample_ggx(xi: vec2<f32>, alpha: f32) -> vec3<f32> {
    let a2 = alpha * alpha;
    let phi = 2.0 * PI * xi.x;
    let cos_theta = sqrt(max((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y), 0.0));
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    return vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}

// Split-sum BRDF integral (Karis 2013) with k_IBL = r²/2: returns (A, B) with
// ∫ f_r (n·l) = F0·A + B.
fn dfg_integrate(n_dot_v_in: f32, perceptual_roughness: f32, samples: u32) -> vec2<f32> {
    let n_dot_v = clamp(n_dot_v_in, 1e-4, 1.0);
    let v = vec3<f32>(sqrt(max(1.0 - n_dot_v * n_dot_v, 0.0)), 0.0, n_dot_v);
    let alpha = perceptual_roughness_to_alpha(perceptual_roughness);
    let k = k_ibl(clamp_perceptual_roughness(perceptual_roughness));
    var sum = vec2<f32>(0.0);
    for (var i = 0u; i < samples; i++) {
        let h = importance_sample_ggx(hammersley(i, samples), alpha);
        let v_dot_h = dot(v, h);
        let l = 2.0 * v_dot_h * h - v;
        let n_dot_l = l.z;
        if n_dot_l > 0.0 && v_dot_h > 0.0 {
            let g = g_smith_schlick_ggx(n_dot_v, n_dot_l, k);
            let g_vis = g * v_dot_h / (max(h.z, 1e-6) * n_dot_v);
            let fc = pow5_one_minus(v_dot_h);
            sum += vec2<f32>((1.0 - fc) * g_vis, fc * g_vis);
        }
    }
    return sum / f32(max(samples, 1u));
}

// Multiple-scattering energy compensation (Kulla & Conty 2017; Filament).
// A GGX visible normal for v in the local frame (z = normal), Heitz 2018.
fn sample_ggx_vndf(v: vec3<f32>, alpha: f32, xi: vec2<f32>) -> vec3<f32> {
    let vh = safe_normalize(vec3<f32>(alpha * v.x, alpha * v.y, v.z), vec3<f32>(0.0, 0.0, 1.0));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(len2), len2 > 0.0);
    let t2 = cross(vh, t1);
    let r = sqrt(xi.x);
    let phi = 2.0 * PI * xi.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    return safe_normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)), vec3<f32>(0.0, 0.0, 1.0));
}

fn energy_compensation(f0: vec3<f32>, dfg: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(1.0) + f0 * (1.0 / max(dfg.x + dfg.y, 1e-4) - 1.0);
}

// Specular occlusion from ambient occlusion (Lagarde & de Rousiers 2014).
fn specular_occlusion(n_dot_v: f32, ao: f32, perceptual_roughness: f32) -> f32 {
    let alpha = perceptual_roughness_to_alpha(perceptual_roughness);
    return clamp(pow(max(n_dot_v + ao, 0.0), exp2(-16.0 * alpha - 1.0)) - 1.0 + ao, 0.0, 1.0);
}

//! Image-based lighting on the CPU, the same as `shaders/ibl.wgsl` (same names): the
//! equirectangular mapping, spherical harmonics irradiance, GGX importance sampling, the
//! split-sum BRDF integral, energy compensation and specular occlusion.
//!
//! Units: radiance and irradiance carry the environment's units (cd/m² and lux once the
//! intensity is applied); the DFG terms are dimensionless.

use crate::shading::brdf::{
    PI, clamp_perceptual_roughness, g_smith_schlick_ggx, k_ibl, perceptual_roughness_to_alpha,
    pow5_one_minus,
};
use glam::{Vec2, Vec3};

/// Texture coordinates of a direction in an equirectangular image: the image centre
/// (u = 0.5) looks along −Z, u grows towards +X, the top row (v = 0) is +Y:
/// `u = 0.5 + atan2(x, −z) / 2π`, `v = acos(y) / π`.
pub fn equirect_uv(d: Vec3) -> Vec2 {
    let d = d.normalize_or(Vec3::NEG_Z);
    Vec2::new(
        0.5 + d.x.atan2(-d.z) / (2.0 * PI),
        d.y.clamp(-1.0, 1.0).acos() / PI,
    )
}

/// The direction of texture coordinates `uv` (inverse of [`equirect_uv`]).
pub fn equirect_direction(uv: Vec2) -> Vec3 {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    Vec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    )
}

/// Rotates `d` about +Y by `angle` radians (counter-clockwise seen from above).
pub fn rotate_y(d: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

/// The 9 real spherical harmonics of bands 0–2 at unit direction `d` (the normalised
/// basis of Ramamoorthi & Hanrahan 2001, "An Efficient Representation for Irradiance
/// Environment Maps").
pub fn sh_basis(d: Vec3) -> [f32; 9] {
    [
        0.282_095,
        0.488_603 * d.y,
        0.488_603 * d.z,
        0.488_603 * d.x,
        1.092_548 * d.x * d.y,
        1.092_548 * d.y * d.z,
        0.315_392 * (3.0 * d.z * d.z - 1.0),
        1.092_548 * d.x * d.z,
        0.546_274 * (d.x * d.x - d.y * d.y),
    ]
}

/// Projects an equirectangular image of `width` × `height` texels (linear RGB radiance,
/// row by row from the top, as the scene's `EquirectImage` holds them) onto the 9 SH
/// coefficients (RGB), integrating over the sphere with each texel's solid angle
/// `(2π/W)(π/H) sin θ` (f64 accumulation).
pub fn sh_project(width: u32, height: u32, texels: &[[f32; 3]]) -> [Vec3; 9] {
    let (w, h) = (width as usize, height as usize);
    let mut acc = [[0.0f64; 3]; 9];
    for j in 0..h {
        let v = (j as f32 + 0.5) / h as f32;
        let d_omega = (2.0 * std::f64::consts::PI / w as f64)
            * (std::f64::consts::PI / h as f64)
            * (std::f64::consts::PI * v as f64).sin();
        for i in 0..w {
            let d = equirect_direction(Vec2::new((i as f32 + 0.5) / w as f32, v));
            let basis = sh_basis(d);
            let Some(texel) = texels.get(j * w + i) else {
                continue;
            };
            for (k, b) in basis.iter().enumerate() {
                for c in 0..3 {
                    acc[k][c] += texel[c] as f64 * *b as f64 * d_omega;
                }
            }
        }
    }
    acc.map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
}

/// The SH coefficients of a uniform environment of radiance `radiance`.
pub fn sh_uniform(radiance: Vec3) -> [Vec3; 9] {
    let mut sh = [Vec3::ZERO; 9];
    sh[0] = radiance * (0.282_095 * 4.0 * PI);
    sh
}

/// Irradiance (the cosine-weighted integral of radiance) arriving at a surface with normal
/// `n`: `E(n) = Σ Â_l L_lm Y_lm(n)` with Â₀ = π, Â₁ = 2π/3, Â₂ = π/4 (Ramamoorthi &
/// Hanrahan 2001). Clamped to ≥ 0: the band-limited approximation rings slightly negative
/// opposite a very bright, small light (a sun).
pub fn sh_irradiance(sh: &[Vec3; 9], n: Vec3) -> Vec3 {
    let b = sh_basis(n);
    let a = [
        PI,
        2.0 * PI / 3.0,
        2.0 * PI / 3.0,
        2.0 * PI / 3.0,
        PI / 4.0,
        PI / 4.0,
        PI / 4.0,
        PI / 4.0,
        PI / 4.0,
    ];
    let mut e = Vec3::ZERO;
    for k in 0..9 {
        e += sh[k] * (a[k] * b[k]);
    }
    e.max(Vec3::ZERO)
}

/// Radical inverse in base 2: the second coordinate of the Hammersley point set.
pub fn radical_inverse(i: u32) -> f32 {
    i.reverse_bits() as f32 * 2.328_306_4e-10
}

/// Point `i` of an `n`-point Hammersley set in [0, 1)².
pub fn hammersley(i: u32, n: u32) -> Vec2 {
    Vec2::new(i as f32 / n.max(1) as f32, radical_inverse(i))
}

/// A GGX-distributed half vector around +Z for the uniform sample `xi` (pdf of h:
/// D(h)·(n·h)); `cos θ = √((1 − ξ₂)/(1 + (α² − 1) ξ₂))`, φ = 2π ξ₁ (Walter et al. 2007).
pub fn importance_sample_ggx(xi: Vec2, alpha: f32) -> Vec3 {
    let a2 = alpha * alpha;
    let phi = 2.0 * PI * xi.x;
    let cos_theta = ((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y)).max(0.0).sqrt();
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// The split-sum BRDF integral (Karis 2013) for view cosine `n_dot_v` and perceptual
/// roughness `r`, with Smith Schlick-GGX and `k_IBL = r²/2`:
/// `∫ f_r (n·l) dl = F0 · A + B`, where `A = ∫ (1 − Fc) G_vis`, `B = ∫ Fc G_vis`,
/// `Fc = (1 − v·h)⁵`, `G_vis = G (v·h) / ((n·h)(n·v))`; `samples` GGX-importance samples.
pub fn dfg_integrate(n_dot_v: f32, perceptual_roughness: f32, samples: u32) -> Vec2 {
    let n_dot_v = n_dot_v.clamp(1e-4, 1.0);
    let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
    let alpha = perceptual_roughness_to_alpha(perceptual_roughness);
    let k = k_ibl(clamp_perceptual_roughness(perceptual_roughness));
    let mut sum = Vec2::ZERO;
    for i in 0..samples {
        let h = importance_sample_ggx(hammersley(i, samples), alpha);
        let v_dot_h = v.dot(h);
        let l = 2.0 * v_dot_h * h - v;
        let n_dot_l = l.z;
        if n_dot_l > 0.0 && v_dot_h > 0.0 {
            let g = g_smith_schlick_ggx(n_dot_v, n_dot_l, k);
            let g_vis = g * v_dot_h / (h.z.max(1e-6) * n_dot_v);
            let fc = pow5_one_minus(v_dot_h);
            sum += Vec2::new((1.0 - fc) * g_vis, fc * g_vis);
        }
    }
    sum / samples.max(1) as f32
}

/// Multiple-scattering energy compensation (Kulla & Conty 2017, as in Filament): single
/// scattering GGX returns `E₁ = A + B` of the light for F0 = 1; scaling specular by
/// `1 + F0 (1/E₁ − 1)` restores the energy lost to multiple bounces between microfacets.
pub fn energy_compensation(f0: Vec3, dfg: Vec2) -> Vec3 {
    Vec3::ONE + f0 * (1.0 / (dfg.x + dfg.y).max(1e-4) - 1.0)
}

/// A GGX visible normal (Heitz 2018, "Sampling the GGX Distribution of Visible
/// Normals") for the view direction `v` in the local frame (z = normal) and width
/// `alpha`, from the uniform pair `xi`: normals are drawn in proportion to how much of
/// them `v` sees, D(h)·G₁(v)·max(v·h, 0)/(n·v), so reflected rays waste no samples on
/// normals facing away.
pub fn sample_ggx_vndf(v: Vec3, alpha: f32, xi: Vec2) -> Vec3 {
    sample_ggx_vndf_anisotropic(v, Vec2::splat(alpha), xi)
}

/// [`sample_ggx_vndf`] for an anisotropic lobe of widths `alphas` = (α_x, α_y) along the
/// frame's first two axes (Heitz 2018 stretches by each): the path tracer's sampler of
/// anisotropic GGX (`crate::shading::anisotropy`).
pub fn sample_ggx_vndf_anisotropic(v: Vec3, alphas: Vec2, xi: Vec2) -> Vec3 {
    let vh = Vec3::new(alphas.x * v.x, alphas.y * v.y, v.z).normalize_or(Vec3::Z);
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3::X
    };
    let t2 = vh.cross(t1);
    let r = xi.x.sqrt();
    let phi = 2.0 * std::f32::consts::PI * xi.y;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(alphas.x * nh.x, alphas.y * nh.y, nh.z.max(0.0)).normalize_or(Vec3::Z)
}

/// Specular occlusion from ambient occlusion `ao` (Lagarde & de Rousiers 2014, "Moving
/// Frostbite to PBR"): `saturate((n·v + ao)^(2^(−16α − 1)) − 1 + ao)` with α the GGX width.
pub fn specular_occlusion(n_dot_v: f32, ao: f32, perceptual_roughness: f32) -> f32 {
    let alpha = perceptual_roughness_to_alpha(perceptual_roughness);
    ((n_dot_v + ao).max(0.0).powf((-16.0 * alpha - 1.0).exp2()) - 1.0 + ao).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equirect_round_trip() {
        for d in [
            Vec3::X,
            -Vec3::X,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, 0.8, -0.5).normalize(),
            Vec3::new(-0.6, -0.7, 0.2).normalize(),
        ] {
            let back = equirect_direction(equirect_uv(d));
            assert!(back.abs_diff_eq(d, 1e-5), "{d} → {back}");
        }
        assert!(equirect_uv(-Vec3::Z).abs_diff_eq(Vec2::new(0.5, 0.5), 1e-6));
        assert!(equirect_uv(Vec3::Y).y.abs() < 1e-6);
        assert!(rotate_y(Vec3::X, PI / 2.0).abs_diff_eq(-Vec3::Z, 1e-6));
    }

    fn constant_sh(value: f32, w: u32, h: u32) -> [Vec3; 9] {
        sh_project(w, h, &vec![[value; 3]; (w * h) as usize])
    }

    #[test]
    fn irradiance_of_a_constant_environment_is_pi_times_it() {
        let sh = constant_sh(2.5, 128, 64);
        for n in [
            Vec3::Y,
            -Vec3::Y,
            Vec3::X,
            Vec3::new(0.2, -0.4, 0.9).normalize(),
        ] {
            let e = sh_irradiance(&sh, n);
            assert!(
                (e / PI - Vec3::splat(2.5)).abs().max_element() < 2.5e-3,
                "{n}: {e}"
            );
        }
        let sh = sh_uniform(Vec3::new(1.0, 2.0, 3.0));
        assert!(
            (sh_irradiance(&sh, Vec3::Z) / PI - Vec3::new(1.0, 2.0, 3.0))
                .abs()
                .max_element()
                < 1e-5
        );
    }

    #[test]
    fn irradiance_of_a_bright_upper_hemisphere() {
        // Radiance 1 above the horizon, 0 below: E(up) = π, E(down) = 0, E(side) = π/2.
        let (w, h) = (256u32, 128u32);
        let texels: Vec<[f32; 3]> = (0..h)
            .flat_map(|j| (0..w).map(move |_| if j < h / 2 { [1.0; 3] } else { [0.0; 3] }))
            .collect();
        let sh = sh_project(w, h, &texels);
        let e = |n| sh_irradiance(&sh, n).x / PI;
        // Band-limited to order 2 (≤ ~9 % error for a step, Ramamoorthi & Hanrahan).
        assert!((e(Vec3::Y) - 1.0).abs() < 0.1, "{}", e(Vec3::Y));
        assert!(e(-Vec3::Y).abs() < 0.1, "{}", e(-Vec3::Y));
        assert!((e(Vec3::X) - 0.5).abs() < 0.02, "{}", e(Vec3::X));
    }

    #[test]
    fn dfg_known_values() {
        // Smooth surface at normal incidence: A ≈ 1 (F = F0 at v·h = 1), B ≈ 0.
        let s = dfg_integrate(1.0, 0.0, 1024);
        assert!((s.x - 1.0).abs() < 0.01 && s.y < 0.01, "{s}");
        // Energy of single scattering falls with roughness at F0 = 1.
        let e = |r: f32| {
            let d = dfg_integrate(0.5, r, 4096);
            d.x + d.y
        };
        assert!(
            e(0.1) > e(0.5) && e(0.5) > e(1.0),
            "{} {} {}",
            e(0.1),
            e(0.5),
            e(1.0)
        );
        assert!(e(0.1) <= 1.001);
        // Against brute-force quadrature of ∫ D G / (4 n·v n·l) (n·l) dl over the hemisphere
        // (F = 1), for wide lobes where a grid is accurate.
        for (nv, r) in [(0.5f32, 1.0f32), (0.8, 0.7), (0.3, 0.6)] {
            let alpha = perceptual_roughness_to_alpha(r);
            let k = k_ibl(r);
            let v = Vec3::new((1.0 - nv * nv).sqrt(), 0.0, nv);
            let (nt, np) = (600, 1200);
            let mut sum = 0.0f64;
            for it in 0..nt {
                let theta = (it as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
                for ip in 0..np {
                    let phi = (ip as f64 + 0.5) / np as f64 * 2.0 * std::f64::consts::PI;
                    let l = Vec3::new(
                        (theta.sin() * phi.cos()) as f32,
                        (theta.sin() * phi.sin()) as f32,
                        theta.cos() as f32,
                    );
                    let h = (v + l).normalize();
                    let d = crate::shading::brdf::d_ggx(alpha, h.z, 1.0 - h.z * h.z);
                    let g = g_smith_schlick_ggx(nv, l.z, k);
                    let f = d * g / (4.0 * nv * l.z) * l.z;
                    sum += f as f64
                        * theta.sin()
                        * (std::f64::consts::FRAC_PI_2 / nt as f64)
                        * (2.0 * std::f64::consts::PI / np as f64);
                }
            }
            let is = dfg_integrate(nv, r, 8192);
            assert!(
                ((is.x + is.y) as f64 - sum).abs() < 0.01 * sum,
                "n·v {nv}, r {r}: {} vs quadrature {sum}",
                is.x + is.y
            );
        }
        // Energy compensation restores F0 = 1 to exactly 1.
        let d = dfg_integrate(0.3, 0.8, 2048);
        let comp = energy_compensation(Vec3::ONE, d);
        assert!(((d.x + d.y) * comp.x - 1.0).abs() < 1e-5);
        assert_eq!(energy_compensation(Vec3::ZERO, d), Vec3::ONE);
    }

    #[test]
    fn specular_occlusion_limits() {
        for r in [0.0f32, 0.5, 1.0] {
            for nv in [0.0f32, 0.5, 1.0] {
                assert_eq!(specular_occlusion(nv, 1.0, r), 1.0);
                assert_eq!(specular_occlusion(nv, 0.0, r), 0.0);
                let so = specular_occlusion(nv, 0.5, r);
                assert!((0.0..=1.0).contains(&so));
            }
        }
    }
}

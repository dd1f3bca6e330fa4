//! The sheen layer (glTF's `KHR_materials_sheen`): the CPU twins of `shaders/sheen.wgsl`,
//! with the same names, and the table of the sheen lobe's albedo
//! (docs/src/materials.md#sheen).
//!
//! Sheen is the back-scattering of fibres standing out of a surface: velvet, satin, dust,
//! peach skin. Its lobe is `f_sheen = sheen_colour · D_Charlie · V_Neubelt` (1/sr), with
//! - the "Charlie" distribution of Conty Estevez & Kulla 2017 ("Production Friendly
//!   Microfacet Sheen BRDF"): `D = (2 + 1/α) · sin(θ_h)^(1/α) / (2π)`, α = r², which
//!   puts its normals at grazing angles (a fuzzy rim);
//! - the visibility of Neubelt & Pettineo 2013 ("Crafting a Next-Gen Material Pipeline
//!   for The Order: 1886"): `V = 1 / (4 (n·l + n·v − (n·l)(n·v)))`;
//! - no Fresnel (the colour is the reflectance).
//!
//! The layer sits over the base as glTF and the same paper layer it, by albedo:
//! `L = L_sheen + (1 − max(sheen_colour) · E_sheen(n·v, r)) · L_base`, where E_sheen is the
//! directional albedo of D·V, tabulated by [`albedo_table`] (glTF's "albedo scaling").

use glam::Vec3;
use std::f32::consts::PI;
use std::sync::OnceLock;

/// Entries of the albedo table along n·v and along the sheen roughness.
pub const ALBEDO_TABLE_SIZE: usize = 32;

/// The smallest sheen perceptual roughness used (α = 0.0049): below it sin(θ_h)^(1/α)
/// underflows f32 everywhere but at grazing half vectors. glTF's default, 0, is clamped
/// to it.
pub const MIN_SHEEN_ROUGHNESS: f32 = 0.07;

/// The sheen roughness clamped into [`MIN_SHEEN_ROUGHNESS`]..1 (NaN: 1).
pub fn clamp_sheen_roughness(perceptual_roughness: f32) -> f32 {
    if perceptual_roughness.is_nan() {
        1.0
    } else {
        perceptual_roughness.clamp(MIN_SHEEN_ROUGHNESS, 1.0)
    }
}

/// The Charlie distribution (1/sr) at n·h for perceptual roughness r (clamped):
/// `(2 + 1/α) · (1 − (n·h)²)^(1/(2α)) / (2π)`, α = r².
pub fn d_charlie(perceptual_roughness: f32, n_dot_h: f32) -> f32 {
    let r = clamp_sheen_roughness(perceptual_roughness);
    let inv_alpha = 1.0 / (r * r);
    let sin2 = (1.0 - n_dot_h * n_dot_h).max(0.0);
    (2.0 + inv_alpha) * sin2.powf(0.5 * inv_alpha) / (2.0 * PI)
}

/// Neubelt's visibility (dimensionless, clamped to 0..1):
/// `1 / (4 (n·l + n·v − (n·l)(n·v)))`.
pub fn v_neubelt(n_dot_v: f32, n_dot_l: f32) -> f32 {
    let v = n_dot_v.clamp(0.0, 1.0);
    let l = n_dot_l.clamp(0.0, 1.0);
    (1.0 / (4.0 * (l + v - l * v)).max(1e-6)).min(1.0)
}

/// The sheen lobe of colour `color` (linear, 0..1) and perceptual roughness r
/// (1/sr): `color · D_Charlie · V_Neubelt`; zero below either horizon.
pub fn sheen_brdf(
    color: Vec3,
    perceptual_roughness: f32,
    n_dot_v: f32,
    n_dot_l: f32,
    n_dot_h: f32,
) -> Vec3 {
    if n_dot_l <= 0.0 || n_dot_v <= 0.0 {
        return Vec3::ZERO;
    }
    color * (d_charlie(perceptual_roughness, n_dot_h) * v_neubelt(n_dot_v, n_dot_l))
}

/// The fraction (0..1) of the base's light that leaves through a sheen of colour `color`
/// whose lobe's albedo (colour 1) is `albedo`: `1 − max(color) · albedo` (glTF's albedo
/// scaling).
pub fn sheen_base_weight(color: Vec3, albedo: f32) -> f32 {
    let c = color.max_element();
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    1.0 - c * albedo.clamp(0.0, 1.0)
}

/// The directional albedo E(n·v, r) = ∫ D·V (n·l) dω_l of the sheen lobe of colour 1, at
/// `ALBEDO_TABLE_SIZE`² points: entry `j · size + i` is n·v = i/(size − 1) (at least
/// 10⁻³), r = j/(size − 1) clamped by [`clamp_sheen_roughness`]. Integrated by the
/// midpoint rule over the hemisphere of l (128 × 128 cells in θ and φ), once per process.
pub fn albedo_table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let size = ALBEDO_TABLE_SIZE;
        let (steps_t, steps_p) = (128, 128);
        let mut out = Vec::with_capacity(size * size);
        for j in 0..size {
            let r = j as f32 / (size - 1) as f32;
            for i in 0..size {
                let n_dot_v = (i as f32 / (size - 1) as f32).max(1e-3);
                let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
                let mut sum = 0.0;
                for a in 0..steps_t {
                    let theta = (a as f32 + 0.5) / steps_t as f32 * 0.5 * PI;
                    let (sin_t, cos_t) = theta.sin_cos();
                    for b in 0..steps_p {
                        let phi = (b as f32 + 0.5) / steps_p as f32 * 2.0 * PI;
                        let l = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
                        let h = (v + l).normalize_or(Vec3::Z);
                        let f = sheen_brdf(Vec3::ONE, r, n_dot_v, cos_t, h.z).x;
                        // dω = sinθ dθ dφ.
                        sum += f * cos_t * sin_t;
                    }
                }
                let cell = (0.5 * PI / steps_t as f32) * (2.0 * PI / steps_p as f32);
                out.push((sum * cell).clamp(0.0, 1.0));
            }
        }
        out
    })
}

/// Bilinear lookup of `table` ([`albedo_table`]'s layout) at (n·v, r), both clamped to
/// 0..1 (NaN: 1).
pub fn sheen_albedo(table: &[f32], n_dot_v: f32, perceptual_roughness: f32) -> f32 {
    let size = ALBEDO_TABLE_SIZE;
    let scale = (size - 1) as f32;
    let x = if n_dot_v.is_nan() {
        1.0
    } else {
        n_dot_v.clamp(0.0, 1.0)
    } * scale;
    let y = if perceptual_roughness.is_nan() {
        1.0
    } else {
        perceptual_roughness.clamp(0.0, 1.0)
    } * scale;
    let (x0, y0) = ((x as usize).min(size - 1), (y as usize).min(size - 1));
    let (x1, y1) = ((x0 + 1).min(size - 1), (y0 + 1).min(size - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let at = |i: usize, j: usize| table.get(j * size + i).copied().unwrap_or(0.0);
    let row = |j: usize| at(x0, j) + (at(x1, j) - at(x0, j)) * fx;
    row(y0) + (row(y1) - row(y0)) * fy
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed-seed uniform generator in [0, 1) (xorshift32).
    fn uniforms(mut state: u32) -> impl FnMut() -> f32 {
        move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    #[test]
    fn the_charlie_distribution_is_normalised() {
        // ∫ D(h) (n·h) dω_h = 1 over the hemisphere, by the midpoint rule in θ.
        for r in [0.1f32, 0.3, 0.6, 1.0] {
            let steps = 20_000;
            let total: f32 = (0..steps)
                .map(|i| {
                    let theta = (i as f32 + 0.5) / steps as f32 * 0.5 * PI;
                    let d = d_charlie(r, theta.cos());
                    d * theta.cos() * theta.sin() * 2.0 * PI * (0.5 * PI / steps as f32)
                })
                .sum();
            assert!((total - 1.0).abs() < 2e-3, "r {r}: {total}");
        }
    }

    #[test]
    fn the_albedo_table_matches_a_monte_carlo_integration() {
        // E(n·v, r) at table points against 400 000 directions drawn uniformly over the
        // hemisphere (density 1/(2π)), independent of the table's quadrature: within 1 %
        // of the value (or 10⁻³).
        let table = albedo_table();
        let mut next = uniforms(0x9e37_79b9);
        for (i, j) in [(31usize, 3usize), (16, 9), (6, 15), (2, 31), (25, 22)] {
            let n_dot_v = (i as f32 / 31.0).max(1e-3);
            let r = j as f32 / 31.0;
            let v = Vec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
            let count = 400_000;
            let mut sum = 0.0f64;
            for _ in 0..count {
                let cos_t = next();
                let phi = 2.0 * PI * next();
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let l = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
                let h = (v + l).normalize_or(Vec3::Z);
                let f = sheen_brdf(Vec3::ONE, r, n_dot_v, cos_t, h.z).x;
                sum += f64::from(f * cos_t * 2.0 * PI);
            }
            let estimate = (sum / f64::from(count)) as f32;
            let tabled = table[j * ALBEDO_TABLE_SIZE + i];
            assert!(
                (estimate - tabled).abs() < (0.01 * tabled).max(1e-3),
                "n·v {n_dot_v}, r {r}: table {tabled}, Monte Carlo {estimate}"
            );
        }
    }

    #[test]
    fn the_lookup_returns_the_table_at_its_points_and_blends_between() {
        let table = albedo_table();
        let at = |i: usize, j: usize| table[j * ALBEDO_TABLE_SIZE + i];
        assert_eq!(sheen_albedo(table, 1.0, 1.0), at(31, 31));
        assert!((sheen_albedo(table, 10.0 / 31.0, 20.0 / 31.0) - at(10, 20)).abs() < 1e-5);
        let mid = sheen_albedo(table, 10.5 / 31.0, 20.0 / 31.0);
        assert!((mid - 0.5 * (at(10, 20) + at(11, 20))).abs() < 1e-5);
        assert!(sheen_albedo(table, f32::NAN, f32::NAN).is_finite());
    }
}

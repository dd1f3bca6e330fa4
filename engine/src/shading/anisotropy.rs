//! Anisotropic GGX (glTF's `KHR_materials_anisotropy`): the CPU twins of
//! `shaders/anisotropy.wgsl`, with the same names (docs/src/materials.md#anisotropy).
//!
//! Brushed metal, satin and hair reflect a highlight stretched across the grooves. The
//! base's specular lobe is then a GGX distribution with two widths: α_t along the
//! anisotropy direction t (in the tangent plane) and α_b along b = n × t. glTF sets them
//! from the material's perceptual roughness r (α = r²) and the anisotropy strength
//! s ∈ [0, 1]:
//!
//! `α_t = mix(α, 1, s²)`, `α_b = α`,
//!
//! so s = 0 is the isotropic lobe and s = 1 spreads the microfacets' slopes fully along t.
//! The distribution and the height-correlated Smith visibility are the anisotropic forms
//! of Heitz 2014 ("Understanding the Masking-Shadowing Function in Microfacet-Based
//! BRDFs", JCGT 3(2), eqs. 2 and 99), as Burley 2012 ("Physically Based Shading at
//! Disney") writes D:
//!
//! `D(h) = 1 / (π α_t α_b ((t·h / α_t)² + (b·h / α_b)² + (n·h)²)²)`,
//! `V(v, l) = 0.5 / ((n·l) |(α_t t·v, α_b b·v, n·v)| + (n·v) |(α_t t·l, α_b b·l, n·l)|)`.
//!
//! Image-based light reads the prefiltered environment along the reflection about a
//! bent normal (McAuley 2015, "Rendering the World of Far Cry 4", as the Khronos sample
//! renderer does): the normal is turned towards the plane that contains the anisotropic
//! bitangent and the viewer, by `1 − (1 − s (1 − r))⁴`.

use crate::shading::brdf::{
    BrdfLobes, PI, Surface, clamp_perceptual_roughness, fd_lambert, safe_normalize, tinted_f0,
};
use glam::{Vec2, Vec3};

/// The widths (α_t along the anisotropy direction, α_b across it) of a GGX lobe of
/// width `alpha` (α = r²) and anisotropy strength `strength` (0..1, clamped; NaN: 0).
pub fn anisotropic_alphas(alpha: f32, strength: f32) -> Vec2 {
    let s = if strength.is_nan() {
        0.0
    } else {
        strength.clamp(0.0, 1.0)
    };
    Vec2::new(alpha + (1.0 - alpha) * s * s, alpha)
}

/// The anisotropic GGX distribution (1/sr) for the half vector's coordinates
/// `(t·h, b·h, n·h)` in the lobe's frame and the widths `alphas` = (α_t, α_b), written
/// as Filament writes it, without dividing by the widths squared.
pub fn d_ggx_anisotropic(alphas: Vec2, h: Vec3) -> f32 {
    let a2 = alphas.x * alphas.y;
    let f = Vec3::new(alphas.y * h.x, alphas.x * h.y, a2 * h.z.clamp(0.0, 1.0));
    let w2 = a2 / f.length_squared().max(1e-30);
    a2 * w2 * w2 / PI
}

/// The height-correlated Smith visibility `G / (4 (n·v)(n·l))` of the anisotropic
/// lobe (dimensionless over sr) for the directions' coordinates `v` and `l` in the lobe's
/// frame (t, b, n) and the widths `alphas`.
pub fn v_smith_ggx_correlated_anisotropic(alphas: Vec2, v: Vec3, l: Vec3) -> f32 {
    let nv = v.z.max(0.0);
    let nl = l.z.max(0.0);
    let lambda_v = nl * Vec3::new(alphas.x * v.x, alphas.y * v.y, nv).length();
    let lambda_l = nv * Vec3::new(alphas.x * l.x, alphas.y * l.y, nl).length();
    0.5 / (lambda_v + lambda_l).max(1e-8)
}

/// The unit anisotropy direction in the tangent plane of the unit normal `n`: the
/// tangent `tangent` (made perpendicular to `n`) turned towards the bitangent
/// `b = n × t · handedness` by the angle whose cosine and sine are `rotation`.
pub fn anisotropy_direction(n: Vec3, tangent: Vec3, handedness: f32, rotation: Vec2) -> Vec3 {
    let fallback = safe_normalize(n.cross(Vec3::Y), Vec3::X);
    let t = safe_normalize(tangent - n * n.dot(tangent), fallback);
    let b = n.cross(t) * if handedness < 0.0 { -1.0 } else { 1.0 };
    safe_normalize(t * rotation.x + b * rotation.y, t)
}

/// The anisotropy at a texel of glTF's `anisotropyTexture` (`KHR_materials_anisotropy`):
/// the texel's red and green, each × 2 − 1, are a direction in tangent space (the tangent
/// itself where they are 0), turned by the material's rotation (cosine and sine
/// `rotation`); its blue scales the strength. Returns the strength and the cosine and sine
/// of the direction's angle from the tangent towards the bitangent.
pub fn textured_anisotropy(strength: f32, rotation: Vec2, texel: Vec3) -> (f32, Vec2) {
    let d = texel.truncate() * 2.0 - Vec2::ONE;
    let len = d.length();
    let d = if len > 1e-6 { d / len } else { Vec2::X };
    let turned = Vec2::new(
        rotation.x * d.x - rotation.y * d.y,
        rotation.y * d.x + rotation.x * d.y,
    );
    (strength * texel.z.clamp(0.0, 1.0), turned)
}

/// What a relit base adds to its metal/roughness surface (docs/src/materials.md#anisotropy):
/// what the G-buffer cannot hold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelitLobe {
    /// The anisotropy's strength, 0..1 (0: isotropic).
    pub strength: f32,
    /// The dielectric F0's tint, linear RGB 0..1 (1: untinted).
    pub tint: Vec3,
    /// The iridescent film ([`crate::shading::iridescence::iridescent_mix`]): factor (0: none),
    /// index of refraction, thickness (nm).
    pub film: Vec3,
}

impl Default for RelitLobe {
    /// Isotropic, untinted, no film.
    fn default() -> Self {
        RelitLobe {
            strength: 0.0,
            tint: Vec3::ONE,
            film: Vec3::ZERO,
        }
    }
}

/// The Fresnel reflectance of a relit base at the cosine `v_dot_h` (clamped to 0..1) of
/// the angle between the view and the half vector: its dielectric F0 tinted
/// ([`crate::shading::brdf::tinted_f0`]) and mixed with the iridescent film's
/// ([`crate::shading::iridescence::iridescent_mix`]). Shared by the reflected lobes and the diffuse
/// transmission ([`crate::shading::diffuse_transmission`]).
pub fn relit_fresnel(surface: &Surface, lobe: &RelitLobe, v_dot_h: f32) -> Vec3 {
    let f0 = tinted_f0(
        surface.base_color,
        surface.metallic.clamp(0.0, 1.0),
        surface.specular_level,
        lobe.tint,
    );
    crate::shading::iridescence::iridescent_mix(f0, v_dot_h.clamp(0.0, 1.0), lobe.film)
}

/// The Cook-Torrance lobes (1/sr) of a relit base (docs/src/materials.md#anisotropy):
/// the anisotropic GGX specular lobe along the unit direction `t` (perpendicular to `n`)
/// of the lobe's strength (0: isotropic GGX with the height-correlated Smith term), its
/// dielectric F0 tinted ([`crate::shading::brdf::tinted_f0`]) and its Fresnel mixed with the
/// iridescent film's ([`crate::shading::iridescence::iridescent_mix`]); the diffuse lobe of
/// [`crate::shading::brdf::surface_brdf_lobes`], and `D F V` with the anisotropic D and V. Both
/// zero for lights below the horizon.
pub fn relit_brdf_lobes(
    n: Vec3,
    v: Vec3,
    l: Vec3,
    t: Vec3,
    surface: &Surface,
    lobe: &RelitLobe,
) -> BrdfLobes {
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 || n_dot_l.is_nan() {
        return BrdfLobes::ZERO;
    }
    let b = n.cross(t);
    let h = safe_normalize(v + l, n);
    let local = |x: Vec3| Vec3::new(t.dot(x), b.dot(x), n.dot(x));
    let r = clamp_perceptual_roughness(surface.perceptual_roughness);
    let alphas = anisotropic_alphas(r * r, lobe.strength);
    let metallic = surface.metallic.clamp(0.0, 1.0);
    let f = relit_fresnel(surface, lobe, v.dot(h));
    let mut lv = local(v);
    lv.z = lv.z.max(crate::shading::brdf::MIN_N_DOT_V);
    let d = d_ggx_anisotropic(alphas, local(h));
    let vis = v_smith_ggx_correlated_anisotropic(alphas, lv, local(l));
    let k_d = (Vec3::ONE - f) * (1.0 - metallic);
    BrdfLobes {
        diffuse: k_d * surface.base_color * fd_lambert(),
        specular: f * (d * vis),
    }
}

/// The normal whose mirror reflection of `v` reads the prefiltered environment for an
/// anisotropic lobe along the unit direction `t` of strength `strength` and perceptual
/// roughness `perceptual_roughness`: `n` bent towards `(b × v) × b`, b = n × t, by
/// `1 − (1 − s (1 − r))⁴` (McAuley 2015). Unit length; `n` itself at strength 0.
pub fn anisotropic_bent_normal(
    n: Vec3,
    v: Vec3,
    t: Vec3,
    strength: f32,
    perceptual_roughness: f32,
) -> Vec3 {
    let s = if strength.is_nan() {
        0.0
    } else {
        strength.clamp(0.0, 1.0)
    };
    let r = clamp_perceptual_roughness(perceptual_roughness);
    let b = n.cross(t);
    let grain = b.cross(v).cross(b);
    let bent = safe_normalize(grain, n);
    let keep = (1.0 - s * (1.0 - r)).powi(4);
    safe_normalize(bent + (n - bent) * keep, n)
}

/// Entries of the anisotropic split-sum table ([`dfg_table`]) along n·v, the view's
/// azimuth from the anisotropy direction (0..π/2), the perceptual roughness and the
/// squared strength s².
pub const DFG_TABLE_DIMS: [usize; 4] = [16, 8, 16, 8];

/// GGX visible-normal samples per entry of [`dfg_table`].
pub const DFG_TABLE_SAMPLES: u32 = 512;

/// The azimuth (rad, 0..π/2) of the view direction `v` about the normal, measured from
/// the anisotropy direction `t` towards `b = n × t`, folded by the lobe's two mirror
/// symmetries (t → −t, b → −b): `atan2(|b·v|, |t·v|)`. 0 where v lies along n.
pub fn view_azimuth(t: Vec3, b: Vec3, v: Vec3) -> f32 {
    let (x, y) = (t.dot(v).abs(), b.dot(v).abs());
    if x + y > 0.0 { y.atan2(x) } else { 0.0 }
}

/// The split sum's BRDF integral (Karis 2013) of the anisotropic lobe
/// (docs/src/materials.md#anisotropy): `∫ f_r (n·l) dl = F0 · A + B` with Schlick's
/// Fresnel, `A = ∫ (1 − Fc) f₁ (n·l)`, `B = ∫ Fc f₁ (n·l)`, `Fc = (1 − v·h)⁵` and f₁ the
/// lobe with F = 1 (anisotropic D and height-correlated V), for the view at cosine
/// `n_dot_v` and azimuth `azimuth` (rad) from the anisotropy direction, perceptual
/// roughness `perceptual_roughness` and strength `strength`. Estimated with `samples`
/// visible normals (Heitz 2018, [`crate::shading::ibl::sample_ggx_vndf_anisotropic`]) on a
/// Hammersley set, each weighing `G₂(v, l) / G₁(v)`. A + B is the lobe's directional
/// albedo E₁, which the energy compensation divides by; unlike the isotropic lobe's it
/// depends on the azimuth: a white metal of roughness 0.5 and strength 1 seen at n·v 0.5
/// reflects 0.64 of the light along the direction and 0.50 across it.
pub fn anisotropic_dfg_integrate(
    n_dot_v: f32,
    azimuth: f32,
    perceptual_roughness: f32,
    strength: f32,
    samples: u32,
) -> Vec2 {
    let n_dot_v = n_dot_v.clamp(1e-3, 1.0);
    let sin_v = (1.0 - n_dot_v * n_dot_v).max(0.0).sqrt();
    let v = Vec3::new(sin_v * azimuth.cos(), sin_v * azimuth.sin(), n_dot_v);
    let r = clamp_perceptual_roughness(perceptual_roughness);
    let alphas = anisotropic_alphas(r * r, strength);
    // |(α_t v_t, α_b v_b, n·v)| = (n·v)(1 + 2Λ(v)) in the height-correlated form.
    let stretched = |d: Vec3| Vec3::new(alphas.x * d.x, alphas.y * d.y, d.z).length();
    let lambda_v = stretched(v);
    let mut sum = Vec2::ZERO;
    for i in 0..samples {
        let h = crate::shading::ibl::sample_ggx_vndf_anisotropic(
            v,
            alphas,
            crate::shading::ibl::hammersley(i, samples),
        );
        let v_dot_h = v.dot(h);
        let l = 2.0 * v_dot_h * h - v;
        if l.z > 0.0 && v_dot_h > 0.0 {
            // G₂/G₁(v) = (1 + Λ(v)) / (1 + Λ(v) + Λ(l)).
            let weight =
                l.z * (n_dot_v + lambda_v) / (l.z * lambda_v + n_dot_v * stretched(l)).max(1e-12);
            let fc = crate::shading::brdf::pow5_one_minus(v_dot_h);
            sum += Vec2::new((1.0 - fc) * weight, fc * weight);
        }
    }
    sum / samples.max(1) as f32
}

/// The table of [`anisotropic_dfg_integrate`] that [`anisotropic_dfg`] interpolates,
/// once per process: (A, B) pairs, entry `((k · R + j) · Z + a) · N + i` at
/// n·v = i/(N − 1) (at least 10⁻³), azimuth (π/2) a/(Z − 1), perceptual roughness
/// j/(R − 1) and strength √(k/(S − 1)), for [N, Z, R, S] = [`DFG_TABLE_DIMS`], with
/// [`DFG_TABLE_SAMPLES`] samples each. The GPU reads it from a storage buffer
/// (`shaders/anisotropic_dfg.wgsl`).
pub fn dfg_table() -> &'static [Vec2] {
    static TABLE: std::sync::OnceLock<Vec<Vec2>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let [n, z, r, s] = DFG_TABLE_DIMS;
        let at = |i: usize, size: usize| i as f32 / (size - 1) as f32;
        let mut out = Vec::with_capacity(n * z * r * s);
        for k in 0..s {
            for j in 0..r {
                for a in 0..z {
                    for i in 0..n {
                        out.push(anisotropic_dfg_integrate(
                            at(i, n),
                            at(a, z) * std::f32::consts::FRAC_PI_2,
                            at(j, r),
                            at(k, s).sqrt(),
                            DFG_TABLE_SAMPLES,
                        ));
                    }
                }
            }
        }
        out
    })
}

/// Quadrilinear lookup of `table` ([`dfg_table`]'s layout) at n·v, the view's azimuth
/// (rad, from [`view_azimuth`]), the perceptual roughness and the strength, each clamped
/// to its range (NaN: n·v 1, azimuth 0, roughness 1, strength 0): the anisotropic lobe's
/// (A, B) for the split sum and the energy compensation.
pub fn anisotropic_dfg(
    table: &[Vec2],
    n_dot_v: f32,
    azimuth: f32,
    perceptual_roughness: f32,
    strength: f32,
) -> Vec2 {
    let unit = |x: f32, nan: f32| if x.is_nan() { nan } else { x.clamp(0.0, 1.0) };
    let s = unit(strength, 0.0);
    let coords = [
        unit(n_dot_v, 1.0),
        unit(azimuth / std::f32::consts::FRAC_PI_2, 0.0),
        unit(perceptual_roughness, 1.0),
        s * s,
    ];
    let mut base = [0usize; 4];
    let mut frac = [0.0f32; 4];
    for d in 0..4 {
        let x = coords[d] * (DFG_TABLE_DIMS[d] - 1) as f32;
        base[d] = (x as usize).min(DFG_TABLE_DIMS[d] - 2);
        frac[d] = x - base[d] as f32;
    }
    let [n, z, r, _] = DFG_TABLE_DIMS;
    let mut sum = Vec2::ZERO;
    for corner in 0..16usize {
        let mut index = [0usize; 4];
        let mut weight = 1.0;
        for d in 0..4 {
            let up = (corner >> d) & 1;
            index[d] = base[d] + up;
            weight *= if up == 1 { frac[d] } else { 1.0 - frac[d] };
        }
        sum += weight * table[((index[3] * r + index[2]) * z + index[1]) * n + index[0]];
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::brdf::{
        VisibilityModel, d_ggx, surface_brdf_lobes, v_smith_ggx_correlated,
    };
    use std::f32::consts::FRAC_PI_2;

    #[test]
    fn a_texel_turns_the_direction_and_scales_the_strength() {
        let quarter = Vec2::new(0.0, 1.0);
        // Red 1, green 0.5: the tangent itself, so the material's rotation alone.
        let (s, d) = textured_anisotropy(0.8, quarter, Vec3::new(1.0, 0.5, 0.5));
        assert!(
            (s - 0.4).abs() < 1e-6 && (d - quarter).length() < 1e-6,
            "{s} {d}"
        );
        // Green 1: the bitangent, turned a further quarter: −tangent.
        let (_, d) = textured_anisotropy(0.8, quarter, Vec3::new(0.5, 1.0, 1.0));
        assert!((d - Vec2::new(-1.0, 0.0)).length() < 1e-6, "{d}");
        // No direction (0.5, 0.5): the tangent; blue outside 0..1 is clamped.
        let (s, d) = textured_anisotropy(0.8, Vec2::X, Vec3::new(0.5, 0.5, 2.0));
        assert!(
            (s - 0.8).abs() < 1e-6 && (d - Vec2::X).length() < 1e-6,
            "{s} {d}"
        );
    }

    /// ∫ f(x) over the hemisphere about +z, x a unit direction, by the midpoint rule in
    /// (cos θ, φ).
    fn hemisphere(steps: usize, f: impl Fn(Vec3) -> f32) -> f32 {
        let mut sum = 0.0f64;
        for i in 0..steps {
            let cos_t = (i as f32 + 0.5) / steps as f32;
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            for j in 0..steps {
                let phi = (j as f32 + 0.5) / steps as f32 * 2.0 * PI;
                sum += f64::from(f(Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)));
            }
        }
        (sum * 2.0 * f64::from(PI) / (steps * steps) as f64) as f32
    }

    #[test]
    fn the_distribution_is_normalised_at_every_strength() {
        // ∫ D(h) (n·h) dω_h = 1: the projected microfacet area is the macro surface's.
        for alpha in [0.1, 0.3, 0.7] {
            for s in [0.0, 0.5, 0.9, 1.0] {
                let alphas = anisotropic_alphas(alpha, s);
                let integral = hemisphere(1600, |h| d_ggx_anisotropic(alphas, h) * h.z);
                assert!(
                    (integral - 1.0).abs() < 0.01,
                    "α {alpha}, s {s}: ∫ D cos = {integral}"
                );
            }
        }
    }

    #[test]
    fn strength_zero_is_the_isotropic_lobe() {
        // D and V reduce to brdf.rs's isotropic GGX and height-correlated Smith.
        let n = Vec3::Z;
        let t = Vec3::X;
        for (alpha, h, v, l) in [
            (
                0.2,
                Vec3::new(0.1, 0.2, 0.97),
                Vec3::new(0.3, 0.1, 0.95),
                Vec3::new(-0.5, 0.2, 0.84),
            ),
            (
                0.8,
                Vec3::new(-0.4, 0.3, 0.87),
                Vec3::new(0.0, 0.9, 0.44),
                Vec3::new(0.6, -0.6, 0.53),
            ),
        ] {
            let (h, v, l) = (h.normalize(), v.normalize(), l.normalize());
            let alphas = anisotropic_alphas(alpha, 0.0);
            let d = d_ggx_anisotropic(alphas, h);
            let iso = d_ggx(alpha, h.z, n.cross(h).length_squared());
            assert!((d - iso).abs() < 1e-4 * iso, "{d} vs {iso}");
            let vis = v_smith_ggx_correlated_anisotropic(alphas, v, l);
            let iso = v_smith_ggx_correlated(v.z, l.z, alpha);
            assert!((vis - iso).abs() < 1e-4 * iso, "{vis} vs {iso}");
        }
        let surface = Surface {
            base_color: Vec3::new(0.8, 0.5, 0.2),
            metallic: 1.0,
            perceptual_roughness: 0.5,
            specular_level: 0.5,
        };
        let (v, l) = (
            Vec3::new(0.3, 0.1, 0.95).normalize(),
            Vec3::new(-0.5, 0.2, 0.84).normalize(),
        );
        let aniso = relit_brdf_lobes(n, v, l, t, &surface, &RelitLobe::default());
        let iso = surface_brdf_lobes(n, v, l, &surface, VisibilityModel::SmithGgxCorrelated);
        assert!((aniso.specular - iso.specular).length() < 1e-4 * iso.specular.length());
        assert_eq!(aniso.diffuse, iso.diffuse);
    }

    #[test]
    fn the_lobe_is_wider_along_its_direction() {
        // Tilting h by the same angle towards t and towards b: D falls less along t.
        let alphas = anisotropic_alphas(0.1, 0.8);
        let along = d_ggx_anisotropic(alphas, Vec3::new(0.2, 0.0, 1.0).normalize());
        let across = d_ggx_anisotropic(alphas, Vec3::new(0.0, 0.2, 1.0).normalize());
        assert!(along > 10.0 * across, "{along} vs {across}");
        assert!(alphas.x > alphas.y && alphas.y == 0.1);
        assert_eq!(anisotropic_alphas(0.1, f32::NAN), Vec2::splat(0.1));
        assert_eq!(anisotropic_alphas(0.1, 3.0), Vec2::new(1.0, 0.1));
    }

    #[test]
    fn a_white_anisotropic_lobe_loses_energy_but_never_gains_it() {
        // The single-scattering albedo ∫ D F V (n·l) dω of a white metal (F = 1) stays
        // ≤ 1 at every strength and view, and falls as the lobe widens (what the
        // isotropic energy compensation does not restore, docs/src/materials.md).
        let (n, t) = (Vec3::Z, Vec3::X);
        let white = Surface {
            base_color: Vec3::ONE,
            metallic: 1.0,
            perceptual_roughness: 0.5,
            specular_level: 0.5,
        };
        for n_dot_v in [1.0f32, 0.5, 0.1] {
            let v = Vec3::new((1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v);
            let mut previous = f32::INFINITY;
            for s in [0.0, 0.5, 1.0] {
                let albedo = hemisphere(600, |l| {
                    relit_brdf_lobes(
                        n,
                        v,
                        l,
                        t,
                        &white,
                        &RelitLobe {
                            strength: s,
                            ..RelitLobe::default()
                        },
                    )
                    .specular
                    .x * l.z
                });
                println!("n·v {n_dot_v}, s {s}: albedo {albedo:.4}");
                assert!(albedo <= 1.0 + 1e-3, "n·v {n_dot_v}, s {s}: {albedo}");
                assert!(
                    n_dot_v < 0.5 || albedo <= previous + 1e-3,
                    "n·v {n_dot_v}, s {s}: {albedo} > {previous}"
                );
                previous = albedo;
            }
        }
    }

    #[test]
    fn the_bent_normal_stays_unit_and_is_the_normal_without_anisotropy() {
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        let t = anisotropy_direction(n, Vec3::X, 1.0, Vec2::new(1.0, 0.0));
        let v = Vec3::new(0.4, -0.3, 0.8).normalize();
        assert!((anisotropic_bent_normal(n, v, t, 0.0, 0.5) - n).length() < 1e-6);
        for s in [0.3, 1.0, f32::NAN, -2.0] {
            let bent = anisotropic_bent_normal(n, v, t, s, 0.2);
            assert!((bent.length() - 1.0).abs() < 1e-5 && bent.is_finite());
        }
        // A tangent along the normal falls back to a direction in the tangent plane.
        let d = anisotropy_direction(Vec3::Z, Vec3::Z, 1.0, Vec2::new(1.0, 0.0));
        assert!(d.is_finite() && d.dot(Vec3::Z).abs() < 1e-6);
    }
    /// The white metal's single-scattering albedo (F = 1) by [`relit_brdf_lobes`] on a
    /// uniform hemisphere grid: independent of the visible-normal sampling.
    fn white_albedo(n_dot_v: f32, azimuth: f32, r: f32, s: f32) -> f32 {
        let white = Surface {
            base_color: Vec3::ONE,
            metallic: 1.0,
            perceptual_roughness: r,
            specular_level: 0.5,
        };
        let sin_v = (1.0 - n_dot_v * n_dot_v).sqrt();
        let v = Vec3::new(sin_v * azimuth.cos(), sin_v * azimuth.sin(), n_dot_v);
        let lobe = RelitLobe {
            strength: s,
            ..RelitLobe::default()
        };
        hemisphere(800, |l| {
            relit_brdf_lobes(Vec3::Z, v, l, Vec3::X, &white, &lobe)
                .specular
                .x
                * l.z
        })
    }

    #[test]
    fn the_anisotropic_split_sum_is_the_lobes_albedo() {
        // A + B (F = 1) by visible normals against the lobe integrated on a hemisphere
        // grid, along and across the direction, grazing and not: within 1 %.
        for (n_dot_v, azimuth, r, s) in [
            (0.5f32, 0.0f32, 0.5f32, 1.0f32),
            (0.5, FRAC_PI_2, 0.5, 1.0),
            (0.9, 0.7, 0.3, 0.6),
            (0.2, 1.2, 0.8, 0.9),
            (0.7, 0.3, 0.2, 0.0),
        ] {
            let dfg = anisotropic_dfg_integrate(n_dot_v, azimuth, r, s, 4096);
            let grid = white_albedo(n_dot_v, azimuth, r, s);
            println!(
                "n·v {n_dot_v} φ {azimuth} r {r} s {s}: A + B {}, grid {grid}",
                dfg.x + dfg.y
            );
            assert!(
                (dfg.x + dfg.y - grid).abs() < 0.01 * grid,
                "n·v {n_dot_v} φ {azimuth} r {r} s {s}: {dfg} against {grid}"
            );
        }
        // The azimuth matters: roughness 0.5, strength 1, n·v 0.5 (measured 0.64 along
        // the direction, 0.50 across it).
        let along = anisotropic_dfg_integrate(0.5, 0.0, 0.5, 1.0, 4096);
        let across = anisotropic_dfg_integrate(0.5, FRAC_PI_2, 0.5, 1.0, 4096);
        assert!((along.x + along.y - 0.64).abs() < 0.01, "{along}");
        assert!((across.x + across.y - 0.50).abs() < 0.01, "{across}");
    }

    #[test]
    fn the_anisotropic_table_interpolates_within_a_percent() {
        // Between the table's entries (half a step off on every axis) against the
        // integral itself, and exactly the entries at the grid points.
        let table = dfg_table();
        let [n, z, r, s] = DFG_TABLE_DIMS;
        assert_eq!(table.len(), n * z * r * s);
        let mut worst = 0.0f32;
        for (i, a, j, k) in [(7, 3, 9, 4), (13, 0, 2, 6), (2, 6, 13, 1), (10, 5, 5, 3)] {
            let step = |x: usize, size: usize| (x as f32 + 0.5) / (size - 1) as f32;
            let (n_dot_v, azimuth) = (step(i, n), step(a, z) * FRAC_PI_2);
            let (rough, strength) = (step(j, r), step(k, s).sqrt());
            let looked_up = anisotropic_dfg(table, n_dot_v, azimuth, rough, strength);
            let exact = anisotropic_dfg_integrate(n_dot_v, azimuth, rough, strength, 4096);
            let error = ((looked_up.x + looked_up.y) / (exact.x + exact.y) - 1.0).abs();
            worst = worst.max(error);
        }
        println!("worst relative error of A + B between entries: {worst}");
        assert!(worst < 0.01, "{worst}");
        let entry = anisotropic_dfg(table, 1.0, FRAC_PI_2, 1.0, 1.0);
        assert!((entry - table[table.len() - 1]).length() < 1e-6);
        let first = anisotropic_dfg(table, f32::NAN, f32::NAN, 0.0, f32::NAN);
        assert!((first - table[n - 1]).length() < 1e-6, "{first}");
    }

    #[test]
    fn the_view_azimuth_folds_into_a_quarter_turn() {
        let (t, b) = (Vec3::X, Vec3::Y);
        let at = |x: f32, y: f32| view_azimuth(t, b, Vec3::new(x, y, 0.5).normalize());
        assert!(at(1.0, 0.0).abs() < 1e-6);
        assert!((at(0.0, -1.0) - FRAC_PI_2).abs() < 1e-6);
        assert!((at(-1.0, 1.0) - FRAC_PI_2 / 2.0).abs() < 1e-6);
        assert_eq!(view_azimuth(t, b, Vec3::Z), 0.0);
    }
}

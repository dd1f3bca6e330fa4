//! The two PBR workflows of docs/src/formulas.md#material-workflows and the conversions between them.
//!
//! - Metal/roughness: base colour, metallic, perceptual roughness (Lumen's own model):
//!   diffuse colour `c_diff = base · (1 − metallic)`, `F0 = mix(0.04, base, metallic)`.
//! - Specular/glossiness as `KHR_materials_pbrSpecularGlossiness` defines it:
//!   `c_diff = diffuse · (1 − max(specular))`, `F0 = specular`, roughness = 1 − gloss.
//!
//! Both sides feed the same BRDF, so two materials are equivalent when their `c_diff`,
//! `F0` and roughness agree. The conversions keep exactly that: metal/rough → spec/gloss
//! sets `specular = F0` and `diffuse = c_diff / (1 − max(F0))` (Substance's converter,
//! docs/src/formulas.md#material-workflows, writes `diffuse = c_diff` and so differs by that factor). Spec/gloss
//! → metal/rough solves, on perceived brightness, the metallic value for which one base
//! colour gives both `c_diff` and `F0`:
//! `0.04 (1 − m)² − (s + d)(1 − m) + d = 0`, then recovers each channel from the diffuse
//! and the specular side, blended by metallic² (the approach of the Khronos converter).
//! Grey materials and pure dielectrics or metals come back exactly; a coloured partial
//! metal is the only case the one-metallic model cannot represent exactly. Colours are
//! linear RGB.

use glam::Vec3;

/// F0 of a dielectric, the 4 % both workflows assume (docs/src/formulas.md#material-workflows).
pub const DIELECTRIC_F0: f32 = 0.04;

/// A metal/roughness material's colour terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    /// Linear base colour.
    pub base_color: Vec3,
    /// 0 = dielectric, 1 = metal.
    pub metallic: f32,
    /// Perceptual roughness, 0 (mirror) .. 1.
    pub roughness: f32,
}

/// A specular/glossiness material's colour terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecGloss {
    /// Linear diffuse colour (black for bare metal).
    pub diffuse: Vec3,
    /// Linear specular colour: F0 per channel.
    pub specular: Vec3,
    /// Glossiness, 0 (rough) .. 1 (smooth) = 1 − roughness.
    pub glossiness: f32,
}

/// `x` clamped to [0, 1], NaN to 0.
fn unit(x: f32) -> f32 {
    if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
}

/// A colour clamped to [0, 1] per channel, NaN to 0.
fn unit_color(c: Vec3) -> Vec3 {
    Vec3::new(unit(c.x), unit(c.y), unit(c.z))
}

/// Perceived brightness of a linear colour: √(0.299 r² + 0.587 g² + 0.114 b²).
fn perceived_brightness(c: Vec3) -> f32 {
    (0.299 * c.x * c.x + 0.587 * c.y * c.y + 0.114 * c.z * c.z).sqrt()
}

/// `1 − m` for which one base colour gives the effective diffuse brightness `d` and the
/// specular brightness `s`: the root in [0, 1] of `0.04 x² − (s + d) x + d = 0`.
fn solve_one_minus_metallic(d: f32, s: f32) -> f32 {
    if s <= DIELECTRIC_F0 {
        return 1.0;
    }
    let a = DIELECTRIC_F0;
    let b = s + d;
    let discriminant = (b * b - 4.0 * a * d).max(0.0);
    unit((b - discriminant.sqrt()) / (2.0 * a))
}

/// Metal/rough → spec/gloss: the same `c_diff`, `F0` and roughness. A dielectric base
/// colour above 1 − 0.04 = 0.96 does not fit spec/gloss's diffuse range [0, 1]; it is
/// clamped there.
pub fn to_spec_gloss(m: MetalRough) -> SpecGloss {
    let metallic = unit(m.metallic);
    let base = unit_color(m.base_color);
    let specular = Vec3::splat(DIELECTRIC_F0).lerp(base, metallic);
    let c_diff = base * (1.0 - metallic);
    let keep = 1.0 - specular.max_element();
    SpecGloss {
        diffuse: if keep > 0.0 {
            unit_color(c_diff / keep)
        } else {
            Vec3::ZERO
        },
        specular,
        glossiness: 1.0 - unit(m.roughness),
    }
}

/// Spec/gloss → metal/rough (see the module documentation).
pub fn to_metal_rough(s: SpecGloss) -> MetalRough {
    let specular = unit_color(s.specular);
    let c_diff = unit_color(s.diffuse) * (1.0 - specular.max_element());
    let x = solve_one_minus_metallic(perceived_brightness(c_diff), perceived_brightness(specular));
    let metallic = 1.0 - x;
    let from_diffuse = if x > 1e-6 { c_diff / x } else { Vec3::ZERO };
    let from_specular = if metallic > 1e-6 {
        (specular - Vec3::splat(DIELECTRIC_F0 * x)) / metallic
    } else {
        Vec3::ZERO
    };
    MetalRough {
        base_color: unit_color(from_diffuse.lerp(from_specular, metallic * metallic)),
        metallic,
        roughness: 1.0 - unit(s.glossiness),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_forward_conversion_is_substances() {
        let s = to_spec_gloss(MetalRough {
            base_color: Vec3::new(0.9, 0.6, 0.3),
            metallic: 1.0,
            roughness: 0.3,
        });
        assert_eq!(s.diffuse, Vec3::ZERO);
        assert!((s.specular - Vec3::new(0.9, 0.6, 0.3)).abs().max_element() < 1e-6);
        assert!((s.glossiness - 0.7).abs() < 1e-6);
        let d = to_spec_gloss(MetalRough {
            base_color: Vec3::splat(0.5),
            metallic: 0.0,
            roughness: 1.0,
        });
        assert_eq!(d.specular, Vec3::splat(DIELECTRIC_F0));
        // c_diff = diffuse · (1 − max F0) = 0.5.
        assert!(
            (d.diffuse * (1.0 - DIELECTRIC_F0) - Vec3::splat(0.5))
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(d.glossiness, 0.0);
    }

    #[test]
    fn round_trips_come_back() {
        // Spec/gloss cannot hold a dielectric c_diff above 1 − 0.04 (diffuse ≤ 1).
        for base in [0.05f32, 0.2, 0.5, 0.8, 0.96] {
            for metallic in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
                let m = MetalRough {
                    base_color: Vec3::splat(base),
                    metallic,
                    roughness: 0.4,
                };
                let back = to_metal_rough(to_spec_gloss(m));
                // Where base = F0 = 0.04, metallic is not observable; compare what the BRDF
                // sees (c_diff and F0) instead of the parameters.
                let c_diff = |m: MetalRough| m.base_color * (1.0 - m.metallic);
                let f0 = |m: MetalRough| Vec3::splat(DIELECTRIC_F0).lerp(m.base_color, m.metallic);
                assert!(
                    (c_diff(m) - c_diff(back)).abs().max_element() < 1e-4
                        && (f0(m) - f0(back)).abs().max_element() < 1e-4,
                    "base {base} metallic {metallic}: {back:?}"
                );
                assert!((back.roughness - 0.4).abs() < 1e-6);
            }
        }
        for colour in [Vec3::new(0.95, 0.64, 0.54), Vec3::new(0.2, 0.6, 0.9)] {
            for metallic in [0.0, 1.0] {
                let m = MetalRough {
                    base_color: colour,
                    metallic,
                    roughness: 0.5,
                };
                let back = to_metal_rough(to_spec_gloss(m));
                assert!(
                    (back.base_color - colour).abs().max_element() < 1e-3
                        && (back.metallic - metallic).abs() < 1e-3,
                    "{colour} metallic {metallic}: {back:?}"
                );
            }
        }
    }

    #[test]
    fn bad_input_stays_in_range() {
        for v in [f32::NAN, f32::INFINITY, -1.0, 0.0, 2.0] {
            let m = to_metal_rough(SpecGloss {
                diffuse: Vec3::splat(v),
                specular: Vec3::splat(v),
                glossiness: v,
            });
            assert!(
                (0.0..=1.0).contains(&m.metallic) && (0.0..=1.0).contains(&m.roughness),
                "{v}: {m:?}"
            );
            assert!(m.base_color.cmpge(Vec3::ZERO).all() && m.base_color.cmple(Vec3::ONE).all());
        }
    }
}

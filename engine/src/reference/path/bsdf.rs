//! The path tracer's BSDF at a hit: `brdf.rs`'s Cook-Torrance (diffuse and GGX specular
//! lobes) about the shading normal, sampled as a mixture of a cosine lobe and GGX visible
//! normals (Heitz 2018); on a material with a sheen, the sheen lobe about the mesh's own
//! normal over it (`crate::shading::sheen`), and on a clearcoated material the coat's GGX lobe
//! over both (`crate::shading::clearcoat`), layered as the rasterizer layers them:
//! `f = factor · f_coat + (1 − factor · E_coat(n·v)) · (f_sheen + (1 − max(c) · E_sheen(n·v)) · f_base)`.
//! The sheen is sampled by a cosine lobe about its normal. An anisotropic base
//! (`crate::shading::anisotropy`) has its GGX lobe stretched along a direction in the tangent
//! plane, evaluated and sampled (visible normals of the stretched lobe) in a frame whose
//! first axis is that direction. A translucent base (`crate::shading::diffuse_transmission`)
//! moves part of its diffuse lobe to the other side of the surface, sampled by a cosine
//! lobe about the turned normal; paths then continue through the surface.

use super::microfacet::{basis, concentric_disk, g1_ggx_anisotropic};
use super::rng::Rng;
use super::traced_scene::{AlbedoTable, TraceMaterial};
use crate::shading::anisotropy::{
    RelitLobe, anisotropic_alphas, d_ggx_anisotropic, relit_brdf_lobes,
};
use crate::shading::brdf::{Surface, VisibilityModel, surface_brdf_lobes};
use crate::shading::clearcoat::{CLEARCOAT_SPECULAR_LEVEL, clearcoat_base_weight};
use crate::shading::diffuse_transmission::diffuse_transmission_lobe;
use crate::shading::iridescence::iridescent_mix;
use glam::{Mat3, Vec2, Vec3, Vec4};
use std::f32::consts::PI;

/// Solid-angle density (1/sr) of drawing `l` by reflecting `v` about a GGX visible normal
/// of widths `alphas` along the first two axes of `frame` (its third column the normal)
/// (Heitz 2018: G1(v) D / (4 n·v)); 0 below either horizon.
fn reflection_pdf(frame: Mat3, v: Vec3, l: Vec3, alphas: Vec2) -> f32 {
    let (v, l) = (frame.transpose() * v, frame.transpose() * l);
    if l.z <= 0.0 || v.z <= 0.0 {
        return 0.0;
    }
    let h = (v + l).normalize_or(Vec3::Z);
    let d = d_ggx_anisotropic(alphas, h);
    g1_ggx_anisotropic(v, alphas) * d / (4.0 * v.z)
}

/// `v` reflected about a GGX visible normal of widths `alphas` drawn in `frame` (its third
/// column the normal); `None` when `v` or the reflection is below the surface.
fn sample_reflection(frame: Mat3, alphas: Vec2, v: Vec3, rng: &mut Rng) -> Option<Vec3> {
    let local_v = frame.transpose() * v;
    if local_v.z <= 0.0 {
        return None;
    }
    let h = crate::shading::ibl::sample_ggx_vndf_anisotropic(local_v, alphas, rng.pair());
    let local_l = 2.0 * local_v.dot(h) * h - local_v;
    (local_l.z > 0.0).then(|| (frame * local_l).normalize())
}

/// The F0 the energy compensation sees for a base of `surface` with the relit `lobe`,
/// seen at cosine `n_dot_v`: the tinted F0 whose Schlick Fresnel is the film's, as the
/// rasterizer's split sum uses it.
fn compensated_f0(surface: &Surface, lobe: &RelitLobe, n_dot_v: f32) -> Vec3 {
    let f0 = crate::shading::brdf::tinted_f0(
        surface.base_color,
        surface.metallic,
        surface.specular_level,
        lobe.tint,
    );
    crate::shading::iridescence::film_f0(f0, n_dot_v, lobe.film)
}

/// A clearcoat's specular lobe (F0 0.04) about its own normal.
struct CoatLobe {
    frame: Mat3,
    surface: Surface,
    /// Multiplies the lobe (its energy compensation; 1 when off).
    specular_scale: Vec3,
    /// Its GGX width, along both axes.
    alphas: Vec2,
    /// The coat's strength, 0..1.
    factor: f32,
}

impl CoatLobe {
    fn n(&self) -> Vec3 {
        self.frame.z_axis
    }

    /// factor · f_coat(v, l) · (n_c·l).
    fn eval(&self, v: Vec3, l: Vec3, model: VisibilityModel) -> Vec3 {
        let n = self.n();
        let lobes = surface_brdf_lobes(n, v, l, &self.surface, model);
        lobes.specular * self.specular_scale * (self.factor * n.dot(l).max(0.0))
    }
}

/// A sheen lobe (Charlie distribution, Neubelt visibility) about its own normal.
struct SheenLobe {
    frame: Mat3,
    color: Vec3,
    roughness: f32,
}

impl SheenLobe {
    fn n(&self) -> Vec3 {
        self.frame.z_axis
    }

    /// f_sheen(v, l) · (n_s·l).
    fn eval(&self, v: Vec3, l: Vec3) -> Vec3 {
        let n = self.n();
        let (n_dot_v, n_dot_l) = (n.dot(v), n.dot(l));
        let h = (v + l).normalize_or(n);
        crate::shading::sheen::sheen_brdf(self.color, self.roughness, n_dot_v, n_dot_l, n.dot(h))
            * n_dot_l.max(0.0)
    }

    /// The cosine lobe's density about the sheen's normal.
    fn pdf(&self, l: Vec3) -> f32 {
        self.n().dot(l).max(0.0) / PI
    }
}

/// The BSDF at a hit, in a local frame around the shading normal.
pub(super) struct Bsdf {
    frame: Mat3,
    surface: Surface,
    /// Multiplies the specular lobe (energy compensation; 1 when off).
    specular_scale: Vec3,
    /// The specular lobe's GGX widths along the frame's first two axes.
    alphas: Vec2,
    /// What a relit base adds (anisotropy along the frame's first axis, tint, film).
    lobe: RelitLobe,
    /// A relit base (anisotropic, tinted, iridescent or translucent): evaluated by
    /// `relit_brdf_lobes`, as the rasterizer's layers pass relights it.
    relit: bool,
    /// The diffuse transmission's factor (0: none) and colour.
    translucency: (f32, Vec3),
    /// Probability of sampling the specular lobe (when the base is sampled).
    p_specular: f32,
    /// Probability of sampling the transmitted diffuse lobe when the diffuse lobe is
    /// sampled (0 without diffuse transmission).
    p_transmit: f32,
    model: VisibilityModel,
    /// The clearcoat over the base, if any.
    coat: Option<CoatLobe>,
    /// What the coat lets through of the base's light: 1 − factor · E_coat (1 uncoated).
    base_weight: f32,
    /// Probability of sampling the coat's lobe (0 uncoated).
    p_coat: f32,
    /// The sheen over the base (under the coat), if any.
    sheen: Option<SheenLobe>,
    /// What the sheen lets through of the base's light: 1 − max(colour) · E_sheen.
    sheen_weight: f32,
    /// Probability of sampling the sheen's lobe when the coat is not sampled.
    p_sheen: f32,
}

impl Bsdf {
    /// The base of material `m` about the unit shading normal `n`, seen from `v`.
    /// `compensation`: the energy compensation's albedo table, when it is on.
    pub(super) fn new(
        n: Vec3,
        v: Vec3,
        m: &TraceMaterial,
        model: VisibilityModel,
        compensation: Option<&AlbedoTable>,
    ) -> Bsdf {
        let surface = Surface {
            base_color: m.base_color,
            metallic: m.metallic,
            perceptual_roughness: m.roughness,
            specular_level: m.specular_level,
        };
        let lobe = RelitLobe {
            strength: 0.0,
            tint: m.specular_tint.unwrap_or(Vec3::ONE),
            film: m
                .iridescence
                .map_or(Vec3::ZERO, |f| Vec3::new(f.factor, f.ior, f.thickness_nm)),
        };
        let f0 =
            crate::shading::brdf::tinted_f0(m.base_color, m.metallic, m.specular_level, lobe.tint);
        let f = iridescent_mix(f0, n.dot(v).clamp(0.0, 1.0), lobe.film);
        let spec = luminance(f);
        let diff = luminance(m.base_color) * (1.0 - m.metallic);
        let p_specular = lobe_probability(spec, diff);
        let translucency = m
            .diffuse_transmission
            .map_or((0.0, Vec3::ZERO), |d| (d.factor, d.color));
        let p_transmit = if translucency.0 > 0.0 {
            lobe_probability(
                translucency.0 * luminance(translucency.1),
                (1.0 - translucency.0) * luminance(m.base_color),
            )
        } else {
            0.0
        };
        let compensated = compensated_f0(&surface, &lobe, n.dot(v).clamp(0.0, 1.0));
        let specular_scale = compensation.map_or(Vec3::ONE, |table| {
            table.compensation(compensated, n.dot(v), m.roughness)
        });
        Bsdf {
            frame: basis(n),
            surface,
            specular_scale,
            alphas: Vec2::splat(m.roughness * m.roughness),
            lobe,
            relit: m.specular_tint.is_some()
                || m.iridescence.is_some()
                || m.diffuse_transmission.is_some(),
            translucency,
            p_specular,
            p_transmit,
            model,
            coat: None,
            base_weight: 1.0,
            p_coat: 0.0,
            sheen: None,
            sheen_weight: 1.0,
            p_sheen: 0.0,
        }
    }

    /// The same base with its specular lobe made anisotropic (`anisotropy`, clamped):
    /// stretched along the direction it makes with the interpolated tangent `tangent`
    /// (xyz, handedness in w), in the tangent plane of the shading normal, seen from `v`.
    /// With `compensated`, the energy compensation divides by the anisotropic lobe's
    /// albedo at v's cosine and azimuth ([`crate::shading::anisotropy::anisotropic_dfg`]), as the
    /// rasterizer's relit base does. Call before the layers.
    pub(super) fn with_anisotropy(
        mut self,
        tangent: Vec4,
        anisotropy: crate::scene::Anisotropy,
        v: Vec3,
        compensated: bool,
    ) -> Bsdf {
        let n = self.n();
        let (sin, cos) = anisotropy.rotation_rad.sin_cos();
        let t = crate::shading::anisotropy::anisotropy_direction(
            n,
            tangent.truncate(),
            tangent.w,
            Vec2::new(cos, sin),
        );
        self.frame = Mat3::from_cols(t, n.cross(t), n);
        self.alphas = anisotropic_alphas(self.alphas.y, anisotropy.strength);
        self.lobe.strength = anisotropy.strength;
        self.relit = true;
        if compensated {
            let n_dot_v = n.dot(v).clamp(0.0, 1.0);
            let dfg = crate::shading::anisotropy::anisotropic_dfg(
                crate::shading::anisotropy::dfg_table(),
                n_dot_v.max(crate::shading::brdf::MIN_N_DOT_V),
                crate::shading::anisotropy::view_azimuth(t, n.cross(t), v),
                self.surface.perceptual_roughness,
                anisotropy.strength,
            );
            let f0 = compensated_f0(&self.surface, &self.lobe, n_dot_v);
            self.specular_scale = crate::shading::ibl::energy_compensation(f0, dfg);
        }
        self
    }

    /// The same base under a sheen of colour `color` and perceptual roughness
    /// `roughness` on the unit normal `n_s` (turned to the viewer), seen from `v`.
    /// Call before [`Bsdf::with_coat`].
    pub(super) fn with_sheen(
        mut self,
        n_s: Vec3,
        v: Vec3,
        (color, roughness): (Vec3, f32),
    ) -> Bsdf {
        let albedo = crate::shading::sheen::sheen_albedo(
            crate::shading::sheen::albedo_table(),
            n_s.dot(v).clamp(0.0, 1.0),
            roughness,
        );
        self.sheen_weight = crate::shading::sheen::sheen_base_weight(color, albedo);
        let sheen = luminance(color) * albedo;
        let base = self.sheen_weight * self.reflectance(v);
        self.p_sheen = lobe_probability(sheen, base);
        self.sheen = Some(SheenLobe {
            frame: basis(n_s),
            color,
            roughness,
        });
        self
    }

    /// An estimate of the base's reflectance towards `v` (luminance of F plus the
    /// diffuse albedo), for choosing between lobes.
    fn reflectance(&self, v: Vec3) -> f32 {
        let f0 = crate::shading::brdf::tinted_f0(
            self.surface.base_color,
            self.surface.metallic,
            self.surface.specular_level,
            self.lobe.tint,
        );
        let f = iridescent_mix(f0, self.n().dot(v).clamp(0.0, 1.0), self.lobe.film);
        luminance(f) + luminance(self.surface.base_color) * (1.0 - self.surface.metallic)
    }

    /// The same base under a clearcoat of strength `factor` (0..1) and perceptual
    /// roughness `roughness` on the unit normal `n_c` (turned to the viewer), seen from
    /// `v`. `coat_albedo`: the single-scattering albedo of a GGX lobe of F0 0.04;
    /// `compensation`: the energy compensation's table, when it is on.
    pub(super) fn with_coat(
        mut self,
        n_c: Vec3,
        v: Vec3,
        (factor, roughness): (f32, f32),
        coat_albedo: &AlbedoTable,
        compensation: Option<&AlbedoTable>,
    ) -> Bsdf {
        let f0 = crate::shading::brdf::dielectric_f0(CLEARCOAT_SPECULAR_LEVEL);
        let n_dot_v = n_c.dot(v).clamp(0.0, 1.0);
        let specular_scale = compensation.map_or(Vec3::ONE, |table| {
            table.compensation(Vec3::splat(f0), n_dot_v, roughness)
        });
        let albedo = (coat_albedo.lookup(n_dot_v, roughness) * specular_scale.x).clamp(0.0, 1.0);
        self.base_weight = clearcoat_base_weight(factor, albedo);
        // Sample the coat in proportion to what it reflects against what the base does.
        let coat = factor * albedo;
        let base = self.base_weight * self.reflectance(v);
        self.p_coat = lobe_probability(coat, base);
        self.coat = Some(CoatLobe {
            frame: basis(n_c),
            surface: Surface {
                base_color: Vec3::ZERO,
                metallic: 0.0,
                perceptual_roughness: roughness,
                specular_level: CLEARCOAT_SPECULAR_LEVEL,
            },
            specular_scale,
            alphas: Vec2::splat(roughness * roughness),
            factor,
        });
        self
    }

    /// The base's specular lobe: its frame (tangent, bitangent, normal: the anisotropy's
    /// direction first) and its GGX widths along the first two axes.
    pub(super) fn lobe_frame(&self) -> (Mat3, Vec2) {
        (self.frame, self.alphas)
    }

    /// A tinted or iridescent base's dielectric surface and lobe (its tint and film),
    /// for a transmissive interface's Fresnel; `None` when untinted and without a film.
    pub(super) fn tinted_interface(&self) -> Option<(Surface, RelitLobe)> {
        (self.lobe.tint != Vec3::ONE || self.lobe.film.x > 0.0).then_some((
            Surface {
                metallic: 0.0,
                ..self.surface
            },
            self.lobe,
        ))
    }

    /// The fraction of the light beneath the layers (the base's, its emission included)
    /// that leaves through them towards the viewer: 1 without layers.
    pub(super) fn through_layers(&self) -> f32 {
        self.base_weight * self.sheen_weight
    }

    /// Whether light passes through the base (diffuse transmission): `eval` is then not
    /// zero below its horizon, and sampled directions may be there.
    pub(super) fn transmits(&self) -> bool {
        self.translucency.0 > 0.0
    }

    /// The shading normal of the base.
    pub(super) fn n(&self) -> Vec3 {
        self.frame.z_axis
    }

    /// f(v, l) · |cos|: the base's lobes × |n·l| (below the horizon, its diffuse
    /// transmission), dimmed by the coat, plus the coat's.
    pub(super) fn eval(&self, v: Vec3, l: Vec3) -> Vec3 {
        let n = self.n();
        let n_dot_l = n.dot(l);
        let (factor, color) = self.translucency;
        let mut base = if n_dot_l < 0.0 {
            diffuse_transmission_lobe(n, v, l, &self.surface, &self.lobe, factor, color) * -n_dot_l
        } else {
            let lobes = if self.relit {
                relit_brdf_lobes(n, v, l, self.frame.x_axis, &self.surface, &self.lobe)
            } else {
                surface_brdf_lobes(n, v, l, &self.surface, self.model)
            };
            (lobes.diffuse * (1.0 - factor) + lobes.specular * self.specular_scale)
                * n_dot_l.max(0.0)
        };
        if let Some(sheen) = &self.sheen {
            base = sheen.eval(v, l) + base * self.sheen_weight;
        }
        match &self.coat {
            None => base,
            Some(coat) => base * self.base_weight + coat.eval(v, l, self.model),
        }
    }

    /// Solid-angle density of [`Bsdf::sample`] choosing `l`.
    pub(super) fn pdf(&self, v: Vec3, l: Vec3) -> f32 {
        let n = self.n();
        let n_dot_l = n.dot(l);
        let p_diffuse = 1.0 - self.p_specular;
        let mut base = if n.dot(v) <= 0.0 || n_dot_l.is_nan() {
            0.0
        } else if n_dot_l > 0.0 {
            self.p_specular * reflection_pdf(self.frame, v, l, self.alphas)
                + p_diffuse * (1.0 - self.p_transmit) * n_dot_l / PI
        } else {
            p_diffuse * self.p_transmit * -n_dot_l / PI
        };
        if let Some(sheen) = &self.sheen {
            base = self.p_sheen * sheen.pdf(l) + (1.0 - self.p_sheen) * base;
        }
        match &self.coat {
            None => base,
            Some(coat) => {
                self.p_coat * reflection_pdf(coat.frame, v, l, coat.alphas)
                    + (1.0 - self.p_coat) * base
            }
        }
    }

    /// A direction drawn from the mixture, with f·cos/pdf and the pdf.
    pub(super) fn sample(&self, v: Vec3, rng: &mut Rng) -> Option<(Vec3, Vec3, f32)> {
        let coat = self.coat.as_ref().filter(|_| rng.uniform() < self.p_coat);
        let sheen = match coat {
            None => self.sheen.as_ref().filter(|_| rng.uniform() < self.p_sheen),
            Some(_) => None,
        };
        let l = match (coat, sheen) {
            (Some(coat), _) => sample_reflection(coat.frame, coat.alphas, v, rng)?,
            (None, Some(sheen)) => {
                let d = concentric_disk(rng.pair());
                let local = Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt());
                (sheen.frame * local).normalize()
            }
            (None, None) => {
                if (self.frame.transpose() * v).z <= 0.0 {
                    return None;
                }
                if rng.uniform() < self.p_specular {
                    sample_reflection(self.frame, self.alphas, v, rng)?
                } else {
                    let d = concentric_disk(rng.pair());
                    let local = Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt());
                    if local.z <= 0.0 {
                        return None;
                    }
                    // Through the surface: the same cosine lobe about the turned normal.
                    let through = self.p_transmit > 0.0 && rng.uniform() < self.p_transmit;
                    let local = if through {
                        Vec3::new(local.x, local.y, -local.z)
                    } else {
                        local
                    };
                    (self.frame * local).normalize()
                }
            }
        };
        let pdf = self.pdf(v, l);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(v, l) / pdf;
        weight.is_finite().then_some((l, weight, pdf))
    }
}

/// The probability of sampling a lobe that reflects `lobe` against the `rest` (both
/// luminances), kept in 0.1..0.9 so that neither side is starved; 0.5 when both are 0.
pub(super) fn lobe_probability(lobe: f32, rest: f32) -> f32 {
    if lobe + rest > 0.0 {
        (lobe / (lobe + rest)).clamp(0.1, 0.9)
    } else {
        0.5
    }
}

/// Rec. 709 luminance weights, for choosing between lobes.
fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampled_albedo_matches_quadrature() {
        // ∫ f cos dω two ways: the mean of the sampler's weights f·cos/pdf, and stratified
        // quadrature. They agree only if the pdf is the density the sampler draws from.
        let n = Vec3::Z;
        let v = Vec3::new(0.5, 0.0, 0.866).normalize();
        // (metallic, roughness, clearcoat (factor, roughness), sheen (colour, roughness),
        // anisotropy (strength, rotation)), the layers on a normal tilted from n.
        let sheen = |c: f32, r: f32| Some((Vec3::splat(c), r));
        let aniso = |s: f32, r: f32| {
            Some(crate::scene::Anisotropy {
                strength: s,
                rotation_rad: r,
            })
        };
        let cases = [
            (0.0, 0.5, None, None, None),
            (1.0, 0.3, None, None, None),
            (0.5, 0.9, None, None, None),
            (1.0, 0.2, None, None, None),
            (0.0, 0.6, Some((1.0, 0.3)), None, None),
            (1.0, 0.5, Some((0.5, 0.8)), None, None),
            (0.0, 0.8, None, sheen(0.8, 0.3), None),
            (0.0, 0.4, Some((1.0, 0.1)), sheen(1.0, 0.7), None),
            (1.0, 0.3, None, None, aniso(0.8, 0.0)),
            (1.0, 0.5, None, None, aniso(1.0, 1.0)),
            (0.0, 0.4, Some((1.0, 0.2)), None, aniso(0.6, -0.5)),
            // Roughness 0.7 and 0.45: translucent (diffuse transmission).
            (0.0, 0.7, None, None, None),
            (0.0, 0.45, Some((1.0, 0.3)), sheen(0.5, 0.5), None),
        ];
        let n_c = Vec3::new(0.2, 0.1, 1.0).normalize();
        let coat_albedo = AlbedoTable::with_f0(32, 1024, VisibilityModel::default(), 0.04);
        let tangent = Vec4::new(1.0, 0.3, 0.2, 1.0);
        for (metallic, roughness, coat, sheen, anisotropy) in cases {
            let m = TraceMaterial {
                base_color: Vec3::splat(0.7),
                metallic,
                roughness,
                specular_level: 0.5,
                emissive: Vec3::ZERO,
                maps: None,
                alpha: 1.0,
                blend: false,
                transmission: None,
                unlit: false,
                clearcoat: None,
                sheen: None,
                anisotropy: None,
                // The anisotropic dielectric is tinted too.
                specular_tint: (metallic == 0.0 && anisotropy.is_some())
                    .then_some(Vec3::new(1.0, 0.5, 0.2)),
                // The first anisotropic metal has an iridescent film.
                iridescence: (metallic == 1.0 && roughness == 0.3 && anisotropy.is_some())
                    .then_some(crate::scene::Iridescence::default()),
                diffuse_transmission: [0.7, 0.45].contains(&roughness).then_some(
                    crate::scene::DiffuseTransmission {
                        factor: 0.6,
                        color: Vec3::new(0.9, 0.5, 0.2),
                    },
                ),
            };
            let bsdf = Bsdf::new(n, v, &m, VisibilityModel::default(), None);
            let bsdf = match anisotropy {
                Some(a) => bsdf.with_anisotropy(tangent, a, v, false),
                None => bsdf,
            };
            let bsdf = match sheen {
                Some(s) => bsdf.with_sheen(n_c, v, s),
                None => bsdf,
            };
            let bsdf = match coat {
                Some(c) => bsdf.with_coat(n_c, v, c, &coat_albedo, None),
                None => bsdf,
            };
            let steps = 800;
            let mut quadrature = 0.0;
            for i in 0..steps {
                for j in 0..steps {
                    // The whole sphere: a tilted coat reflects below the base's horizon.
                    let cos_t = (i as f32 + 0.5) / steps as f32 * 2.0 - 1.0;
                    let phi = (j as f32 + 0.5) / steps as f32 * 2.0 * PI;
                    let s = (1.0 - cos_t * cos_t).sqrt();
                    let l = Vec3::new(s * phi.cos(), s * phi.sin(), cos_t);
                    quadrature += bsdf.eval(v, l).x * (4.0 * PI / (steps * steps) as f32);
                }
            }
            let mut rng = Rng::new(3, 5, 7);
            let count = 200_000;
            let sampled: f32 = (0..count)
                .filter_map(|_| bsdf.sample(v, &mut rng))
                .map(|(_, w, _)| w.x)
                .sum::<f32>()
                / count as f32;
            let err = (sampled - quadrature).abs() / quadrature;
            assert!(
                err < 0.02,
                "metallic {metallic} roughness {roughness} coat {coat:?} sheen {sheen:?} anisotropy {anisotropy:?}: {sampled} vs {quadrature}"
            );
        }
    }
}

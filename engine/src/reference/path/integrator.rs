//! Unidirectional path tracing with next-event estimation (Pharr, Jakob & Humphreys,
//! "Physically Based Rendering", 4th ed., ch. 13):
//!
//! - every light is sampled at every hit with a shadow ray, using the rasterizer's
//!   attenuation functions (`punctual.rs`); point and spot lights are points, a shadowed
//!   sun is its disc (the angular size PCSS uses);
//! - the environment is sampled in proportion to luminance × sin θ (an image) or cosine
//!   weighted (uniform), and combined with BSDF sampling by the power heuristic (Veach
//!   1997);
//! - the BSDF is `brdf.rs`'s Cook-Torrance with the scene's visibility term (and the
//!   rasterizer's energy compensation when it is on), sampled as a mixture of a cosine
//!   lobe and GGX visible normals (Heitz 2018);
//! - light that reaches a surface after one bounce off another is found two ways: by
//!   sampling the BSDF towards the other surface and a shadow ray from there to the light,
//!   and by tracing a ray from a point or spot light to a surface and connecting that
//!   surface to the path's vertex (the s = 2 strategy of bidirectional path tracing,
//!   Veach & Guibas 1995, "Bidirectional Estimators for Light Transport"). The power
//!   heuristic (Veach 1997) weights the two by their densities over the bounce surface's
//!   area. The second finds the small bright patch a light just under a ceiling makes,
//!   which BSDF sampling hits rarely (the fireflies of an indoor scene);
//! - a transmissive surface (`KHR_materials_transmission`) is, with probability
//!   (1 − metallic) × transmission, a rough dielectric interface that reflects or
//!   refracts ([`super::dielectric`]), absorbing by Beer–Lambert inside its volume; its
//!   lights are sampled through its specular reflection lobe only, and everything it
//!   refracts is found by following the ray (no light is connected through glass: shadow
//!   rays stop at it, as the rasterizer's shadow maps do). A sheen and a clearcoat lie
//!   on its outside, over the interface: its lights are sampled through the layered
//!   reflection, and the path follows a layer's reflection with probability
//!   lobe_probability(1 − w, w), w being what the layers let through, else the interface,
//!   × w. A tint or an iridescent film on its outside colours what it reflects and lets
//!   through 1 − the largest channel of that Fresnel. At the first dispersive
//!   interface a path picks red, green or blue with probability 1/3 and carries that
//!   channel alone, × 3, through that channel's index from then on;
//! - paths end at `max_bounces` surface interactions, with Russian roulette after 3.
//!
//! `max_bounces = 1` is direct lighting only: what the rasterizer computes, without its
//! approximations (shadow maps, split-sum IBL, prefiltered environment).

use super::bsdf::{Bsdf, lobe_probability};
use super::microfacet::{basis, concentric_disk};
use super::rng::Rng;
use super::traced_scene::{
    LightVisibility, SurfacePoint, TraceEnvironment, TraceLight, TraceMaterial, TraceScene,
};
use crate::shading::punctual::{distance_attenuation, spot_attenuation};
use glam::{Vec2, Vec3, Vec4};
use std::f32::consts::PI;

/// `normal`, or its opposite where it points away from `facing`.
fn turned(normal: Vec3, facing: Vec3) -> Vec3 {
    if normal.dot(facing) < 0.0 {
        -normal
    } else {
        normal
    }
}

/// A direction drawn uniformly from the cone of directions within `cos_max` of the unit
/// `axis` (cos_max = −1: the whole sphere); its solid-angle density is [`cone_pdf`].
fn uniform_cone(axis: Vec3, cos_max: f32, xi: Vec2) -> Vec3 {
    let cos_t = 1.0 - xi.x * (1.0 - cos_max);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * xi.y;
    basis(axis) * Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// Solid-angle density (1/sr) of [`uniform_cone`]: one over the cone's solid angle
/// 2π(1 − cos_max).
fn cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max)).max(1e-12)
}

/// How a path reached a surface by sampling the BSDF of the surface before it.
#[derive(Clone, Copy)]
struct Arrival {
    /// Density over the surface's area (1/m²): the BSDF's solid-angle density × cos θ / d².
    pdf_area: f32,
    /// The surface's geometric normal, turned to where the path came from.
    facing: Vec3,
}

/// Where a point or spot light sends light rays from, and into which cone.
struct Emitter {
    /// Position (m).
    position: Vec3,
    /// Unit axis of the cone.
    axis: Vec3,
    /// Cosine of the cone's half angle (−1: every direction).
    cos_max: f32,
}

impl Emitter {
    /// Solid-angle density (1/sr) of a light ray along the unit `dir`.
    fn pdf(&self, dir: Vec3) -> f32 {
        if dir.dot(self.axis) >= self.cos_max {
            cone_pdf(self.cos_max)
        } else {
            0.0
        }
    }
}

impl TraceLight {
    /// The light's [`Emitter`]; None for a sun, which has no position to trace from. A
    /// spot light emits into its outer cone, where its cone factor
    /// `saturate(cos θ · scale + offset)²` is above 0: cos θ > −offset / scale.
    fn emitter(&self) -> Option<Emitter> {
        match *self {
            TraceLight::Directional { .. } => None,
            TraceLight::Point { position_m, .. } => Some(Emitter {
                position: position_m,
                axis: Vec3::Y,
                cos_max: -1.0,
            }),
            TraceLight::Spot {
                position_m,
                axis,
                cone_scale,
                cone_offset,
                ..
            } => {
                let cos_outer = if cone_scale > 0.0 {
                    (-cone_offset / cone_scale).clamp(-1.0, 1.0)
                } else {
                    -1.0
                };
                Some(Emitter {
                    position: position_m,
                    axis: axis.normalize_or(Vec3::NEG_Y),
                    cos_max: cos_outer,
                })
            }
        }
    }

    /// Pre-exposed illuminance (lux, rgb) on a surface facing a point or spot light, `d2`
    /// m² away from it along the unit `dir` (away from the light): I × the range-windowed
    /// inverse square law (× the cone factor for a spot). Zero for a sun.
    fn illuminance(&self, dir: Vec3, d2: f32) -> Vec3 {
        match *self {
            TraceLight::Directional { .. } => Vec3::ZERO,
            TraceLight::Point {
                intensity,
                inv_range2,
                ..
            } => intensity * distance_attenuation(d2, inv_range2),
            TraceLight::Spot {
                axis,
                intensity,
                inv_range2,
                cone_scale,
                cone_offset,
                ..
            } => {
                intensity
                    * distance_attenuation(d2, inv_range2)
                    * spot_attenuation(dir.dot(axis), cone_scale, cone_offset)
            }
        }
    }
}

/// The uniform number in [0, 1) that decides whether a ray passes a blended surface:
/// a hash of the ray (its origin, direction and the hit distance, as bits) through
/// SplitMix64's finalizer (Steele et al. 2014). Rays differ from sample to sample, so the
/// draws are independent across paths, and a render stays a function of its seed.
fn transparency_draw(origin: Vec3, dir: Vec3, t: f32) -> f32 {
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15;
    for x in [origin.x, origin.y, origin.z, dir.x, dir.y, dir.z, t] {
        h = (h ^ u64::from(x.to_bits())).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h ^= h >> 31;
    }
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^= h >> 31;
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// Which part of a transmissive material a path meets: with probability
/// (1 − metallic) × transmission its dielectric interface (`Some` transmission), else the
/// rest of it, an opaque material whose metallic is renormalised to
/// metallic / (1 − that probability), so the expectation is glTF's mix of the metal and
/// the dielectric base. Opaque materials draw nothing from `rng`.
fn transmission_choice(
    m: &TraceMaterial,
    rng: &mut Rng,
) -> (TraceMaterial, Option<crate::scene::Transmission>) {
    let Some(tr) = m.transmission.filter(|t| t.factor > 0.0) else {
        return (*m, None);
    };
    let p = (1.0 - m.metallic.clamp(0.0, 1.0)) * tr.factor.clamp(0.0, 1.0);
    if rng.uniform() < p {
        (*m, Some(tr))
    } else {
        let opaque = TraceMaterial {
            metallic: (m.metallic / (1.0 - p).max(1e-6)).clamp(0.0, 1.0),
            ..*m
        };
        (opaque, None)
    }
}

/// Where a ray along `l` leaves the surface at `p`: lifted by `offset` (the geometric
/// normal turned to the viewer, scaled) to the viewer's side, or, for a direction
/// through a translucent `bsdf`, to the other side. `None` where a translucent surface's
/// shading and geometric normals disagree on the side `l` is on (smooth or mapped normals
/// at grazing angles): light reflected by the lobes must not leave through the back, nor
/// transmitted light through the front.
fn departure(p: Vec3, offset: Vec3, l: Vec3, bsdf: &Bsdf) -> Option<Vec3> {
    if !bsdf.transmits() {
        return Some(p + offset);
    }
    let through = l.dot(offset) < 0.0;
    (through == (bsdf.n().dot(l) < 0.0)).then_some(if through { p - offset } else { p + offset })
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 { a2 / (a2 + b2) } else { 0.0 }
}

impl TraceScene {
    /// Radiance leaving the environment towards the scene along `-dir`.
    fn environment_radiance(&self, dir: Vec3) -> Vec3 {
        match &self.environment {
            TraceEnvironment::None => Vec3::ZERO,
            TraceEnvironment::Uniform(c) => *c,
            TraceEnvironment::Image(img) => img.radiance(dir),
        }
    }

    /// Density with which next-event estimation picks `dir` at a surface of normal `n`.
    fn environment_pdf(&self, dir: Vec3, n: Vec3) -> f32 {
        match &self.environment {
            TraceEnvironment::None => 0.0,
            TraceEnvironment::Uniform(_) => n.dot(dir).max(0.0) / PI,
            TraceEnvironment::Image(img) => img.pdf(dir),
        }
    }

    /// A next-event direction towards the environment: direction, radiance, density.
    fn sample_environment(&self, n: Vec3, rng: &mut Rng) -> Option<(Vec3, Vec3, f32)> {
        match &self.environment {
            TraceEnvironment::None => None,
            TraceEnvironment::Uniform(c) => {
                let d = concentric_disk(rng.pair());
                let l = basis(n) * Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt());
                let pdf = n.dot(l).max(0.0) / PI;
                (pdf > 0.0).then_some((l, *c, pdf))
            }
            TraceEnvironment::Image(img) => img.sample(rng.pair()),
        }
    }

    /// Whether light connections reach `light`: a point or spot light whose shadow rays
    /// are tested (a light the frame lets through walls has no light rays to trace).
    fn connectable(&self, light: &TraceLight) -> bool {
        self.light_connections
            && light.emitter().is_some()
            && (light.casts_shadows() || self.light_visibility == LightVisibility::Physical)
    }

    /// How many lights [`TraceScene::bounced_light`] chooses from, uniformly.
    fn connectable_count(&self) -> usize {
        self.lights.iter().filter(|l| self.connectable(l)).count()
    }

    /// Density over the area of a surface at `y` (1/m²) with which a light connection
    /// reaches `y` from `light`, one of `count` connectable lights: the light's emission
    /// density towards `y` (along `dir`, unit, away from the light) × cos θ_y / d².
    /// `cos_y` is the cosine between the direction to the light and `y`'s geometric
    /// normal, `d2` the squared distance (m²).
    fn connection_pdf(light: &TraceLight, count: usize, dir: Vec3, cos_y: f32, d2: f32) -> f32 {
        light.emitter().map_or(0.0, |emitter| {
            emitter.pdf(dir) * cos_y.abs() / (d2.max(1e-12) * count.max(1) as f32)
        })
    }

    /// Light from every punctual light and the environment reaching `p` and reflected
    /// towards `v`: [`TraceScene::direct_lights`] and [`TraceScene::direct_environment`].
    fn direct(
        &self,
        p: Vec3,
        offset: Vec3,
        v: Vec3,
        bsdf: &Bsdf,
        arrival: Option<Arrival>,
        rng: &mut Rng,
    ) -> Vec3 {
        self.direct_lights(p, offset, v, bsdf, arrival, rng)
            + self.direct_environment(p, offset, v, bsdf, rng)
    }

    /// Light from every punctual light reaching `p` and reflected towards `v`. `arrival`
    /// is set when the path reached `p` by sampling the BSDF of a surface before it: the
    /// light of connectable lights is then weighted against the light connections from
    /// that surface ([`TraceScene::bounced_light`]).
    fn direct_lights(
        &self,
        p: Vec3,
        offset: Vec3,
        v: Vec3,
        bsdf: &Bsdf,
        arrival: Option<Arrival>,
        rng: &mut Rng,
    ) -> Vec3 {
        let count = if arrival.is_some() {
            self.connectable_count()
        } else {
            0
        };
        let mut sum = Vec3::ZERO;
        // Unit direction and squared distance (m²) from `p` to a light at `position`.
        let towards = |position: Vec3| {
            let to_light = position - p;
            let d2 = to_light.length_squared();
            (to_light.normalize_or(bsdf.n()), d2)
        };
        for light in &self.lights {
            let (l, e, distance) = match *light {
                TraceLight::Directional {
                    direction_to_light,
                    illuminance,
                    tan_angular_radius: tan_radius,
                    ..
                } => {
                    let axis = direction_to_light.normalize_or(Vec3::Y);
                    // A shadowed sun has its disc (tan of the angular radius): sample it
                    // uniformly, so its shadows get their true penumbrae. E stays the
                    // illuminance of the whole disc.
                    let l = if tan_radius > 0.0 && tan_radius.is_finite() {
                        let cos_max = 1.0 / (1.0 + tan_radius * tan_radius).sqrt();
                        uniform_cone(axis, cos_max, rng.pair())
                    } else {
                        axis
                    };
                    (l, illuminance, f32::MAX)
                }
                TraceLight::Point { position_m, .. } | TraceLight::Spot { position_m, .. } => {
                    let (l, d2) = towards(position_m);
                    (l, light.illuminance(-l, d2), d2.sqrt())
                }
            };
            if e == Vec3::ZERO || (!bsdf.transmits() && bsdf.n().dot(l) <= 0.0) {
                continue;
            }
            let f = bsdf.eval(v, l);
            let tested =
                light.casts_shadows() || self.light_visibility == LightVisibility::Physical;
            let Some(origin) = departure(p, offset, l, bsdf) else {
                continue;
            };
            if f == Vec3::ZERO || (tested && self.occluded(origin, l, distance * (1.0 - 1e-4))) {
                continue;
            }
            // Light connections reach `p` only from the side the path arrived on
            // (reflection): light through a translucent surface has no other strategy.
            let weight = match arrival {
                Some(a) if count > 0 && self.connectable(light) && a.facing.dot(l) > 0.0 => {
                    let d2 = distance * distance;
                    let pdf = Self::connection_pdf(light, count, -l, a.facing.dot(l), d2);
                    power_heuristic(a.pdf_area, pdf)
                }
                _ => 1.0,
            };
            sum += f * e * weight;
        }
        sum
    }

    /// The environment's light reaching `p` and reflected towards `v`, by one sample of
    /// the environment weighted against sampling `bsdf` (power heuristic).
    fn direct_environment(
        &self,
        p: Vec3,
        offset: Vec3,
        v: Vec3,
        bsdf: &Bsdf,
        rng: &mut Rng,
    ) -> Vec3 {
        let mut sum = Vec3::ZERO;
        if let Some((l, radiance, pdf)) = self.sample_environment(bsdf.n(), rng) {
            let f = bsdf.eval(v, l);
            let origin = departure(p, offset, l, bsdf);
            if let Some(origin) = origin.filter(|_| f != Vec3::ZERO)
                && !self.occluded(origin, l, f32::MAX)
            {
                let w = power_heuristic(pdf, bsdf.pdf(v, l));
                sum += f * radiance * (w / pdf);
            }
        }
        sum
    }

    /// Light that reaches `p` after one bounce off another surface, by a light
    /// connection: one of the connectable lights, chosen uniformly, sends a ray into its
    /// cone of emission; the surface y it meets is connected to `p` by a shadow ray, and
    /// the light y reflects towards `p` is reflected towards `v`. Weighted by the power
    /// heuristic against reaching y by sampling `bsdf` (the light [`TraceScene::direct`]
    /// finds at y with `arrival` set). `facing` is `p`'s geometric normal turned to `v`.
    fn bounced_light(
        &self,
        p: Vec3,
        offset: Vec3,
        facing: Vec3,
        v: Vec3,
        bsdf: &Bsdf,
        rng: &mut Rng,
    ) -> Option<Vec3> {
        let count = self.connectable_count();
        if count == 0 {
            return None;
        }
        let pick = ((rng.uniform() * count as f32) as usize).min(count - 1);
        let light = self
            .lights
            .iter()
            .filter(|l| self.connectable(l))
            .nth(pick)?;
        let emitter = light.emitter()?;
        let dir = uniform_cone(emitter.axis, emitter.cos_max, rng.pair());
        let (t_light, t, surface) = self.trace(emitter.position, dir)?;
        let y = emitter.position + dir * t_light;
        let e = light.illuminance(dir, t_light * t_light);
        // y's side facing the light, which `p` must be on: reflection only.
        let (facing_y, n_y) = self.facing_normals(t, surface.normal, -dir);
        let origin = p + offset;
        let y_lifted = y + facing_y * (1e-4 * (1.0 + y.abs().max_element()));
        let to_y = y_lifted - origin;
        let d2 = to_y.length_squared();
        let d = d2.sqrt();
        let l = to_y / d;
        let cos_y = facing_y.dot(-l);
        if e == Vec3::ZERO || d <= 0.0 || !d.is_finite() || cos_y <= 0.0 || l.dot(facing) <= 0.0 {
            return None;
        }
        let f_p = bsdf.eval(v, l);
        if f_p == Vec3::ZERO {
            return None;
        }
        let bsdf_y = self.bsdf(n_y, facing_y, &surface, &surface.material, -l);
        let f_y = bsdf_y.eval(-l, -dir);
        if f_y == Vec3::ZERO || self.occluded(origin, l, d * (1.0 - 1e-4)) {
            return None;
        }
        let pdf = Self::connection_pdf(light, count, dir, facing_y.dot(-dir), t_light * t_light);
        let bsdf_pdf = bsdf.pdf(v, l) * cos_y / d2;
        let weight = power_heuristic(pdf, bsdf_pdf);
        Some(f_p * f_y * e * (cos_y / d2) * (weight / pdf))
    }

    /// The camera ray through image position `pixel` (pixels from the top-left) of an
    /// image `size`, with lens sample `lens`.
    pub fn camera_ray(&self, pixel: Vec2, size: Vec2, lens: Vec2) -> (Vec3, Vec3) {
        let c = &self.camera;
        let ndc = Vec2::new(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
        let near = c.world_from_clip * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let dir = (near.truncate() / near.w - c.position).normalize_or(c.basis.z_axis);
        match c.lens {
            Some((radius, focus)) if radius > 0.0 => {
                let d = concentric_disk(lens) * radius;
                let origin = c.position + c.basis.x_axis * d.x + c.basis.y_axis * d.y;
                if focus.is_finite() {
                    let target = c.position + dir * (focus / dir.dot(c.basis.z_axis).max(1e-6));
                    (origin, (target - origin).normalize_or(dir))
                } else {
                    (origin, dir)
                }
            }
            _ => (c.position, dir),
        }
    }

    /// The closest surface along the ray that stops it: masked-out texels are passed
    /// through, as the G-buffer discards them, and a blended surface of coverage α with
    /// probability 1 − α (stochastic transparency, Enderton et al. 2010: its expectation
    /// is α × the surface + (1 − α) × what lies behind, the rasterizer's "over"). Up to 64
    /// surfaces are passed. Returns the hit distance from `origin`, the triangle and the
    /// surface there.
    fn trace(&self, origin: Vec3, dir: Vec3) -> Option<(f32, usize, SurfacePoint)> {
        let mut start = 0.0;
        for _ in 0..64 {
            let hit = self.bvh.closest(origin, dir, start, f32::MAX)?;
            let t = hit.triangle as usize;
            let surface = self.surface(t, hit.u, hit.v);
            let masked_out = surface
                .alpha_cutoff
                .is_some_and(|cutoff| surface.alpha < cutoff);
            let passed =
                surface.material.blend && transparency_draw(origin, dir, hit.t) >= surface.alpha;
            if !(masked_out || passed) {
                return Some((hit.t, t, surface));
            }
            start = hit.t * (1.0 + 1e-5) + 1e-5;
        }
        None
    }

    /// Whether a surface that stops the ray (`TraceScene::trace`) lies along it from
    /// `origin` closer than `t_max`: masked-out texels let light through, as the shadow
    /// pass drops them, and blended surfaces 1 − α of it on average. Any hit is enough
    /// where no material masks or blends.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        self.bvh.occluded(origin, dir, 0.0, t_max)
            && (!self.masked || self.trace(origin, dir).is_some_and(|(t, _, _)| t < t_max))
    }

    /// Triangle `t`'s unit geometric normal by its winding (counter-clockwise seen from
    /// the outside of a closed mesh, as glTF winds its triangles).
    fn geometric_normal(&self, t: usize) -> Vec3 {
        let tri = self.bvh.triangles()[t];
        (tri.p[1] - tri.p[0])
            .cross(tri.p[2] - tri.p[0])
            .normalize_or(Vec3::Z)
    }

    /// The fraction of light left at `hit`, reached along `dir`, of what entered the
    /// volume behind it: Beer–Lambert over the distance travelled where the ray leaves a
    /// transmissive volume (it meets the surface from the inside), else 1.
    fn absorption(&self, hit: &(f32, usize, SurfacePoint), dir: Vec3) -> Vec3 {
        let (distance, t, surface) = hit;
        match surface.material.transmission {
            Some(tr) if tr.thickness_m > 0.0 && self.geometric_normal(*t).dot(dir) > 0.0 => {
                crate::shading::transmission::volume_transmittance(
                    tr.attenuation_color,
                    tr.attenuation_distance_m,
                    *distance,
                )
            }
            _ => Vec3::ONE,
        }
    }

    /// The BSDF of `material` (the hit's, or its opaque choice) at `surface`, seen from
    /// `v`: the base about the shading normal `n`, and a sheen and a clearcoat about the
    /// mesh's own normal turned to the same side as the geometric normal `facing`.
    fn bsdf(
        &self,
        n: Vec3,
        facing: Vec3,
        surface: &SurfacePoint,
        material: &TraceMaterial,
        v: Vec3,
    ) -> Bsdf {
        let base = Bsdf::new(
            n,
            v,
            material,
            self.visibility,
            self.energy_compensation.as_ref(),
        );
        // Seen from behind (the normal turned), the handedness turns too, so that the
        // bitangent, and with it the grain, is the front's.
        let turned_over = n.dot(surface.normal) < 0.0;
        let tangent =
            surface.tangent * Vec4::new(1.0, 1.0, 1.0, if turned_over { -1.0 } else { 1.0 });
        let base = match material.anisotropy {
            Some(a) => base.with_anisotropy(tangent, a, v, self.energy_compensation.is_some()),
            None => base,
        };
        let n_sheen = turned(surface.layer_normal, facing);
        let base = match material.sheen {
            Some(sheen) => base.with_sheen(n_sheen, v, (sheen.color, sheen.perceptual_roughness)),
            None => base,
        };
        match (material.clearcoat, self.coat_albedo.as_ref()) {
            (Some(coat), Some(table)) => base.with_coat(
                turned(surface.coat_normal, facing),
                v,
                (coat.factor, coat.perceptual_roughness),
                table,
                self.energy_compensation.as_ref(),
            ),
            _ => base,
        }
    }

    /// The pre-exposed light hit `hit` emits back along the ray direction `dir`: its
    /// material's emission ([`TraceMaterial::emitted`]), dimmed by its sheen and coat as
    /// the rasterizer's layers pass dims everything beneath them.
    fn emitted(&self, hit: &(f32, usize, SurfacePoint), dir: Vec3) -> Vec3 {
        let (_, t, surface) = hit;
        let m = &surface.material;
        let e = m.emitted();
        if e == Vec3::ZERO || (m.clearcoat.is_none() && m.sheen.is_none()) {
            return e;
        }
        let v = -dir;
        let (facing, n) = self.facing_normals(*t, surface.normal, v);
        e * self.bsdf(n, facing, surface, m, v).through_layers()
    }

    /// The geometric and shading normals of triangle `t` (shading normal `normal`) turned
    /// to the side `v` comes from: (geometric, shading).
    fn facing_normals(&self, t: usize, normal: Vec3, v: Vec3) -> (Vec3, Vec3) {
        let tri = self.bvh.triangles()[t];
        let ng = (tri.p[1] - tri.p[0])
            .cross(tri.p[2] - tri.p[0])
            .normalize_or(Vec3::Z);
        let facing = if ng.dot(v) < 0.0 { -ng } else { ng };
        (facing, turned(normal, facing))
    }

    /// One sample of the ambient occlusion at the first surface along a camera ray: a
    /// cosine-distributed direction about the shading normal (turned to the viewer), and
    /// 1 minus the falloff weight ([`crate::shading::ambient_occlusion::ao_falloff`]) of the first
    /// surface it meets within `radius_m` metres (a direction below the geometric surface
    /// is occluded at once). Its mean is the cosine-weighted visibility that the AO pass
    /// estimates from the depth buffer; a ray that meets nothing gives 1.
    pub fn ambient_occlusion(&self, origin: Vec3, dir: Vec3, radius_m: f32, rng: &mut Rng) -> f32 {
        let Some((distance, t, surface)) = self.trace(origin, dir) else {
            return 1.0;
        };
        let p = origin + dir * distance;
        let (facing, n) = self.facing_normals(t, surface.normal, -dir);
        let d = concentric_disk(rng.pair());
        let l = basis(n) * Vec3::new(d.x, d.y, (1.0 - d.length_squared()).max(0.0).sqrt());
        if l.dot(facing) <= 0.0 {
            return 0.0;
        }
        let offset = facing * (1e-4 * (1.0 + p.abs().max_element()));
        match self.trace(p + offset, l) {
            Some((hit, _, _)) => 1.0 - crate::shading::ambient_occlusion::ao_falloff(hit, radius_m),
            None => 1.0,
        }
    }

    /// One path's radiance (pre-exposed) along a camera ray. It can be NaN or infinite
    /// (finite terms that overflow f32 when added): [`super::render`] counts and drops
    /// such paths.
    pub fn radiance(&self, origin: Vec3, dir: Vec3, max_bounces: u32, rng: &mut Rng) -> Vec3 {
        let Some(mut hit) = self.trace(origin, dir) else {
            return self
                .background
                .unwrap_or_else(|| self.environment_radiance(dir));
        };
        let mut ray_origin = origin;
        let mut ray_dir = dir;
        let mut throughput = Vec3::ONE;
        let mut radiance = self.emitted(&hit, dir);
        // Density over the area of the current hit with which the previous surface's BSDF
        // sample reached it (None at the first hit).
        let mut arrival_pdf: Option<f32> = None;
        // The colour channel a path follows once a dispersive interface has split it.
        let mut channel: Option<usize> = None;
        for bounce in 0..max_bounces {
            let (distance, t, surface) = hit;
            // An unlit surface's colour was counted on arrival; it scatters nothing.
            if surface.material.unlit {
                break;
            }
            let p = ray_origin + ray_dir * distance;
            let v = -ray_dir;
            let (facing, n) = self.facing_normals(t, surface.normal, v);
            let offset = facing * (1e-4 * (1.0 + p.abs().max_element()));
            let arrival = arrival_pdf.map(|pdf_area| Arrival { pdf_area, facing });
            let (material, transmission) = transmission_choice(&surface.material, rng);
            // Through the interface: its specular reflection of the lights, then the
            // sampled reflection or refraction, followed without light connections.
            if let Some(tr) = transmission {
                let tr = if tr.dispersion > 0.0 {
                    let c = match channel {
                        Some(c) => c,
                        None => {
                            let c = ((rng.uniform() * 3.0) as usize).min(2);
                            throughput *= Vec3::AXES[c] * 3.0;
                            channel = Some(c);
                            c
                        }
                    };
                    let iors = crate::shading::transmission::dispersion_iors(tr.ior, tr.dispersion);
                    crate::scene::Transmission { ior: iors[c], ..tr }
                } else {
                    tr
                };
                let entering = self.geometric_normal(t).dot(v) > 0.0;
                // Its sheen and clearcoat, its tint and film are on its outside.
                let layered = TraceMaterial {
                    base_color: Vec3::ZERO,
                    metallic: 0.0,
                    sheen: material.sheen.filter(|_| entering),
                    clearcoat: material.clearcoat.filter(|_| entering),
                    specular_tint: material.specular_tint.filter(|_| entering),
                    iridescence: material.iridescence.filter(|_| entering),
                    // A diffuse transmission belongs to the rest of the material.
                    diffuse_transmission: None,
                    ..material
                };
                let bsdf = self.bsdf(n, facing, &surface, &layered, v);
                radiance += throughput * self.direct_lights(p, offset, v, &bsdf, arrival, rng);
                // Under layers, a layer's reflection is sampled with a probability
                // `layer_p`; else the interface, whose reflected and refracted light
                // leaves through the layers by `through`.
                let through = bsdf.through_layers();
                let layer_p = if through < 1.0 {
                    lobe_probability(1.0 - through, through)
                } else {
                    0.0
                };
                if layer_p > 0.0 && rng.uniform() < layer_p {
                    let layers_only = TraceMaterial {
                        specular_level: 0.0,
                        ..layered
                    };
                    let layers = self.bsdf(n, facing, &surface, &layers_only, v);
                    let Some((l, weight, _)) = layers.sample(v, rng) else {
                        break;
                    };
                    if l.dot(facing) <= 0.0 {
                        break;
                    }
                    throughput *= weight / layer_p;
                    ray_origin = p + offset;
                    ray_dir = l;
                } else {
                    let (frame, alphas) = bsdf.lobe_frame();
                    let interface = super::dielectric::Interface {
                        frame,
                        alphas,
                        base: material.base_color,
                        entering,
                        lobe: bsdf.tinted_interface(),
                    };
                    let Some(scattered) = super::dielectric::sample(&tr, v, &interface, rng) else {
                        break;
                    };
                    throughput *= scattered.weight * (through / (1.0 - layer_p));
                    ray_origin = if scattered.transmitted {
                        p - offset
                    } else {
                        p + offset
                    };
                    ray_dir = scattered.l;
                }
                arrival_pdf = None;
                match self.trace(ray_origin, ray_dir) {
                    None => {
                        radiance += throughput * self.environment_radiance(ray_dir);
                        break;
                    }
                    Some(next) => {
                        throughput *= self.absorption(&next, ray_dir);
                        radiance += throughput * self.emitted(&next, ray_dir);
                        hit = next;
                    }
                }
            } else {
                let bsdf = self.bsdf(n, facing, &surface, &material, v);
                radiance += throughput * self.direct(p, offset, v, &bsdf, arrival, rng);
                if bounce + 1 < max_bounces
                    && let Some(bounced) = self.bounced_light(p, offset, facing, v, &bsdf, rng)
                {
                    radiance += throughput * bounced;
                }
                let Some((l, weight, pdf)) = bsdf.sample(v, rng) else {
                    break;
                };
                // Through the surface only by a diffuse transmission.
                let through = l.dot(facing) <= 0.0;
                if through && !bsdf.transmits() {
                    break;
                }
                let Some(origin) = departure(p, offset, l, &bsdf) else {
                    break;
                };
                throughput *= weight;
                ray_origin = origin;
                ray_dir = l;
                match self.trace(ray_origin, ray_dir) {
                    None => {
                        let w = power_heuristic(pdf, self.environment_pdf(l, n));
                        radiance += throughput * self.environment_radiance(l) * w;
                        break;
                    }
                    Some(next) => {
                        throughput *= self.absorption(&next, l);
                        radiance += throughput * self.emitted(&next, l);
                        let (next_facing, _) = self.facing_normals(next.1, next.2.normal, -l);
                        // Light connections reach the next surface by reflection at this
                        // one only: a path through it is not weighted against them.
                        arrival_pdf = (!through).then(|| {
                            pdf * next_facing.dot(-l).abs() / (next.0 * next.0).max(1e-12)
                        });
                        hit = next;
                    }
                }
            }
            if bounce >= 3 {
                let q = throughput.max_element().min(0.95);
                if rng.uniform() >= q {
                    break;
                }
                throughput /= q;
            }
        }
        radiance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vndf_directions_are_reflections_above_the_surface() {
        let mut rng = Rng::new(1, 2, 3);
        let v = Vec3::new(0.6, 0.0, 0.8);
        for alpha in [0.01f32, 0.25, 1.0] {
            for _ in 0..1000 {
                let h = crate::shading::ibl::sample_ggx_vndf(v, alpha, rng.pair());
                assert!(h.is_normalized() && h.z >= 0.0, "{h}");
                assert!(v.dot(h) >= -1e-5, "visible normals face v");
            }
        }
    }

    #[test]
    fn generators_are_deterministic_and_uniform() {
        let a: Vec<u32> = (0..4).map(|_| Rng::new(7, 11, 13).next_u32()).collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        let mut rng = Rng::new(7, 11, 13);
        let mean = (0..100_000).map(|_| rng.uniform()).sum::<f32>() / 100_000.0;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
        assert_ne!(
            Rng::new(7, 11, 13).next_u32(),
            Rng::new(7, 12, 13).next_u32()
        );
    }
}

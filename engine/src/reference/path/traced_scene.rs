//! The scene as the path tracer sees it: world-space triangles in a BVH, per-triangle
//! material, the lights, and the environment with an importance-sampling table, built
//! from a [`TraceInput`] (the rasterizer's own extracted frame in plain types, so both
//! use the same instances, materials, lights, exposure and camera).

use super::bvh::{Bvh, Triangle};
use super::textures::TraceMaps;
use crate::scene::texture::normal_from_map;
use crate::scene::{Environment, EnvironmentSource, MaterialMaps, MeshHandle, Meshes};
use crate::shading::anisotropy::textured_anisotropy;
use crate::shading::brdf::VisibilityModel;
use crate::shading::ibl::{equirect_direction, equirect_uv, rotate_y};
use crate::shading::iridescence::film_thickness;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use std::f32::consts::PI;

/// A light as the path tracer samples it, pre-exposed like the rasterizer's lights:
/// colour × intensity × exposure, as one f32 product.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TraceLight {
    /// A light at infinity (the sun).
    Directional {
        /// Unit vector from the scene towards the light.
        direction_to_light: Vec3,
        /// Illuminance × linear colour × exposure (pre-exposed lux, rgb).
        illuminance: Vec3,
        /// Tangent of the angular radius of the sun's disc, which shadow rays sample
        /// uniformly (true penumbrae; the illuminance is that of the whole disc); 0 when
        /// the rasterizer draws no shadow for this light, which then shines from
        /// `direction_to_light` alone.
        tan_angular_radius: f32,
        /// Whether the frame draws this light's shadow.
        casts_shadows: bool,
    },
    /// A point light (a point: its radius only softens the rasterizer's shadows).
    Point {
        /// Position (m).
        position_m: Vec3,
        /// Luminous intensity × linear colour × exposure (pre-exposed cd, rgb).
        intensity: Vec3,
        /// 1 / range² (1/m²) of the range window; 0: unlimited range.
        inv_range2: f32,
        /// Whether the frame draws this light's shadow.
        casts_shadows: bool,
    },
    /// A spot light: a point light inside a cone.
    Spot {
        /// Position (m).
        position_m: Vec3,
        /// Unit vector along the cone's axis, away from the light.
        axis: Vec3,
        /// Luminous intensity × linear colour × exposure (pre-exposed cd, rgb).
        intensity: Vec3,
        /// 1 / range² (1/m²) of the range window; 0: unlimited range.
        inv_range2: f32,
        /// Cone scale (dimensionless): the cone factor is
        /// `saturate(cos θ · scale + offset)²` ([`crate::shading::punctual::spot_scale_offset`]).
        cone_scale: f32,
        /// Cone offset (dimensionless).
        cone_offset: f32,
        /// Whether the frame draws this light's shadow.
        casts_shadows: bool,
    },
}

impl TraceLight {
    /// Whether the frame draws this light's shadow.
    pub fn casts_shadows(&self) -> bool {
        match *self {
            TraceLight::Directional { casts_shadows, .. }
            | TraceLight::Point { casts_shadows, .. }
            | TraceLight::Spot { casts_shadows, .. } => casts_shadows,
        }
    }
}

crate::choice::choices! {
/// Which lights the path tracer's shadow rays test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightVisibility: "light visibility" {
    /// Every light is occluded by the geometry between it and the surface: the physical
    /// truth.
    #[default]
    Physical = "physical",
    /// Only the lights whose shadow the frame draws are occluded; the others light every
    /// surface facing them, as the rasterizer does. It judges a frame against the same
    /// visibility, separating the cost of unshadowed lights from the rest of the error.
    AsFrame = "frame",
}
}

/// One drawn mesh instance, with the factors of its material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceInstance {
    /// The mesh.
    pub mesh: MeshHandle,
    /// World from local (m).
    pub world_from_local: Mat4,
    /// Normal matrix: inverse-transpose of the upper 3×3 of `world_from_local`.
    pub normal_matrix: Mat3,
    /// Its material's factors as given (clamped into range when traced:
    /// [`TraceMaterial::clamped`]); `maps` indexes [`TraceInput::material_maps`].
    pub material: TraceMaterial,
}

/// What one frame draws, in the path tracer's own types: the rasterizer's extracted frame
/// (instances, material maps, lights, camera, exposure, background), pre-exposed.
#[derive(Clone, Debug)]
pub struct TraceInput {
    /// Instances, in the rasterizer's draw order.
    pub instances: Vec<TraceInstance>,
    /// The distinct material maps of the instances.
    pub material_maps: Vec<MaterialMaps>,
    /// Lights, in the rasterizer's order.
    pub lights: Vec<TraceLight>,
    /// The camera.
    pub camera: TraceCamera,
    /// Exposure multiplier (dimensionless; luminance × exposure = pre-exposed value), for
    /// the environment.
    pub exposure: f32,
    /// Background luminance × exposure (pre-exposed cd/m², rgb): what a primary ray that
    /// misses shows unless the environment is drawn as the background.
    pub background: Vec3,
}

/// A surface's material, pre-exposed like the rasterizer's instance data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceMaterial {
    /// Linear base colour.
    pub base_color: Vec3,
    /// Metallic 0..1.
    pub metallic: f32,
    /// Perceptual roughness.
    pub roughness: f32,
    /// Dielectric specular level (F0 = 0.08 × level).
    pub specular_level: f32,
    /// Emitted luminance × exposure.
    pub emissive: Vec3,
    /// Index into [`TraceScene::maps`] (the same order as [`TraceInput::material_maps`])
    /// of its textures, if any.
    pub maps: Option<u32>,
    /// The base colour factor's alpha: the coverage (0..1) before the texel's and the
    /// vertex colour's.
    pub alpha: f32,
    /// Alpha-blended ([`crate::scene::Material::blend`]): rays pass through with
    /// probability 1 − alpha (stochastic transparency).
    pub blend: bool,
    /// Transmission and volume, the thickness in world metres (the path tracer follows
    /// the geometry instead; a thickness of 0 marks a thin wall).
    pub transmission: Option<crate::scene::Transmission>,
    /// Unlit ([`crate::scene::Material::unlit`]): the surface emits its base colour
    /// (pre-exposed, [`TraceMaterial::emitted`]) and scatters nothing; a path ends there.
    pub unlit: bool,
    /// The clearcoat over an opaque surface ([`crate::scene::Material::coat`]), on the
    /// mesh's own normal ([`SurfacePoint::coat_normal`]).
    pub clearcoat: Option<crate::scene::Clearcoat>,
    /// The sheen over an opaque surface ([`crate::scene::Material::layer_sheen`]), on
    /// the mesh's own normal.
    pub sheen: Option<crate::scene::Sheen>,
    /// The base's anisotropy ([`crate::scene::Material::anisotropic`]), along a direction
    /// from the interpolated tangent ([`SurfacePoint::tangent`]).
    pub anisotropy: Option<crate::scene::Anisotropy>,
    /// The dielectric F0's tint ([`crate::scene::Material::tint`]); `None`: untinted.
    pub specular_tint: Option<Vec3>,
    /// The iridescent film ([`crate::scene::Material::iridescent`]); `None`: no film.
    pub iridescence: Option<crate::scene::Iridescence>,
    /// The diffuse transmission ([`crate::scene::Material::translucent`]); `None`: none.
    pub diffuse_transmission: Option<crate::scene::DiffuseTransmission>,
}

impl TraceMaterial {
    /// The pre-exposed luminance the surface emits: its base colour if it is unlit (as
    /// the lighting pass shows it), else its emissive.
    pub fn emitted(&self) -> Vec3 {
        if self.unlit {
            self.base_color
        } else {
            self.emissive
        }
    }

    /// The factors clamped into the ranges the BRDF takes: base colour, metallic and
    /// specular level into 0..1, roughness by [`crate::shading::brdf::clamp_perceptual_roughness`].
    pub fn clamped(self) -> TraceMaterial {
        TraceMaterial {
            base_color: self.base_color.clamp(Vec3::ZERO, Vec3::ONE),
            metallic: self.metallic.clamp(0.0, 1.0),
            roughness: crate::shading::brdf::clamp_perceptual_roughness(self.roughness),
            specular_level: self.specular_level.clamp(0.0, 1.0),
            alpha: if self.alpha.is_nan() {
                1.0
            } else {
                self.alpha.clamp(0.0, 1.0)
            },
            clearcoat: self
                .clearcoat
                .map(crate::scene::Clearcoat::clamped)
                .filter(|c| c.factor > 0.0),
            sheen: self
                .sheen
                .map(crate::scene::Sheen::clamped)
                .filter(|s| s.color.max_element() > 0.0),
            anisotropy: self
                .anisotropy
                .map(crate::scene::Anisotropy::clamped)
                .filter(|a| a.strength > 0.0),
            specular_tint: self.specular_tint.map(crate::shading::brdf::clamp_tint),
            iridescence: self
                .iridescence
                .map(crate::scene::Iridescence::clamped)
                .filter(|f| f.factor > 0.0),
            diffuse_transmission: self
                .diffuse_transmission
                .map(crate::scene::DiffuseTransmission::clamped)
                .filter(|d| d.factor > 0.0),
            ..self
        }
    }
}

/// Scales `material`'s layers by `maps`' extension textures at (uv0, uv1), as the layers
/// and transparent passes do (`extension_texel` in `material_maps.wgsl`).
fn apply_extensions(maps: &TraceMaps, material: &mut TraceMaterial, uv0: Vec2, uv1: Vec2) {
    let at = |k: usize| maps.extension(k, uv0, uv1);
    let one = Vec4::ONE;
    if let Some(t) = material.transmission.as_mut() {
        t.factor *= at(0).unwrap_or(one).x;
        t.thickness_m *= at(1).unwrap_or(one).y;
    }
    if let Some(c) = material.clearcoat.as_mut() {
        c.factor *= at(2).unwrap_or(one).x;
        // Clamped again, as the layers pass clamps the product.
        c.perceptual_roughness = crate::shading::brdf::clamp_perceptual_roughness(
            c.perceptual_roughness * at(3).unwrap_or(one).y,
        );
    }
    if let Some(sh) = material.sheen.as_mut() {
        sh.color *= at(4).unwrap_or(one).truncate();
        sh.perceptual_roughness *= at(5).unwrap_or(one).w;
    }
    if let (Some(a), Some(texel)) = (material.anisotropy.as_mut(), at(6)) {
        let (sin, cos) = a.rotation_rad.sin_cos();
        let (strength, d) = textured_anisotropy(a.strength, Vec2::new(cos, sin), texel.truncate());
        a.strength = strength;
        a.rotation_rad = d.y.atan2(d.x);
    }
    if let Some(f) = material.iridescence.as_mut() {
        f.factor *= at(7).unwrap_or(one).x;
        if let Some(texel) = at(8) {
            f.thickness_nm = film_thickness(maps.thickness_min_nm, f.thickness_nm, texel.y);
        }
    }
    if let Some(d) = material.diffuse_transmission.as_mut() {
        d.factor *= at(9).unwrap_or(one).w;
        d.color *= at(10).unwrap_or(one).truncate();
    }
    // Only a relit base has a tint (white where only textures set it).
    if let Some(tint) = material.specular_tint.as_mut() {
        material.specular_level *= at(11).unwrap_or(one).w;
        *tint *= at(12).unwrap_or(one).truncate();
    }
}

/// A triangle corner's shading attributes (world space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Corner {
    /// Unit normal.
    pub normal: Vec3,
    /// Tangent (xyz) and handedness (w).
    pub tangent: Vec4,
    /// Texture coordinates, sets 0 and 1.
    pub uv: [Vec2; 2],
    /// Vertex colour (linear RGBA).
    pub color: Vec4,
}

/// The environment, pre-exposed.
#[derive(Clone, Debug)]
pub enum TraceEnvironment {
    /// No environment: nothing arrives from the sky.
    None,
    /// The same radiance from every direction.
    Uniform(Vec3),
    /// An equirectangular image with its sampling table.
    Image(EnvironmentImage),
}

/// An equirectangular environment and the tables that sample it in proportion to
/// luminance × sin θ.
#[derive(Clone, Debug)]
pub struct EnvironmentImage {
    width: usize,
    height: usize,
    texels: Vec<Vec3>,
    rotation: f32,
    /// Cumulative row weights (height + 1 entries, last = 1).
    rows: Vec<f32>,
    /// Per row, cumulative texel weights (width + 1 entries each, last = 1).
    columns: Vec<f32>,
    /// Sum of all weights before normalisation.
    total: f32,
}

fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Index `i` with `cdf[i] ≤ u < cdf[i + 1]` in a cumulative table starting at 0.
fn find(cdf: &[f32], u: f32) -> usize {
    cdf.partition_point(|&c| c <= u)
        .saturating_sub(1)
        .min(cdf.len().saturating_sub(2))
}

/// An [`EnvironmentImage`]'s texels and sampling tables, for the GPU path tracer.
#[derive(Clone, Copy, Debug)]
pub struct EnvironmentTables<'a> {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// Rotation about +y (rad).
    pub rotation: f32,
    /// Pre-exposed radiance per texel, row by row.
    pub texels: &'a [Vec3],
    /// Cumulative row weights (height + 1 entries).
    pub rows: &'a [f32],
    /// Per row, cumulative texel weights (width + 1 entries each).
    pub columns: &'a [f32],
    /// Sum of all weights before normalisation (0: nothing to sample).
    pub total: f32,
}

impl EnvironmentImage {
    /// The texels and tables as they are.
    pub fn tables(&self) -> EnvironmentTables<'_> {
        EnvironmentTables {
            width: self.width,
            height: self.height,
            rotation: self.rotation,
            texels: &self.texels,
            rows: &self.rows,
            columns: &self.columns,
            total: self.total,
        }
    }

    fn new(width: usize, height: usize, texels: Vec<Vec3>, rotation: f32) -> Self {
        let mut columns = Vec::with_capacity(height * (width + 1));
        let mut row_sums = Vec::with_capacity(height);
        for y in 0..height {
            let sin_theta = ((y as f32 + 0.5) / height as f32 * PI).sin();
            let start = columns.len();
            columns.push(0.0);
            let mut sum = 0.0;
            for x in 0..width {
                sum += luminance(texels[y * width + x]).max(0.0) * sin_theta;
                columns.push(sum);
            }
            for c in &mut columns[start..] {
                *c = if sum > 0.0 { *c / sum } else { 0.0 };
            }
            if sum <= 0.0 {
                // A black row: uniform within the row, never chosen by the row table.
                for (k, c) in columns[start..].iter_mut().enumerate() {
                    *c = k as f32 / width as f32;
                }
            }
            row_sums.push(sum);
        }
        let total: f32 = row_sums.iter().sum();
        let mut rows = vec![0.0];
        let mut acc = 0.0;
        for s in &row_sums {
            acc += s;
            rows.push(if total > 0.0 { acc / total } else { 0.0 });
        }
        EnvironmentImage {
            width,
            height,
            texels,
            rotation,
            rows,
            columns,
            total,
        }
    }

    fn texel_index(&self, dir: Vec3) -> usize {
        let uv = equirect_uv(rotate_y(dir, -self.rotation));
        let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        y * self.width + x
    }

    /// Radiance arriving from direction `dir` (pointing away from the scene).
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        self.texels[self.texel_index(dir)]
    }

    /// Solid-angle density of [`EnvironmentImage::sample`] choosing `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        if self.total.is_nan() || self.total <= 0.0 {
            return 0.0;
        }
        let i = self.texel_index(dir);
        let y = i / self.width;
        let sin_theta = ((y as f32 + 0.5) / self.height as f32 * PI).sin();
        let weight = luminance(self.texels[i]).max(0.0) * sin_theta / self.total;
        let texels = (self.width * self.height) as f32;
        // Density over the unit square (texels × weight), then over solid angle.
        weight * texels / (2.0 * PI * PI * sin_theta.max(1e-6))
    }

    /// A direction drawn in proportion to luminance × sin θ, its radiance and density.
    pub fn sample(&self, xi: Vec2) -> Option<(Vec3, Vec3, f32)> {
        if self.total.is_nan() || self.total <= 0.0 {
            return None;
        }
        let y = find(&self.rows, xi.y);
        let row = &self.columns[y * (self.width + 1)..(y + 1) * (self.width + 1)];
        let x = find(row, xi.x);
        // A uniform point inside the chosen texel.
        let fx = (xi.x - row[x]) / (row[x + 1] - row[x]).max(1e-12);
        let fy = (xi.y - self.rows[y]) / (self.rows[y + 1] - self.rows[y]).max(1e-12);
        let uv = Vec2::new(
            (x as f32 + fx.clamp(0.0, 1.0)) / self.width as f32,
            (y as f32 + fy.clamp(0.0, 1.0)) / self.height as f32,
        );
        let dir = rotate_y(equirect_direction(uv), self.rotation);
        let pdf = self.pdf(dir);
        (pdf > 0.0).then(|| (dir, self.radiance(dir), pdf))
    }
}

/// The directional albedo E₁(n·v, r) of the specular lobe for F0 = 1 with the scene's
/// visibility term, tabulated for the multiple-scattering energy compensation
/// `1 + F0 (1/E₁ − 1)` (Kulla & Conty 2017). The rasterizer takes E₁ from its split-sum
/// table; here it is integrated for the exact BRDF the path tracer evaluates, so that a
/// white metal returns exactly the light it receives.
#[derive(Clone, Debug)]
pub struct AlbedoTable {
    size: usize,
    values: Vec<f32>,
}

impl AlbedoTable {
    /// A `size` × `size` table, `samples` GGX importance samples per entry, without
    /// Fresnel (F = 1): E₁, what the energy compensation divides by.
    pub fn new(size: usize, samples: u32, model: VisibilityModel) -> Self {
        AlbedoTable::with_f0(size, samples, model, 1.0)
    }

    /// The same for a lobe with Schlick's Fresnel of reflectance `f0` at normal incidence:
    /// the directional albedo E(n·v, r) of a dielectric specular lobe.
    pub fn with_f0(size: usize, samples: u32, model: VisibilityModel, f0: f32) -> Self {
        use crate::shading::ibl::{hammersley, importance_sample_ggx};
        let size = size.max(2);
        let mut values = Vec::with_capacity(size * size);
        for j in 0..size {
            let r = crate::shading::brdf::clamp_perceptual_roughness(j as f32 / (size - 1) as f32);
            let alpha = r * r;
            for i in 0..size {
                let n_dot_v = (i as f32 / (size - 1) as f32).max(1e-3);
                let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
                let mut sum = 0.0;
                for k in 0..samples {
                    let h = importance_sample_ggx(hammersley(k, samples), alpha);
                    let v_dot_h = v.dot(h);
                    let l = 2.0 * v_dot_h * h - v;
                    if l.z > 0.0 && v_dot_h > 0.0 {
                        // D·V·(n·l) / (D (n·h) / (4 v·h)).
                        let vis = crate::shading::brdf::visibility(model, n_dot_v, l.z, r);
                        let fresnel = crate::shading::brdf::f_schlick(Vec3::splat(f0), v_dot_h).x;
                        sum += fresnel * vis * l.z * 4.0 * v_dot_h / h.z.max(1e-6);
                    }
                }
                values.push((sum / samples as f32).clamp(1e-3, 1.0));
            }
        }
        AlbedoTable { size, values }
    }

    /// Bilinear lookup at (n·v, perceptual roughness), both clamped to [0, 1].
    pub fn lookup(&self, n_dot_v: f32, roughness: f32) -> f32 {
        let scale = (self.size - 1) as f32;
        let x = n_dot_v.clamp(0.0, 1.0) * scale;
        let y = roughness.clamp(0.0, 1.0) * scale;
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.size - 1), (y0 + 1).min(self.size - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let at = |i: usize, j: usize| self.values[j * self.size + i];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        lerp(
            lerp(at(x0, y0), at(x1, y0), fx),
            lerp(at(x0, y1), at(x1, y1), fx),
            fy,
        )
    }

    /// Entries per side.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The `size × size` entries, row by row: n·v along a row, roughness down the rows.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// `1 + F0 (1/E₁ − 1)` at (n·v, roughness).
    pub fn compensation(&self, f0: Vec3, n_dot_v: f32, roughness: f32) -> Vec3 {
        Vec3::ONE + f0 * (1.0 / self.lookup(n_dot_v, roughness) - 1.0)
    }
}

/// The camera: pixel rays from the rasterizer's own matrices, plus the thin lens.
#[derive(Clone, Copy, Debug)]
pub struct TraceCamera {
    /// World from clip (reversed Z).
    pub world_from_clip: Mat4,
    /// Eye position (m).
    pub position: Vec3,
    /// Right, up and forward unit vectors.
    pub basis: Mat3,
    /// Thin lens: aperture radius (m) and focus distance along the view axis (m).
    pub lens: Option<(f32, f32)>,
}

/// Everything the integrator needs.
pub struct TraceScene {
    /// Triangles.
    pub bvh: Bvh,
    /// Per triangle: shading attributes at the corners.
    pub corners: Vec<[Corner; 3]>,
    /// The material maps of textured materials.
    pub maps: Vec<super::textures::TraceMaps>,
    /// Whether any of `maps` masks by alpha or any material blends: shadow rays then look
    /// past the texels a mask drops and through blended surfaces
    /// ([`TraceScene::occluded`]); otherwise any hit occludes.
    pub masked: bool,
    /// Per triangle: index into `materials`.
    pub material: Vec<u32>,
    /// Materials.
    pub materials: Vec<TraceMaterial>,
    /// Lights (pre-exposed).
    pub lights: Vec<TraceLight>,
    /// The environment.
    pub environment: TraceEnvironment,
    /// What a primary ray that misses shows (pre-exposed): the environment or this colour.
    pub background: Option<Vec3>,
    /// The camera.
    pub camera: TraceCamera,
    /// The specular visibility term.
    pub visibility: VisibilityModel,
    /// Energy compensation of the specular lobe, as the rasterizer's `Quality` sets it.
    pub energy_compensation: Option<AlbedoTable>,
    /// The albedo of a GGX lobe of F0 0.04 (a clearcoat's), built only when a material
    /// has a clearcoat.
    pub coat_albedo: Option<AlbedoTable>,
    /// Which lights shadow rays test ([`LightVisibility::Physical`] unless set).
    pub light_visibility: LightVisibility,
    /// Whether paths also reach point and spot lights through a surface lit from the light
    /// (bidirectional connections, combined by MIS); true unless set. Off, the estimator is
    /// the unidirectional one, with the same expectation and more noise where a small
    /// patch near a light lights the rest.
    pub light_connections: bool,
}

impl TraceScene {
    /// Builds the scene from a frame's input.
    pub fn new(
        input: &TraceInput,
        meshes: &Meshes,
        textures: &crate::scene::Textures,
        environment: Option<&Environment>,
        quality: &crate::quality::Quality,
    ) -> TraceScene {
        let exposure = input.exposure;
        let mut triangles = Vec::new();
        let mut corners = Vec::new();
        let mut material = Vec::new();
        let mut materials = Vec::new();
        let maps: Vec<super::textures::TraceMaps> = input
            .material_maps
            .iter()
            .map(|m| super::textures::TraceMaps::new(m, textures))
            .collect();
        for inst in &input.instances {
            let Some(mesh) = meshes.get(inst.mesh) else {
                continue;
            };
            let m = inst.world_from_local;
            let n = inst.normal_matrix;
            let index = materials.len() as u32;
            materials.push(inst.material.clamped());
            for t in mesh.indices.chunks_exact(3) {
                let v = [0, 1, 2].map(|k| mesh.vertices[t[k] as usize]);
                triangles.push(Triangle {
                    p: v.map(|v| m.transform_point3(Vec3::from(v.position))),
                });
                corners.push(v.map(|v| {
                    Corner {
                        normal: (n * Vec3::from(v.normal)).normalize_or(Vec3::Z),
                        tangent: m
                            .transform_vector3(Vec3::from_slice(&v.tangent[..3]))
                            .normalize_or(Vec3::X)
                            .extend(if v.tangent[3] < 0.0 { -1.0 } else { 1.0 }),
                        uv: [Vec2::from(v.uv), Vec2::from(v.uv1)],
                        color: Vec4::from(v.color),
                    }
                }));
                material.push(index);
            }
        }
        let env = match environment {
            None => TraceEnvironment::None,
            Some(e) => {
                let scale = e.intensity.max(0.0) * exposure;
                match &e.source {
                    EnvironmentSource::Uniform(c) => TraceEnvironment::Uniform(*c * scale),
                    EnvironmentSource::Image(img) => {
                        TraceEnvironment::Image(EnvironmentImage::new(
                            img.width as usize,
                            img.height as usize,
                            img.texels.iter().map(|t| Vec3::from(*t) * scale).collect(),
                            e.rotation_y_rad,
                        ))
                    }
                }
            }
        };
        let show_env = environment
            .is_some_and(|e| matches!(e.background, crate::scene::Background::Environment { .. }));
        let coated = materials.iter().any(|m| m.clearcoat.is_some());
        TraceScene {
            bvh: Bvh::build(triangles),
            corners,
            masked: maps.iter().any(|m| m.alpha_cutoff.is_some())
                || materials.iter().any(|m| m.blend),
            maps,
            material,
            materials,
            lights: input.lights.clone(),
            environment: env,
            background: (!show_env).then_some(input.background),
            camera: input.camera,
            visibility: quality.visibility,
            energy_compensation: quality
                .energy_compensation
                .then(|| AlbedoTable::new(32, 1024, quality.visibility)),
            coat_albedo: coated.then(|| {
                AlbedoTable::with_f0(
                    32,
                    1024,
                    quality.visibility,
                    crate::shading::brdf::dielectric_f0(
                        crate::shading::clearcoat::CLEARCOAT_SPECULAR_LEVEL,
                    ),
                )
            }),
            light_visibility: LightVisibility::Physical,
            light_connections: true,
        }
    }
}

/// The surface at a hit: the material with its textures applied, the shading normal
/// (normal-mapped), and the alpha.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// The material at this point.
    pub material: TraceMaterial,
    /// Shading normal (unit, not yet turned towards the viewer).
    pub normal: Vec3,
    /// The interpolated normal without the normal map (unit, not yet turned): a sheen's
    /// normal.
    pub layer_normal: Vec3,
    /// The clearcoat's normal (unit, not yet turned): the interpolated normal, bent by
    /// the coat's own normal map where it has one.
    pub coat_normal: Vec3,
    /// The interpolated tangent (world, xyz; handedness in w), not yet made perpendicular
    /// to the normal: an anisotropic lobe's reference direction.
    pub tangent: Vec4,
    /// Coverage: the base colour factor's alpha × the texel's × the vertex colour's.
    pub alpha: f32,
    /// The material's alpha cutoff, if it is masked.
    pub alpha_cutoff: Option<f32>,
}

impl TraceScene {
    /// The surface of triangle `t` at barycentrics (u, v), as the G-buffer's textured
    /// variant would shade it (`shaders/gbuffer.wgsl`, `fs_textured`).
    pub fn surface(&self, t: usize, u: f32, v: f32) -> SurfacePoint {
        let [c0, c1, c2] = self.corners[t];
        let w = 1.0 - u - v;
        let normal = (c0.normal * w + c1.normal * u + c2.normal * v).normalize_or(Vec3::Z);
        let tangent = c0.tangent * w + c1.tangent * u + c2.tangent * v;
        let mut material = self.materials[self.material[t] as usize];
        let Some(maps) = material.maps.and_then(|m| self.maps.get(m as usize)) else {
            return SurfacePoint {
                material,
                normal,
                layer_normal: normal,
                coat_normal: normal,
                tangent,
                alpha: material.alpha,
                alpha_cutoff: None,
            };
        };
        let uv0 = c0.uv[0] * w + c1.uv[0] * u + c2.uv[0] * v;
        let uv1 = c0.uv[1] * w + c1.uv[1] * u + c2.uv[1] * v;
        let color = c0.color * w + c1.color * u + c2.color * v;
        let base = maps.sample(0, uv0, uv1) * color;
        material.base_color = (material.base_color * base.truncate()).clamp(Vec3::ZERO, Vec3::ONE);
        let mr = maps.sample(1, uv0, uv1);
        material.roughness =
            crate::shading::brdf::clamp_perceptual_roughness(material.roughness * mr.y);
        material.metallic = (material.metallic * mr.z).clamp(0.0, 1.0);
        material.emissive *= maps.sample(4, uv0, uv1).truncate();
        apply_extensions(maps, &mut material, uv0, uv1);
        let mut n = normal;
        if maps.slots[2].is_some() {
            let texel = maps.sample(2, uv0, uv1).truncate();
            n = normal_from_map(normal, tangent, texel, maps.normal_scale);
        }
        SurfacePoint {
            material,
            normal: n,
            layer_normal: normal,
            coat_normal: maps.coat_normal(normal, tangent, uv0, uv1),
            tangent,
            alpha: material.alpha * base.w,
            alpha_cutoff: maps.alpha_cutoff,
        }
    }
}

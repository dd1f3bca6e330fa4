//! glTF 2.0 import (`.gltf` with its buffers, or `.glb`): the node hierarchy becomes
//! entities with [`ChildOf`] and [`Transform`]; every triangle primitive becomes a mesh
//! with a metal/roughness [`Material`]; the first camera and `KHR_lights_punctual`
//! lights are mapped onto ours (glTF's lux and candela are our units). The lights cast
//! shadows unless [`GltfOptions::light_shadows`] is off.
//!
//! - Primitives: u8/u16/u32 or no indices; `KHR_draco_mesh_compression` (decoded with
//!   `draco-core`). Joints, weights and morph targets make a deformable mesh, and a node
//!   with a skin gets a [`crate::scene::SkinnedMesh`], a mesh with morph targets
//!   [`crate::scene::MorphWeights`] on its node (`gltf_skin`). Every accessor's byte range is checked against its buffer before it
//!   is read. Missing normals are computed (area-weighted); missing tangents are
//!   generated with MikkTSpace from texture coordinate set 0.
//! - Materials: the metal/roughness factors; `KHR_materials_pbrSpecularGlossiness`
//!   converted to metal/roughness at load ([`crate::workflow`]); `KHR_materials_ior` and
//!   `KHR_materials_specular` give the dielectric F0; `KHR_materials_emissive_strength`
//!   scales the emission. Alpha mode `MASK` keeps or drops a primitive by its constant
//!   alpha; `BLEND` primitives are blended ([`crate::scene::Material::blend`]), unless
//!   their alpha is a constant 1 (then opaque). `KHR_materials_unlit` materials show
//!   their base colour unlit ([`crate::scene::Material::unlit`]).
//!
//! Textures (base colour, metallic-roughness, normal, occlusion, emissive) are decoded
//! within the texture budget (`gltf_material`). Every file and URI is read through
//! [`files::read`] (regular files only, capped by kind); indices are checked before the
//! `gltf` crate uses them (`gltf_checks`) and its panics become errors.

pub use super::gltf_buffers::external_files;
use super::gltf_buffers::{check_accessor, load_buffers, view_bytes};
use super::gltf_checks;
use super::gltf_material::{self, TextureLoader};
use super::gltf_quantized::{self, read_attribute, unit3};
use super::{draco, gltf_skin, meshopt, tangents};
use crate::app::App;
use crate::error::{Error, Result};
use crate::files;
use crate::limits::FileKind;
use crate::scene::{
    Aabb, Camera, DirectionalLight, GlobalTransform, LightColor, LuminousIntensity, Material,
    Mesh3d, MeshData, PointLight, Projection, SpotLight, Transform, Vertex,
};
use crate::scene::{MaterialMaps, Textures};
use bevy_ecs::hierarchy::ChildOf;
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3};
use gltf::accessor::DataType;
use std::collections::HashMap;
use std::path::Path;

/// What an import brought in.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GltfSummary {
    /// Entities created for nodes.
    pub nodes: usize,
    /// Triangle primitives imported.
    pub primitives: usize,
    /// Triangles in all.
    pub triangles: usize,
    /// Lights imported.
    pub lights: usize,
    /// Whether the file had a camera (else one was placed to frame the scene).
    pub has_camera: bool,
    /// Bounds of all imported geometry in world space (m), if any.
    pub bounds: Option<Aabb>,
    /// Images decoded (once per colour space they are used in).
    pub textures: usize,
    /// Whether the file had no light, so a default sun, sky and exposure were added.
    pub default_lighting: bool,
    /// Problems that did not stop the import.
    pub warnings: Vec<String>,
    /// The animations imported (name, duration in s), in the file's order; an
    /// [`crate::scene::AnimationPlayer`] on the file's root entity plays them.
    pub animations: Vec<(String, f32)>,
}

/// Luminance of the uniform sky added to files without lights (cd/m²): with the default
/// 10 000 lx sun, a white surface facing both receives about 13 000 lx.
pub const DEFAULT_SKY_NITS: f32 = 1000.0;
/// Exposure of files without lights, set for the default sun and sky (EV100).
pub const DEFAULT_EV100: f32 = 13.0;

fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::bad_file(path, message)
}

/// A material's name and its maps.
pub type NamedMaterialInput = (String, crate::validate::MaterialInput);

/// Every material of a glTF file, named (its name, else `material N`), as the validator
/// and converter read it ([`crate::validate::MaterialInput`]), with the problems met
/// while decoding its images. Textures larger than `max_texture_size` are downscaled.
pub fn material_inputs(
    path: &Path,
    max_texture_size: u32,
) -> Result<(Vec<NamedMaterialInput>, Vec<String>)> {
    contained(path, || read_material_inputs(path, max_texture_size))
}

fn read_material_inputs(
    path: &Path,
    max_texture_size: u32,
) -> Result<(Vec<NamedMaterialInput>, Vec<String>)> {
    let (document, buffers) = open(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let views: Vec<gltf::buffer::View> = document.views().collect();
    let images: Vec<gltf::Image> = document.images().collect();
    let textures: Vec<gltf::Texture> = document.textures().collect();
    let mut loader = TextureLoader {
        base,
        buffers: &buffers,
        views: &views,
        images: &images,
        textures: &textures,
        max_size: max_texture_size.max(1),
        cache: HashMap::new(),
        warnings: Vec::new(),
    };
    let materials = document
        .materials()
        .map(|m| {
            let name = m
                .name()
                .map(str::to_string)
                .unwrap_or_else(|| format!("material {}", m.index().unwrap_or(0)));
            (name, gltf_material::material_input(&m, &mut loader))
        })
        .collect();
    Ok((materials, loader.warnings))
}

/// Reads and parses a glTF file (capped as [`FileKind::Model`]) and loads its buffers
/// (each capped as [`FileKind::Buffer`]).
fn open(path: &Path) -> Result<(gltf::Document, Vec<gltf::buffer::Data>)> {
    let bytes = files::read(path, FileKind::Model)?;
    let gltf = parse(&bytes).map_err(|e| bad(path, e))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let mut buffers = load_buffers(&gltf.document, base, gltf.blob)
        .map_err(|e| bad(path, format!("cannot load buffers: {e}")))?;
    meshopt::decompress(&gltf.document, &mut buffers)
        .map_err(|e| bad(path, format!("cannot decompress: {e}")))?;
    Ok((gltf.document, buffers))
}

/// Runs `load` on the file at `path` with any panic inside the `gltf` crate turned into the
/// usual error naming the file.
fn contained<T>(path: &Path, load: impl FnOnce() -> Result<T>) -> Result<T> {
    crate::error::contain_panics(load).unwrap_or_else(|panic| {
        Err(bad(
            path,
            format!("malformed glTF (the glTF reader failed: {panic})"),
        ))
    })
}

/// How a glTF file is imported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GltfOptions {
    /// Whether the file's `KHR_lights_punctual` lights cast shadows. On by default: a light
    /// inside a room must not light through its walls, and the path tracer, the judge,
    /// always has shadows.
    pub light_shadows: bool,
    /// Whether a file without a camera gets one that frames it, and a file without
    /// lights a default sun, sky and exposure. On by default; a script that places its
    /// own camera and lights turns it off.
    pub staging: bool,
}

impl Default for GltfOptions {
    fn default() -> Self {
        GltfOptions {
            light_shadows: true,
            staging: true,
        }
    }
}

/// Loads a glTF file into `app`'s World with the default [`GltfOptions`]. Fails with an
/// error naming the file and the problem; never panics on malformed input.
pub fn load_gltf(app: &mut App, path: &Path) -> Result<GltfSummary> {
    load_gltf_with(app, path, &GltfOptions::default())
}

/// [`load_gltf`] with `options`.
pub fn load_gltf_with(app: &mut App, path: &Path, options: &GltfOptions) -> Result<GltfSummary> {
    contained(path, || load_into(app, path, options))
}

fn load_into(app: &mut App, path: &Path, options: &GltfOptions) -> Result<GltfSummary> {
    let (document, buffers) = open(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let mut summary = GltfSummary::default();

    let source = Source {
        buffers: &buffers,
        views: document.views().collect(),
    };
    let max_size = texture_budget(app);
    let images: Vec<gltf::Image> = document.images().collect();
    let textures: Vec<gltf::Texture> = document.textures().collect();
    let mut loader = TextureLoader {
        base,
        buffers: &buffers,
        views: &source.views,
        images: &images,
        textures: &textures,
        max_size,
        cache: HashMap::new(),
        warnings: Vec::new(),
    };
    // Meshes: one MeshData + Material (+ MaterialMaps) per triangle primitive, and
    // whether it has joints; per mesh, its morph target count.
    type Drawn = (
        crate::scene::MeshHandle,
        Material,
        Option<MaterialMaps>,
        bool,
    );
    let mut meshes: Vec<Vec<Drawn>> = Vec::new();
    let mut morph_targets: Vec<usize> = Vec::new();
    for mesh in document.meshes() {
        let mut prims = Vec::new();
        let mut mesh_targets: Option<usize> = None;
        for (p, primitive) in mesh.primitives().enumerate() {
            let what = format!("mesh {} primitive {p}", mesh.index());
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                summary.warnings.push(format!(
                    "{what}: {:?} primitives are not drawn",
                    primitive.mode()
                ));
                continue;
            }
            let data = match read_primitive(&primitive, &source, &mut summary.warnings, &what) {
                Ok(d) => d,
                Err(e) => return Err(bad(path, format!("{what}: {e}"))),
            };
            let has_colors = primitive.get(&gltf::Semantic::Colors(0)).is_some();
            let Some((material, maps)) = gltf_material::material(
                &primitive.material(),
                &what,
                has_colors,
                &mut loader,
                &mut app.world_mut().resource_mut::<Textures>(),
            ) else {
                continue;
            };
            if data.indices.is_empty() {
                summary
                    .warnings
                    .push(format!("{what}: no drawable triangle"));
                continue;
            }
            summary.triangles += data.triangle_count();
            summary.primitives += 1;
            let deformation = if primitive.extension_value(draco::EXTENSION).is_some() {
                let deformed = primitive.morph_targets().next().is_some()
                    || primitive.get(&gltf::Semantic::Joints(0)).is_some();
                if deformed {
                    summary.warnings.push(format!(
                        "{what}: joints and morph targets are not decoded from Draco streams"
                    ));
                }
                None
            } else {
                gltf_skin::read_deformation(&primitive, &buffers, &mut summary.warnings, &what)
                    .map_err(|e| bad(path, format!("{what}: {e}")))?
            };
            let skinned = deformation.as_ref().is_some_and(|d| !d.joints.is_empty());
            let handle = match deformation {
                Some(d) => {
                    let targets = d.targets.len();
                    let count = mesh_targets.get_or_insert(targets);
                    if *count != targets {
                        return Err(bad(
                            path,
                            format!("{what}: {targets} morph targets where the mesh's other primitives have {count}"),
                        ));
                    }
                    app.add_deformable_mesh(data, d.joints, d.weights, d.targets)
                }
                None => app.add_mesh(data),
            }
            .map_err(|e| bad(path, format!("{what}: {e}")))?;
            prims.push((handle, material, maps, skinned));
        }
        meshes.push(prims);
        morph_targets.push(mesh_targets.unwrap_or(0));
    }
    summary.textures = loader.cache.len();
    summary.warnings.append(&mut loader.warnings);

    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| bad(path, "the file has no scene"))?;
    let world = app.world_mut();
    let root = world.spawn(Transform::IDENTITY).id();
    let mut drawn = Vec::new();
    let mut skinned_primitives: Vec<(Entity, gltf::Skin)> = Vec::new();
    let mut nodes = HashMap::new();
    let mut stack: Vec<(gltf::Node, Entity, usize)> = scene.nodes().map(|n| (n, root, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(bad(
                path,
                "node hierarchy deeper than 256 levels (a cycle?)",
            ));
        }
        let (t, r, s) = node.transform().decomposed();
        let transform = Transform {
            translation: finite_vec(Vec3::from(t), Vec3::ZERO),
            rotation: {
                let q = Quat::from_array(r);
                if q.is_finite() && q.length() > 1e-6 {
                    q.normalize()
                } else {
                    Quat::IDENTITY
                }
            },
            scale: finite_vec(Vec3::from(s), Vec3::ONE),
        };
        let entity = world.spawn((transform, ChildOf(parent))).id();
        nodes.insert(node.index(), entity);
        summary.nodes += 1;
        if let Some(mesh) = node.mesh() {
            for (handle, mat, maps, skinned) in meshes.get(mesh.index()).into_iter().flatten() {
                let mut e =
                    world.spawn((Mesh3d(*handle), *mat, Transform::IDENTITY, ChildOf(entity)));
                if let Some(maps) = maps {
                    e.insert(maps.clone());
                }
                match (node.skin(), skinned) {
                    (Some(skin), true) => skinned_primitives.push((e.id(), skin)),
                    (None, true) => summary.warnings.push(format!(
                        "node {}: its mesh has joints but the node no skin: drawn unskinned",
                        node.index()
                    )),
                    _ => {}
                }
                drawn.push(e.id());
            }
            let targets = morph_targets.get(mesh.index()).copied().unwrap_or(0);
            if targets > 0 {
                let mut weights: Vec<f32> = node
                    .weights()
                    .or(mesh.weights())
                    .map(<[f32]>::to_vec)
                    .unwrap_or_default();
                weights.resize(targets, 0.0);
                world
                    .entity_mut(entity)
                    .insert(crate::scene::MorphWeights(weights));
            }
        }
        if let (Some(camera), false) = (node.camera(), summary.has_camera) {
            match camera.projection() {
                gltf::camera::Projection::Perspective(p) => match degenerate_perspective(&p) {
                    Some(problem) => summary.warnings.push(format!(
                        "camera {}: {problem}: ignored, the view is framed automatically",
                        camera.index()
                    )),
                    None => {
                        world.entity_mut(entity).insert(Camera {
                            projection: Projection {
                                fov_y_rad: p.yfov(),
                                near_m: p.znear(),
                                far_m: p.zfar().unwrap_or(p.znear() * 1e5),
                                ..Projection::default()
                            },
                            ..Camera::default()
                        });
                        summary.has_camera = true;
                    }
                },
                gltf::camera::Projection::Orthographic(_) => summary
                    .warnings
                    .push("orthographic cameras are not supported; ignored".into()),
            }
        }
        if let Some(light) = node.light() {
            spawn_light(world, entity, &light, options.light_shadows);
            summary.lights += 1;
        }
        stack.extend(node.children().map(|c| (c, entity, depth + 1)));
    }
    for (entity, skin) in skinned_primitives {
        let what = format!("skin {}", skin.index());
        let checked = gltf_skin::read_skin(&skin, &buffers, &nodes).and_then(|s| {
            let mesh = world.get::<Mesh3d>(entity).map(|m| m.0);
            let needed = mesh
                .and_then(|m| world.resource::<crate::scene::Meshes>().deformation(m))
                .map_or(0, |d| d.joint_count());
            if needed > s.joints.len() {
                Err(format!(
                    "the mesh refers to joint {} but the skin has {}",
                    needed - 1,
                    s.joints.len()
                ))
            } else {
                Ok(s)
            }
        });
        match checked {
            Ok(s) => {
                world.entity_mut(entity).insert(s);
            }
            Err(e) => summary
                .warnings
                .push(format!("{what}: {e}; its mesh is drawn unskinned")),
        }
    }
    let morph_targets = |e: Entity| {
        world
            .get::<crate::scene::MorphWeights>(e)
            .map_or(0, |w| w.0.len())
    };
    let clips = super::gltf_animation::read_animations(
        &document,
        &buffers,
        &nodes,
        &morph_targets,
        &mut summary.warnings,
    );
    if !clips.is_empty() {
        summary.animations = clips
            .iter()
            .map(|c| (c.name.clone(), c.duration_s))
            .collect();
        let clips = clips.into_iter().map(std::sync::Arc::new).collect();
        world
            .entity_mut(root)
            .insert(crate::scene::AnimationPlayer::new(clips));
    }

    // Bounds of the file's geometry (in the nodes' rest pose) in world space, for framing.
    let mut schedule = Schedule::default();
    schedule.add_systems(crate::scene::propagate_transforms);
    schedule.run(world);
    let mut query = world.query::<(
        &Mesh3d,
        &GlobalTransform,
        Option<&crate::scene::SkinnedMesh>,
    )>();
    let meshes_store = world.resource::<crate::scene::Meshes>();
    for (mesh, global, skin) in drawn.iter().filter_map(|e| query.get(world, *e).ok()) {
        let rest = meshes_store.bounds(mesh.0);
        let b = match (skin, meshes_store.deformation(mesh.0)) {
            (Some(skin), Some(d)) => {
                let matrices =
                    skin.joint_matrices(|j| world.get::<GlobalTransform>(j).map(|g| g.0));
                d.bounds(rest, Some(&matrices), &[])
            }
            _ => rest.and_then(|b| b.transformed(&global.0)),
        };
        if let Some(b) = b {
            summary.bounds = Some(summary.bounds.map_or(b, |a| a.union(&b)));
        }
    }
    if !summary.has_camera && options.staging {
        let (target, radius) = summary
            .bounds
            .map(|b| (b.center(), ((b.max - b.min).length() * 0.5).max(1e-3)))
            .unwrap_or((Vec3::ZERO, 1.0));
        let projection = Projection {
            near_m: radius * 0.01,
            far_m: radius * 100.0,
            ..Projection::default()
        };
        let distance = radius / (projection.fov_y_rad * 0.5).sin() * 1.1;
        let eye = target + Vec3::new(0.0, 0.35, 1.0).normalize() * distance;
        world.spawn((
            Camera {
                projection,
                ..Camera::default()
            },
            Transform::from_translation(eye).looking_at(target, Vec3::Y),
        ));
    }
    if summary.lights == 0 && options.staging {
        // Default lighting: a 10 000 lx sun from the upper right, a uniform sky of
        // DEFAULT_SKY_NITS, and every camera exposed for them.
        world.spawn((
            DirectionalLight {
                cast_shadows: true,
                ..DirectionalLight::default()
            },
            crate::scene::ShadowSettings::directional(),
            Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
        ));
        let has_environment = world
            .query::<&crate::scene::Environment>()
            .iter(world)
            .next()
            .is_some();
        if !has_environment {
            world.spawn(crate::scene::Environment::uniform(Vec3::splat(
                DEFAULT_SKY_NITS,
            )));
        }
        let mut cameras = world.query::<&mut Camera>();
        for mut camera in cameras.iter_mut(world) {
            camera.exposure = crate::scene::Exposure::Ev100(DEFAULT_EV100);
        }
        summary.default_lighting = true;
    }
    for w in &summary.warnings {
        log::warn!("{}: {w}", path.display());
    }
    Ok(summary)
}

/// The longest texture side a load keeps: the quality's budget, and the device's limit
/// when a GPU is attached.
fn texture_budget(app: &App) -> u32 {
    let budget = app
        .world()
        .get_resource::<crate::quality::Quality>()
        .map_or(4096, |q| q.max_texture_size);
    let device = app
        .world()
        .get_resource::<crate::render::device::Gpu>()
        .map_or(8192, |g| g.device.limits().max_texture_dimension_2d);
    budget.min(device).max(1)
}

/// Why a perspective camera describes no view, if it does not: glTF requires
/// 0 < `yfov` < π, `znear` > 0 and `zfar` > `znear` (all finite).
fn degenerate_perspective(p: &gltf::camera::Perspective) -> Option<String> {
    let (yfov, znear, zfar) = (p.yfov(), p.znear(), p.zfar());
    let fov_ok = yfov.is_finite() && yfov > 0.0 && yfov < std::f32::consts::PI;
    let near_ok = znear.is_finite() && znear > 0.0;
    let far_ok = zfar.is_none_or(|f| f.is_finite() && f > znear);
    (!(fov_ok && near_ok && far_ok)).then(|| {
        let far = zfar.map_or("none".into(), |f| f.to_string());
        format!(
            "yfov {yfov}, znear {znear}, zfar {far} describe no view (glTF needs 0 < yfov < π, znear > 0, zfar > znear)"
        )
    })
}

fn finite_vec(v: Vec3, fallback: Vec3) -> Vec3 {
    if v.is_finite() { v } else { fallback }
}

fn spawn_light(
    world: &mut World,
    entity: Entity,
    light: &gltf::khr_lights_punctual::Light,
    cast_shadows: bool,
) {
    let color = LightColor::LinearRgb(Vec3::from(light.color()));
    let intensity = light.intensity();
    let range_m = light.range().unwrap_or(f32::INFINITY);
    let mut e = world.entity_mut(entity);
    match light.kind() {
        gltf::khr_lights_punctual::Kind::Directional => {
            e.insert(DirectionalLight {
                illuminance_lux: intensity,
                color,
                cast_shadows,
                ..DirectionalLight::default()
            });
        }
        gltf::khr_lights_punctual::Kind::Point => {
            e.insert(PointLight {
                intensity: LuminousIntensity::Candela(intensity),
                color,
                range_m,
                cast_shadows,
                ..PointLight::default()
            });
        }
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            e.insert(SpotLight {
                intensity: LuminousIntensity::Candela(intensity),
                color,
                range_m,
                inner_angle_rad: inner_cone_angle,
                outer_angle_rad: outer_cone_angle,
                cast_shadows,
                ..SpotLight::default()
            });
        }
    }
}

/// Extensions Lumen reads itself, beyond those the `gltf` crate knows
/// (`gltf::json::extensions::ENABLED_EXTENSIONS`): a file may require them.
const READ_HERE: &[&str] = &[
    draco::EXTENSION,
    gltf_quantized::EXTENSION,
    meshopt::EXTENSION,
    "KHR_materials_volume",
    "KHR_materials_specular",
    "KHR_materials_dispersion",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_anisotropy",
    "KHR_materials_iridescence",
    "KHR_materials_diffuse_transmission",
];

/// Parses a glTF or GLB file and validates it. A required extension must be one the
/// `gltf` crate or Lumen reads ([`READ_HERE`]); Draco compression also allows accessors
/// without a buffer view (their data is in the Draco stream).
fn parse(bytes: &[u8]) -> std::result::Result<gltf::Gltf, String> {
    use gltf::json::validation::{Error as Invalid, Validate};
    gltf_checks::check_index_ranges(bytes).map_err(|e| format!("invalid glTF: {e}"))?;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| format!("not a valid glTF file: {e}"))?;
    let root = gltf.document.as_json();
    gltf_checks::check_attribute_accessors(root).map_err(|e| format!("invalid glTF: {e}"))?;
    let draco_required = root
        .extensions_required
        .iter()
        .any(|e| e == draco::EXTENSION);
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        // Required extensions are checked by name below.
        let allowed = (error == Invalid::Unsupported && path.starts_with("extensionsRequired"))
            || (draco_required
                && error == Invalid::Missing
                && path.starts_with("accessors[")
                && path.ends_with("].bufferView"));
        if !allowed {
            errors.push(format!("{path}: {error}"));
        }
    });
    if !errors.is_empty() {
        return Err(format!("invalid glTF: {}", errors.join("; ")));
    }
    for required in &root.extensions_required {
        if !READ_HERE.contains(&required.as_str())
            && !gltf::json::extensions::ENABLED_EXTENSIONS.contains(&required.as_str())
        {
            return Err(format!("requires the unsupported extension {required}"));
        }
    }
    Ok(gltf)
}

/// The file's buffers and buffer views.
struct Source<'a> {
    buffers: &'a [gltf::buffer::Data],
    views: Vec<gltf::buffer::View<'a>>,
}

fn read_primitive(
    primitive: &gltf::Primitive,
    source: &Source,
    warnings: &mut Vec<String>,
    what: &str,
) -> std::result::Result<MeshData, String> {
    let buffers = source.buffers;
    // Per vertex: positions, normals, texture sets 0 and 1, colours, tangents; indices.
    type Attributes = (
        Vec<[f32; 3]>,
        Option<Vec<[f32; 3]>>,
        Option<Vec<[f32; 2]>>,
        Option<Vec<[f32; 2]>>,
        Option<Vec<[f32; 4]>>,
        Option<Vec<[f32; 4]>>,
        Option<Vec<u32>>,
    );
    let (positions, normals, uvs, uv1, colors, tangents, indices): Attributes =
        match primitive.extension_value(draco::EXTENSION) {
            Some(extension) => {
                let decoded = draco::decode_primitive(extension, |i| {
                    source.views.get(i).and_then(|v| view_bytes(v, buffers))
                })?;
                for (semantic, _) in primitive.attributes() {
                    if matches!(
                        semantic,
                        gltf::Semantic::Colors(_)
                            | gltf::Semantic::TexCoords(1..)
                            | gltf::Semantic::Tangents
                    ) {
                        warnings.push(format!(
                            "{what}: {semantic:?} is not decoded from Draco streams"
                        ));
                    }
                }
                (
                    decoded.positions,
                    decoded.normals,
                    decoded.uvs,
                    None,
                    None,
                    None,
                    Some(decoded.indices),
                )
            }
            None => {
                for (_, accessor) in primitive.attributes() {
                    check_accessor(&accessor, buffers)?;
                }
                if let Some(accessor) = primitive.indices() {
                    check_accessor(&accessor, buffers)?;
                }
                let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                // Each attribute through the glTF reader when it is f32, dequantized
                // (KHR_mesh_quantization) otherwise.
                let attribute = |semantic: gltf::Semantic| primitive.get(&semantic);
                let positions = match attribute(gltf::Semantic::Positions) {
                    Some(a) => read_attribute(&a, buffers, || {
                        reader.read_positions().map(Iterator::collect)
                    })?,
                    None => None,
                };
                let quantized = |a: &gltf::Accessor| a.data_type() != DataType::F32;
                let normals = match attribute(gltf::Semantic::Normals) {
                    Some(a) => read_attribute(&a, buffers, || {
                        reader.read_normals().map(Iterator::collect)
                    })?
                    .map(|n: Vec<[f32; 3]>| {
                        if quantized(&a) {
                            n.into_iter().map(unit3).collect()
                        } else {
                            n
                        }
                    }),
                    None => None,
                };
                let tex_coords = |set: u32| match attribute(gltf::Semantic::TexCoords(set)) {
                    Some(a) => read_attribute(&a, buffers, || {
                        reader.read_tex_coords(set).map(|t| t.into_f32().collect())
                    }),
                    None => Ok(None),
                };
                let tangents = match attribute(gltf::Semantic::Tangents) {
                    Some(a) => read_attribute(&a, buffers, || {
                        reader.read_tangents().map(Iterator::collect)
                    })?
                    .map(|t: Vec<[f32; 4]>| {
                        if !quantized(&a) {
                            return t;
                        }
                        t.into_iter()
                            .map(|[x, y, z, w]| {
                                let [x, y, z] = unit3([x, y, z]);
                                [x, y, z, if w < 0.0 { -1.0 } else { 1.0 }]
                            })
                            .collect()
                    }),
                    None => None,
                };
                (
                    positions.ok_or("has no POSITION attribute")?,
                    normals,
                    tex_coords(0)?,
                    tex_coords(1)?,
                    reader.read_colors(0).map(|c| c.into_rgba_f32().collect()),
                    tangents,
                    reader.read_indices().map(|i| i.into_u32().collect()),
                )
            }
        };
    let count = positions.len();
    let normals = normals.filter(|n| n.len() == count);
    let uvs = uvs.filter(|t| t.len() == count);
    let uv1 = uv1.filter(|t| t.len() == count);
    let colors = colors.filter(|c| c.len() == count);
    let tangents = tangents.filter(|t| t.len() == count);
    for (semantic, _) in primitive.attributes() {
        if matches!(
            semantic,
            gltf::Semantic::Colors(1..) | gltf::Semantic::TexCoords(2..)
        ) {
            warnings.push(format!("{what}: {semantic:?} is not used"));
        }
    }
    let mut mesh = MeshData {
        vertices: positions
            .iter()
            .enumerate()
            .map(|(i, p)| Vertex {
                position: *p,
                normal: normals.as_ref().map_or([0.0; 3], |n| n[i]),
                uv: uvs.as_ref().map_or([0.0; 2], |t| t[i]),
                tangent: tangents.as_ref().map_or([0.0; 4], |t| t[i]),
                uv1: uv1.as_ref().map_or([0.0; 2], |t| t[i]),
                color: colors.as_ref().map_or([1.0; 4], |c| c[i]),
            })
            .collect(),
        indices: indices.unwrap_or_else(|| (0..count as u32).collect()),
    };
    mesh.validate()?;
    // Drop zero-area triangles: they rasterise nothing and have no normal.
    let before = mesh.indices.len() / 3;
    let vertices = &mesh.vertices;
    let area = |t: &[u32]| {
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(vertices[t[k] as usize].position));
        (b - a).cross(c - a).length_squared()
    };
    mesh.indices = mesh
        .indices
        .chunks_exact(3)
        .filter(|t| area(t) > 0.0)
        .flatten()
        .copied()
        .collect();
    let dropped = before - mesh.indices.len() / 3;
    if dropped > 0 {
        warnings.push(format!("{what}: {dropped} zero-area triangle(s) dropped"));
    }
    if normals.is_none() {
        let computed = computed_normals(&mesh);
        for (v, n) in mesh.vertices.iter_mut().zip(computed) {
            v.normal = n;
        }
    }
    for v in &mut mesh.vertices {
        let n = Vec3::from(v.normal).try_normalize().unwrap_or(Vec3::Z);
        v.normal = n.into();
    }
    match tangents {
        Some(_) => {
            // The file's tangents, with their handedness (w) kept; broken ones get a
            // perpendicular fallback.
            for v in &mut mesh.vertices {
                let n = Vec3::from(v.normal);
                let t = Vec3::from_slice(&v.tangent[..3]);
                if !t.is_finite() || t.length_squared() < 1e-12 {
                    v.tangent = n.any_orthonormal_vector().extend(1.0).into();
                } else {
                    let w = if v.tangent[3] < 0.0 { -1.0 } else { 1.0 };
                    v.tangent = t.normalize().extend(w).into();
                }
            }
        }
        None => {
            tangents::generate_mikktspace(&mut mesh);
        }
    }
    Ok(mesh)
}

/// Area-weighted vertex normals of a validated mesh.
fn computed_normals(mesh: &MeshData) -> Vec<[f32; 3]> {
    let mut acc = vec![Vec3::ZERO; mesh.vertices.len()];
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(mesh.vertices[t[k] as usize].position));
        let n = (b - a).cross(c - a);
        for &k in t {
            acc[k as usize] += n;
        }
    }
    acc.into_iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Z).into())
        .collect()
}

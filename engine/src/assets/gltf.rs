//! glTF 2.0 import (`.gltf` with its buffers, or `.glb`): the node hierarchy becomes
//! entities with [`ChildOf`] and [`Transform`]; every triangle primitive becomes a mesh
//! with a metal/roughness [`Material`]; the first camera and `KHR_lights_punctual`
//! lights are mapped onto ours (glTF's lux and candela are our units).
//!
//! Textures are not read yet: materials use their factors, and a warning says how many
//! textures were ignored. Missing normals are computed (area-weighted); missing tangents
//! are an arbitrary orthonormal basis around the normal.

use crate::app::App;
use crate::brdf::f0_from_ior;
use crate::error::{Error, Result};
use crate::scene::{
    Aabb, Camera, DirectionalLight, GlobalTransform, LightColor, LuminousIntensity, Material,
    Mesh3d, MeshData, PointLight, Projection, SpotLight, Transform, Vertex,
};
use bevy_ecs::hierarchy::ChildOf;
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3, Vec4};
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
    /// Problems that did not stop the import.
    pub warnings: Vec<String>,
}

fn bad(path: &Path, message: impl Into<String>) -> Error {
    Error::bad_file(path, message)
}

/// Loads a glTF file into `app`'s World. Fails with an error naming the file and the
/// problem; never panics on malformed input.
pub fn load_gltf(app: &mut App, path: &Path) -> Result<GltfSummary> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let gltf = gltf::Gltf::from_slice(&bytes)
        .map_err(|e| bad(path, format!("not a valid glTF file: {e}")))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let buffers = gltf::import_buffers(&gltf.document, Some(base), gltf.blob.clone())
        .map_err(|e| bad(path, format!("cannot load buffers: {e}")))?;
    let document = gltf.document;
    let mut summary = GltfSummary::default();

    let textures = document.textures().count();
    if textures > 0 {
        summary.warnings.push(format!(
            "{textures} texture(s) not drawn: materials use their factors only"
        ));
    }

    // Meshes: one MeshData + Material per triangle primitive.
    let mut meshes: Vec<Vec<(crate::scene::MeshHandle, Material)>> = Vec::new();
    for mesh in document.meshes() {
        let mut prims = Vec::new();
        for (p, primitive) in mesh.primitives().enumerate() {
            let what = format!("mesh {} primitive {p}", mesh.index());
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                summary.warnings.push(format!(
                    "{what}: {:?} primitives are not drawn",
                    primitive.mode()
                ));
                continue;
            }
            let data = match read_primitive(&primitive, &buffers) {
                Ok(d) => d,
                Err(e) => return Err(bad(path, format!("{what}: {e}"))),
            };
            if data.indices.is_empty() {
                summary
                    .warnings
                    .push(format!("{what}: no drawable triangle"));
                continue;
            }
            summary.triangles += data.triangle_count();
            summary.primitives += 1;
            let handle = app
                .add_mesh(data)
                .map_err(|e| bad(path, format!("{what}: {e}")))?;
            prims.push((handle, material(&primitive.material())));
        }
        meshes.push(prims);
    }

    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| bad(path, "the file has no scene"))?;
    let world = app.world_mut();
    let root = world.spawn(Transform::IDENTITY).id();
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
        summary.nodes += 1;
        if let Some(mesh) = node.mesh() {
            for (handle, mat) in meshes.get(mesh.index()).into_iter().flatten() {
                world.spawn((Mesh3d(*handle), *mat, Transform::IDENTITY, ChildOf(entity)));
            }
        }
        if let (Some(camera), false) = (node.camera(), summary.has_camera) {
            if let gltf::camera::Projection::Perspective(p) = camera.projection() {
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
            } else {
                summary
                    .warnings
                    .push("orthographic cameras are not supported; ignored".into());
            }
        }
        if let Some(light) = node.light() {
            spawn_light(world, entity, &light);
            summary.lights += 1;
        }
        stack.extend(node.children().map(|c| (c, entity, depth + 1)));
    }

    // Bounds of the geometry in world space, for framing.
    let mut schedule = Schedule::default();
    schedule.add_systems(crate::scene::propagate_transforms);
    schedule.run(world);
    let mut query = world.query::<(&Mesh3d, &GlobalTransform)>();
    let meshes_store = world.resource::<crate::scene::Meshes>();
    for (mesh, global) in query.iter(world) {
        if let Some(b) = meshes_store
            .get(mesh.0)
            .and_then(|m| m.bounds())
            .and_then(|b| b.transformed(&global.0))
        {
            summary.bounds = Some(summary.bounds.map_or(b, |a| a.union(&b)));
        }
    }
    if !summary.has_camera {
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
    if summary.lights == 0 {
        world.spawn((
            DirectionalLight::default(),
            Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
        ));
    }
    for w in &summary.warnings {
        log::warn!("{}: {w}", path.display());
    }
    Ok(summary)
}

fn finite_vec(v: Vec3, fallback: Vec3) -> Vec3 {
    if v.is_finite() { v } else { fallback }
}

fn material(m: &gltf::Material) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let base = Vec4::from(pbr.base_color_factor());
    let strength = m.emissive_strength().unwrap_or(1.0);
    let specular_level = m
        .ior()
        .map(|ior| (f0_from_ior(ior) / 0.08).clamp(0.0, 1.0))
        .unwrap_or(0.5);
    Material {
        base_color: base,
        metallic: pbr.metallic_factor(),
        perceptual_roughness: pbr.roughness_factor(),
        specular_level,
        // glTF emissive is a colour factor × strength in nits (cd/m²) per
        // KHR_materials_emissive_strength's reference of 1 = 1 nit.
        emissive: Vec3::from(m.emissive_factor()) * strength,
        occlusion: 1.0,
    }
}

fn spawn_light(world: &mut World, entity: Entity, light: &gltf::khr_lights_punctual::Light) {
    let color = LightColor::LinearRgb(Vec3::from(light.color()));
    let intensity = light.intensity();
    let range_m = light.range().unwrap_or(f32::INFINITY);
    let mut e = world.entity_mut(entity);
    match light.kind() {
        gltf::khr_lights_punctual::Kind::Directional => {
            e.insert(DirectionalLight {
                illuminance_lux: intensity,
                color,
                ..DirectionalLight::default()
            });
        }
        gltf::khr_lights_punctual::Kind::Point => {
            e.insert(PointLight {
                intensity: LuminousIntensity::Candela(intensity),
                color,
                range_m,
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
                ..SpotLight::default()
            });
        }
    }
}

fn read_primitive(
    primitive: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
) -> std::result::Result<MeshData, String> {
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or("has no POSITION attribute")?
        .collect();
    let count = positions.len();
    let normals: Option<Vec<[f32; 3]>> = reader
        .read_normals()
        .map(|n| n.collect::<Vec<_>>())
        .filter(|n| n.len() == count);
    let uvs: Vec<[f32; 2]> = reader
        .read_tex_coords(0)
        .map(|t| t.into_f32().collect())
        .unwrap_or_default();
    let tangents: Vec<[f32; 4]> = reader
        .read_tangents()
        .map(|t| t.collect())
        .unwrap_or_default();
    let mut mesh = MeshData {
        vertices: positions
            .iter()
            .enumerate()
            .map(|(i, p)| Vertex {
                position: *p,
                normal: normals.as_ref().map_or([0.0; 3], |n| n[i]),
                uv: uvs.get(i).copied().unwrap_or([0.0; 2]),
                tangent: tangents.get(i).copied().unwrap_or([0.0; 4]),
            })
            .collect(),
        indices: match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..count as u32).collect(),
        },
    };
    mesh.validate()?;
    if normals.is_none() {
        let computed = computed_normals(&mesh);
        for (v, n) in mesh.vertices.iter_mut().zip(computed) {
            v.normal = n;
        }
    }
    for v in &mut mesh.vertices {
        let n = Vec3::from(v.normal).try_normalize().unwrap_or(Vec3::Z);
        v.normal = n.into();
        if !Vec3::from_slice(&v.tangent[..3]).is_normalized() {
            v.tangent = n.any_orthonormal_vector().extend(1.0).into();
        }
    }
    // Drop zero-area triangles: they rasterise nothing and have no normal.
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

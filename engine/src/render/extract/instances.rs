//! The instances' extraction: what each drawn entity draws with, its batch, its material
//! maps, whether it casts shadows, and its previous transform for motion vectors.

use super::deformed::DeformSources;
use super::extracted_frame::{
    Batch, Caster, ExtractedFrame, FrameMaps, InstanceSpheres, TemporalMemory, View, Viewpoint,
};
use super::values::{exposed, finite_or};
use crate::quality::Quality;
use crate::render::extract::shadow_views::{frustum_planes, sphere_in_frustum};
use crate::render::gpu_types::GpuInstance;
use crate::scene::{
    GlobalTransform, Material, MaterialMaps, Mesh3d, MeshHandle, Meshes, NotShadowCaster,
    NotShadowReceiver, Transmission,
};
use bevy_ecs::prelude::*;
use glam::{Mat3, Mat4, Vec3};
use std::collections::HashMap;

/// What extraction reads of a drawn entity.
type Drawable = (
    Entity,
    &'static Mesh3d,
    &'static Material,
    &'static GlobalTransform,
    Has<NotShadowCaster>,
    Has<NotShadowReceiver>,
    Option<&'static MaterialMaps>,
);

/// One drawn entity, before the instances are sorted into batches.
struct Item {
    mesh: MeshHandle,
    maps: Option<u32>,
    textured: bool,
    double_sided: bool,
    blend: bool,
    transmissive: bool,
    coated: bool,
    sheened: bool,
    relit: bool,
    /// Squared distance (m²) from the camera to the bounding sphere's centre.
    distance2: f32,
    casts: bool,
    in_view: bool,
    sphere: Option<(Vec3, f32)>,
    instance: GpuInstance,
    entity: Entity,
    deformed: Option<u32>,
}

impl Item {
    fn transparent(&self) -> bool {
        self.blend || self.transmissive
    }
}

/// Extracts [`ExtractedFrame::instances`], its batches, material maps, casters and
/// counts, the skinned and morphed instances ([`ExtractedFrame::deformed`]), each
/// instance's previous transform where TAA runs, and [`InstanceSpheres`].
#[allow(clippy::too_many_arguments)]
pub fn extract_instances(
    drawables: Query<Drawable>,
    meshes: Res<Meshes>,
    quality: Res<Quality>,
    viewpoint: Res<Viewpoint>,
    mut memory: ResMut<TemporalMemory>,
    mut frame: ResMut<ExtractedFrame>,
    mut spheres: ResMut<InstanceSpheres>,
    mut deform: DeformSources,
) {
    let Some(view) = viewpoint.view() else {
        return;
    };
    let frame = &mut *frame;
    frame.material_maps.clear();
    frame.deformed.clear();
    let view_planes = frustum_planes(&view.clip_from_world);
    let mut items: Vec<Item> = Vec::new();
    for drawable in &drawables {
        let seen = (view, &view_planes);
        if let Some(item) = item(drawable, seen, &meshes, frame, &mut deform) {
            items.push(item);
        }
    }
    sort(&mut items);
    // Motion vectors need each instance's previous transform; only TAA uses them, and
    // captures neither read nor update what the frame remembers.
    let temporal = !view.capture && quality.aa.temporal();
    let remembered = batch(
        items,
        &meshes,
        frame,
        &mut spheres.0,
        temporal.then_some(&memory),
    );
    if temporal {
        memory.world = remembered;
    } else if !view.capture {
        memory.world.clear();
    }
}

/// The item of one drawable, its maps added to the frame's: `None` where its mesh does
/// not exist (a warning) or its transform is degenerate or not finite.
fn item(
    (entity, mesh, material, transform, not_caster, not_receiver, maps): (
        Entity,
        &Mesh3d,
        &Material,
        &GlobalTransform,
        bool,
        bool,
        Option<&MaterialMaps>,
    ),
    (view, view_planes): (&View, &[glam::Vec4; 6]),
    meshes: &Meshes,
    frame: &mut ExtractedFrame,
    deform: &mut DeformSources,
) -> Option<Item> {
    if meshes.get(mesh.0).is_none() {
        log::warn!(
            "an entity refers to mesh {} which does not exist; skipped",
            mesh.0.0
        );
        return None;
    }
    // A skinned mesh's vertices come out of the deformation pass in world space.
    let deformed = deform.extract(entity, mesh.0, meshes, &mut frame.deformed);
    let m = match &deformed {
        Some(d) if d.skinned => Mat4::IDENTITY,
        _ => transform.0,
    };
    // A degenerate (zero-scale) or non-finite transform draws nothing.
    let (Some(normal), true) = (normal_matrix(&m), m.is_finite()) else {
        return None;
    };
    let entry = frame_maps(material, maps, &m);
    let (blend, transmissive) = (entry.blend, entry.transmission.is_some());
    let coated = !blend && !transmissive && entry.clearcoat.is_some();
    let sheened = !blend && !transmissive && entry.sheen.is_some();
    // A blended surface's anisotropy, tint, film and diffuse transmission are the
    // transparent pass's, as a transmissive one's are.
    let relit = !blend
        && !transmissive
        && (entry.anisotropy.is_some()
            || entry.specular_tint.is_some()
            || entry.iridescence.is_some()
            || entry.diffuse_transmission.is_some());
    let textured = maps.is_some();
    // The forward passes draw through the maps' bind group: a blended, transmissive or
    // layered material without maps gets the neutral ones (every slot white, every
    // factor as given).
    let forward = blend || transmissive || coated || sheened || relit;
    let maps = (textured || forward).then(|| maps_index(&mut frame.material_maps, entry));
    let sphere = match &deformed {
        Some(d) => d.bounds.map(|b| sphere_around(&b, &m)),
        None => meshes.bounds(mesh.0).map(|b| sphere_around(&b, &m)),
    };
    Some(Item {
        entity,
        deformed: deformed.map(|d| d.index),
        mesh: mesh.0,
        maps,
        textured,
        double_sided: material.double_sided,
        blend,
        transmissive,
        coated,
        sheened,
        relit,
        distance2: sphere
            .map_or(m.w_axis.truncate(), |(c, _)| c)
            .distance_squared(view.position),
        casts: !not_caster,
        in_view: sphere.is_none_or(|(c, r)| sphere_in_frustum(view_planes, c, r)),
        sphere,
        instance: gpu_instance(material, &m, normal, view.exposure, not_receiver),
    })
}

/// The maps entry of `material` with `maps` (the neutral maps where it has none) under
/// the transform `m`: its transmission in world metres, its layers clamped.
fn frame_maps(material: &Material, maps: Option<&MaterialMaps>, m: &Mat4) -> FrameMaps {
    // An unlit surface transmits nothing: it shows its base colour.
    let transmission = material
        .transmission
        .filter(|_| !material.unlit)
        .map(|t| world_transmission(&t, m))
        .filter(|t| t.factor > 0.0);
    let specular_textured = maps.is_some_and(|m| m.extensions.specular_textured());
    FrameMaps {
        maps: maps.cloned().unwrap_or_default(),
        transmission,
        blend: material.blend,
        clearcoat: material.coat(),
        sheen: material.layer_sheen(),
        anisotropy: material.anisotropic(),
        specular_tint: material.relit_tint(specular_textured),
        iridescence: material.iridescent(),
        diffuse_transmission: material.translucent(),
    }
}

/// The index of `entry` in the frame's maps, added unless an equal one is there.
fn maps_index(material_maps: &mut Vec<FrameMaps>, entry: FrameMaps) -> u32 {
    let index = match material_maps.iter().position(|x| *x == entry) {
        Some(i) => i,
        None => {
            material_maps.push(entry);
            material_maps.len() - 1
        }
    };
    index as u32
}

/// The instance data of `material` under the transform `m`, non-finite factors replaced
/// by their defaults and the emission pre-exposed.
fn gpu_instance(
    material: &Material,
    m: &Mat4,
    normal_matrix: [[f32; 4]; 3],
    exposure: f32,
    not_receiver: bool,
) -> GpuInstance {
    let base = material.base_color;
    GpuInstance {
        world_from_local: m.to_cols_array_2d(),
        normal_matrix,
        base_color: [
            finite_or(base.x, 0.0),
            finite_or(base.y, 0.0),
            finite_or(base.z, 0.0),
            finite_or(base.w, 1.0),
        ],
        emissive_occlusion: {
            let e = exposed(material.emissive.max(Vec3::ZERO), 1.0, exposure);
            [e[0], e[1], e[2], finite_or(material.occlusion, 1.0)]
        },
        params: [
            finite_or(material.metallic, 0.0),
            finite_or(material.perceptual_roughness, 1.0),
            if material.unlit {
                crate::shading::encoding::UNLIT_SPECULAR_LEVEL
            } else {
                finite_or(material.specular_level, 0.5).max(0.0)
            },
            if not_receiver { 0.0 } else { 1.0 },
        ],
    }
}

/// Opaque instances by mesh (those in view first, then casters first within a mesh, so
/// each mesh is one instanced draw of the instances in view); the blended and
/// transmissive ones after them, back to front.
fn sort(items: &mut [Item]) {
    items.sort_by(|a, b| {
        let key = |item: &Item| {
            (
                item.mesh,
                item.deformed,
                item.maps,
                item.textured,
                item.double_sided,
                !item.in_view,
                !item.casts,
            )
        };
        a.transparent().cmp(&b.transparent()).then_with(|| {
            if a.transparent() {
                b.distance2.total_cmp(&a.distance2)
            } else {
                key(a).cmp(&key(b))
            }
        })
    });
}

/// Writes the sorted `items` into the frame's instances, batches and casters, their
/// spheres into `spheres`, and, where `memory` is given (TAA runs), each instance's
/// previous transform. Returns each entity's transform, to remember for the next frame.
fn batch(
    items: Vec<Item>,
    meshes: &Meshes,
    frame: &mut ExtractedFrame,
    spheres: &mut Vec<(Vec3, f32)>,
    memory: Option<&TemporalMemory>,
) -> HashMap<Entity, Mat4> {
    frame.instances.clear();
    frame.batches.clear();
    frame.casters.clear();
    frame.triangles = 0;
    frame.receivers = 0;
    spheres.clear();
    frame.temporal.previous_world.clear();
    frame.temporal.moved = 0;
    let mut remembered = HashMap::new();
    for item in items {
        let index = frame.instances.len() as u32;
        if let Some(memory) = memory {
            let now = Mat4::from_cols_array_2d(&item.instance.world_from_local);
            let before = memory.world.get(&item.entity).copied().unwrap_or(now);
            if before != now {
                frame.temporal.moved += 1;
            }
            frame
                .temporal
                .previous_world
                .push(before.to_cols_array_2d());
            remembered.insert(item.entity, now);
        }
        add_to_batches(&mut frame.batches, &item, index);
        if let Some((center, radius)) = item.sphere {
            spheres.push((center, radius));
            if item.casts {
                let mask = item.maps.filter(|&m| {
                    item.blend
                        || frame
                            .material_maps
                            .get(m as usize)
                            .is_some_and(|entry| entry.maps.alpha_cutoff.is_some())
                });
                frame.casters.push(Caster {
                    instance: index,
                    mesh: item.mesh,
                    deformed: item.deformed,
                    center,
                    radius,
                    mask,
                    blend: item.blend,
                });
            }
        }
        frame.receivers += usize::from(item.instance.params[3] > 0.0);
        frame.instances.push(item.instance);
        if item.in_view {
            frame.triangles += meshes
                .get(item.mesh)
                .map_or(0, |m| m.triangle_count() as u64);
        }
    }
    remembered
}

/// Adds instance `index` (`item`) to the last batch where it draws the same way, else as
/// a new batch.
fn add_to_batches(batches: &mut Vec<Batch>, item: &Item, index: u32) {
    match batches.last_mut() {
        Some(b)
            if !item.transparent()
                && !b.transparent()
                && item.deformed.is_none()
                && b.deformed.is_none()
                && b.mesh == item.mesh
                && b.maps == item.maps
                && b.textured == item.textured
                && b.double_sided == item.double_sided =>
        {
            b.count += 1;
            b.visible += u32::from(item.in_view);
        }
        _ => batches.push(Batch {
            mesh: item.mesh,
            maps: item.maps,
            textured: item.textured,
            double_sided: item.double_sided,
            blend: item.blend,
            transmissive: item.transmissive,
            coated: item.coated,
            sheened: item.sheened,
            relit: item.relit,
            deformed: item.deformed,
            first_instance: index,
            count: 1,
            visible: u32::from(item.in_view),
        }),
    }
}

/// The normal matrix (inverse transpose of the upper 3×3) of `m`, as three padded
/// columns; `None` where `m` is singular or not finite.
fn normal_matrix(m: &Mat4) -> Option<[[f32; 4]; 3]> {
    let m3 = Mat3::from_mat4(*m);
    let det = m3.determinant();
    if !det.is_finite() || det.abs() < 1e-12 {
        return None;
    }
    let n = m3.inverse().transpose();
    Some([
        n.x_axis.extend(0.0).into(),
        n.y_axis.extend(0.0).into(),
        n.z_axis.extend(0.0).into(),
    ])
}

/// The bounding sphere (centre and radius, m) of a box under `m`.
fn sphere_around(aabb: &crate::scene::Aabb, m: &Mat4) -> (Vec3, f32) {
    let center = m.transform_point3(aabb.center());
    let scale = m
        .x_axis
        .truncate()
        .length()
        .max(m.y_axis.truncate().length())
        .max(m.z_axis.truncate().length());
    (center, (aabb.max - aabb.min).length() * 0.5 * scale)
}

/// `t` with its factor clamped to 0..1, its index of refraction to 1..10, and its
/// thickness in world metres: the mesh's thickness × the transform's mean scale (the cube
/// root of |det|, as glTF's volume thickness is in the mesh's own units). Non-finite or
/// negative thicknesses become 0 (thin-walled), NaN attenuation values their defaults.
fn world_transmission(t: &Transmission, world_from_local: &Mat4) -> Transmission {
    let scale = world_from_local.determinant().abs().cbrt();
    let thickness = finite_or(t.thickness_m, 0.0).max(0.0) * finite_or(scale, 1.0);
    Transmission {
        factor: finite_or(t.factor, 0.0).clamp(0.0, 1.0),
        ior: crate::shading::transmission::clamp_ior(t.ior),
        thickness_m: finite_or(thickness, 0.0),
        attenuation_color: Vec3::select(
            t.attenuation_color.cmpeq(t.attenuation_color),
            t.attenuation_color,
            Vec3::ONE,
        )
        .clamp(Vec3::ZERO, Vec3::ONE),
        attenuation_distance_m: if t.attenuation_distance_m.is_nan() {
            f32::INFINITY
        } else {
            t.attenuation_distance_m.max(0.0)
        },
        dispersion: finite_or(t.dispersion, 0.0).clamp(0.0, 1e3),
    }
}

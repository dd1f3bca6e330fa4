//! The path tracer's input from the rasterizer's extracted frame: the one place where
//! [`crate::reference::path`] meets the renderer, so that the reference depends on
//! nothing in [`crate::render`].

use crate::app::App;
use crate::error::{Error, Result};
use crate::reference::path::traced_scene::TraceCamera;
use crate::reference::path::{TraceInput, TraceInstance, TraceLight, TraceMaterial, TraceScene};
use crate::render::extract::ExtractedFrame;
use crate::scene::{MeshData, MeshHandle};
use glam::{Mat3, Mat4, Vec3};

/// Builds the trace scene of `app`'s current World: one rasterized frame at `size` runs
/// first, so that extraction (camera, exposure, instances, lights) is the rasterizer's.
/// Skinned and morphed instances are traced in the frame's pose: their vertices deformed
/// on the CPU ([`crate::scene::deform::Deformation::deformed_vertices`]) with the
/// frame's joint matrices and weights.
pub fn trace_scene(app: &mut App, size: (u32, u32)) -> Result<TraceScene> {
    app.render_headless(size)?;
    let world = app.world_mut();
    let environment = world
        .query::<&crate::scene::Environment>()
        .iter(world)
        .next()
        .cloned();
    let frame = world.resource::<ExtractedFrame>();
    let mut meshes = world.resource::<crate::scene::Meshes>().clone();
    let textures = world.resource::<crate::scene::Textures>();
    let quality = world.resource::<crate::quality::Quality>();
    let posed = posed_meshes(frame, &mut meshes);
    let input = trace_input(frame, &posed)?;
    Ok(TraceScene::new(
        &input,
        &meshes,
        textures,
        environment.as_ref(),
        quality,
    ))
}

/// Adds to `meshes` each deformed instance of `frame` in its pose; returns their handles
/// by deformed instance (`None` where the mesh or its deformation is missing).
fn posed_meshes(
    frame: &ExtractedFrame,
    meshes: &mut crate::scene::Meshes,
) -> Vec<Option<MeshHandle>> {
    let deformed = &frame.deformed;
    deformed
        .instances
        .iter()
        .map(|d| {
            let vertices = deformed.posed_vertices(d, meshes)?;
            let indices = meshes.get(d.mesh)?.indices.clone();
            meshes.add(MeshData { vertices, indices }).ok()
        })
        .collect()
}

/// The path tracer's view of `frame`: its instances in draw order (batch by batch), its
/// lights with the values the lighting pass reads (pre-exposed, as the same f32s), its
/// camera, exposure and background. A deformed instance `d` draws `posed[d]` (its posed
/// mesh) when there is one. An error if the frame has no camera.
pub fn trace_input(frame: &ExtractedFrame, posed: &[Option<MeshHandle>]) -> Result<TraceInput> {
    let camera = frame
        .camera
        .as_ref()
        .ok_or_else(|| Error::Scene("the scene has no camera".into()))?;
    let mut instances = Vec::with_capacity(frame.instances.len());
    for batch in &frame.batches {
        let range = batch.first_instance as usize..(batch.first_instance + batch.count) as usize;
        // The batch's forward-pass entry: transmission, layers and anisotropy.
        let entry = batch.maps.and_then(|m| frame.material_maps.get(m as usize));
        for inst in frame.instances.get(range).into_iter().flatten() {
            let [r, g, b, alpha] = inst.base_color;
            let [er, eg, eb, _] = inst.emissive_occlusion;
            instances.push(TraceInstance {
                mesh: batch
                    .deformed
                    .and_then(|d| posed.get(d as usize).copied().flatten())
                    .unwrap_or(batch.mesh),
                world_from_local: Mat4::from_cols_array_2d(&inst.world_from_local),
                normal_matrix: Mat3::from_cols(
                    Vec3::from_slice(&inst.normal_matrix[0][..3]),
                    Vec3::from_slice(&inst.normal_matrix[1][..3]),
                    Vec3::from_slice(&inst.normal_matrix[2][..3]),
                ),
                material: TraceMaterial {
                    base_color: Vec3::new(r, g, b),
                    metallic: inst.params[0],
                    roughness: inst.params[1],
                    specular_level: inst.params[2],
                    emissive: Vec3::new(er, eg, eb),
                    // The neutral maps a layered material without textures gets for
                    // the forward passes are not textures: the G-buffer draws it plain.
                    maps: batch.maps.filter(|_| batch.textured || batch.transparent()),
                    alpha,
                    blend: batch.blend,
                    transmission: entry.and_then(|e| e.transmission),
                    unlit: crate::shading::encoding::is_unlit(inst.params[2]),
                    clearcoat: entry.and_then(|e| e.clearcoat),
                    sheen: entry.and_then(|e| e.sheen),
                    anisotropy: entry.and_then(|e| e.anisotropy),
                    specular_tint: entry.and_then(|e| e.specular_tint),
                    iridescence: entry.and_then(|e| e.iridescence),
                    diffuse_transmission: entry.and_then(|e| e.diffuse_transmission),
                },
            });
        }
    }
    let directional = frame.light_counts.directional as usize;
    let point = frame.light_counts.point as usize;
    let lights = frame
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| {
            let color = Vec3::from_slice(&light.color_inv_range2[..3]);
            let inv_range2 = light.color_inv_range2[3];
            let position_m = Vec3::from_slice(&light.position[..3]);
            let direction = Vec3::from_slice(&light.direction[..3]);
            // A shadow view index of −1: the frame draws no shadow for this light.
            let casts_shadows = light.shadow[0] >= 0.0;
            if i < directional {
                TraceLight::Directional {
                    direction_to_light: direction,
                    illuminance: color,
                    tan_angular_radius: light.shadow[2],
                    casts_shadows,
                }
            } else if i < directional + point {
                TraceLight::Point {
                    position_m,
                    intensity: color,
                    inv_range2,
                    casts_shadows,
                }
            } else {
                TraceLight::Spot {
                    position_m,
                    axis: direction,
                    intensity: color,
                    inv_range2,
                    cone_scale: light.spot[0],
                    cone_offset: light.spot[1],
                    casts_shadows,
                }
            }
        })
        .collect();
    let [br, bg, bb, _] = frame.view.background;
    let world_from_view = camera.view_from_world.inverse();
    let lens = camera.depth_of_field.map(|_| {
        let radius = camera.focal_length_m / camera.lens.aperture_f_stops * 0.5;
        (radius, camera.lens.focus_distance_m)
    });
    Ok(TraceInput {
        instances,
        material_maps: frame
            .material_maps
            .iter()
            .map(|entry| entry.maps.clone())
            .collect(),
        lights,
        camera: TraceCamera {
            world_from_clip: Mat4::from_cols_array_2d(&frame.view.world_from_clip),
            position: camera.position,
            basis: Mat3::from_cols(
                world_from_view.x_axis.truncate().normalize(),
                world_from_view.y_axis.truncate().normalize(),
                -world_from_view.z_axis.truncate().normalize(),
            ),
            lens,
        },
        exposure: camera.exposure,
        background: Vec3::new(br, bg, bb),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::extract::{Batch, LightCounts};
    use crate::render::gpu_types::{GpuInstance, GpuLight};

    #[test]
    fn lights_and_instances_keep_the_extracted_values() {
        let mut frame = ExtractedFrame::default();
        assert!(trace_input(&frame, &[]).is_err(), "no camera");
        let light = |position: [f32; 4], direction: [f32; 4], color: [f32; 4], spot| GpuLight {
            position,
            direction,
            color_inv_range2: color,
            spot,
            shadow: [0.0, 1.0, 0.25, 0.0],
            ..GpuLight::default()
        };
        frame.lights = vec![
            light(
                [0.0; 4],
                [0.0, 1.0, 0.0, 0.0],
                [3.0, 2.0, 1.0, 0.0],
                [0.0; 4],
            ),
            light(
                [1.0, 2.0, 3.0, 1.0],
                [0.0; 4],
                [4.0, 5.0, 6.0, 0.01],
                [0.0; 4],
            ),
            light(
                [4.0, 5.0, 6.0, 1.0],
                [0.0, 0.0, -1.0, 0.0],
                [7.0, 8.0, 9.0, 0.04],
                [2.5, -1.5, 0.0, 0.0],
            ),
        ];
        // The point light has no shadow view: the frame draws no shadow for it.
        frame.lights[1].shadow[0] = -1.0;
        frame.light_counts = LightCounts {
            directional: 1,
            point: 1,
            spot: 1,
        };
        frame.instances = vec![
            GpuInstance {
                base_color: [0.5, 0.25, 2.0, 1.0],
                emissive_occlusion: [1.0, 2.0, 3.0, 1.0],
                params: [0.5, 0.75, 0.25, 1.0],
                ..GpuInstance::default()
            };
            3
        ];
        frame.batches = vec![Batch {
            mesh: crate::scene::MeshHandle(7),
            maps: Some(1),
            textured: true,
            double_sided: false,
            blend: false,
            transmissive: false,
            coated: false,
            sheened: false,
            relit: false,
            deformed: None,
            first_instance: 1,
            count: 2,
            visible: 2,
        }];
        frame.camera = Some(crate::render::extract::ExtractedCamera {
            position: Vec3::new(0.0, 1.0, 5.0),
            view_from_world: Mat4::from_translation(Vec3::new(0.0, -1.0, -5.0)),
            clip_from_view: Mat4::IDENTITY,
            exposure: 0.125,
            ev100: 0.0,
            tonemapper: Default::default(),
            lens: Default::default(),
            focal_length_m: 0.05,
            fov_y: 1.0,
            aspect: 1.0,
            depth_of_field: None,
            vignette: 0.0,
            auto_exposure: None,
            notes: Vec::new(),
        });
        let input = trace_input(&frame, &[]).expect("a camera");
        assert_eq!(
            input.lights,
            [
                TraceLight::Directional {
                    direction_to_light: Vec3::Y,
                    illuminance: Vec3::new(3.0, 2.0, 1.0),
                    tan_angular_radius: 0.25,
                    casts_shadows: true,
                },
                TraceLight::Point {
                    position_m: Vec3::new(1.0, 2.0, 3.0),
                    intensity: Vec3::new(4.0, 5.0, 6.0),
                    inv_range2: 0.01,
                    casts_shadows: false,
                },
                TraceLight::Spot {
                    position_m: Vec3::new(4.0, 5.0, 6.0),
                    axis: Vec3::NEG_Z,
                    intensity: Vec3::new(7.0, 8.0, 9.0),
                    inv_range2: 0.04,
                    cone_scale: 2.5,
                    cone_offset: -1.5,
                    casts_shadows: true,
                },
            ]
        );
        // Only the batched instances, with the batch's mesh and maps.
        assert_eq!(input.instances.len(), 2);
        let inst = input.instances[0];
        assert_eq!(inst.mesh, crate::scene::MeshHandle(7));
        let m = inst.material;
        assert_eq!(m.maps, Some(1));
        assert_eq!(m.base_color, Vec3::new(0.5, 0.25, 2.0));
        assert_eq!(m.emissive, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(
            (m.metallic, m.roughness, m.specular_level),
            (0.5, 0.75, 0.25)
        );
        assert_eq!(input.exposure, 0.125);
        assert_eq!(input.camera.position, Vec3::new(0.0, 1.0, 5.0));
        assert_eq!(
            input.camera.basis,
            Mat3::from_cols(Vec3::X, Vec3::Y, Vec3::NEG_Z)
        );
        assert_eq!(input.camera.lens, None);
        // A deformed batch traces its posed mesh.
        frame.batches[0].deformed = Some(1);
        let posed = [None, Some(crate::scene::MeshHandle(9))];
        let input = trace_input(&frame, &posed).expect("a camera");
        assert_eq!(input.instances[1].mesh, crate::scene::MeshHandle(9));
    }
}

//! Extraction: ECS components → plain, GPU-ready data for one frame.
//!
//! This is the only place the renderer reads the scene's components. Exposure is applied
//! here, in f32, to every light, emissive and background value before anything reaches a
//! 16-bit target (pre-exposure, PBR-REFERENCE §5).

use crate::color::Tonemapper;
use crate::error::Error;
use crate::punctual::spot_scale_offset;
use crate::render::frame::{FrameErrors, FrameOutput};
use crate::render::gpu_types::{GpuInstance, GpuLight, GpuView};
use crate::scene::{
    Camera, DirectionalLight, GlobalTransform, Material, Mesh3d, MeshHandle, Meshes, PointLight,
    SpotLight,
};
use bevy_ecs::prelude::*;
use glam::{Mat3, Mat4, Vec3};

/// The camera as the passes need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtractedCamera {
    /// World-space position in metres.
    pub position: Vec3,
    /// View from world.
    pub view_from_world: Mat4,
    /// Clip from view (reversed Z).
    pub clip_from_view: Mat4,
    /// Linear exposure multiplier applied to luminance.
    pub exposure: f32,
    /// The EV100 equivalent of `exposure`.
    pub ev100: f32,
    /// Tone mapper.
    pub tonemapper: Tonemapper,
}

/// Consecutive instances of one mesh, drawn with one instanced draw call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Batch {
    /// The mesh.
    pub mesh: MeshHandle,
    /// Index of the first instance in [`ExtractedFrame::instances`].
    pub first_instance: u32,
    /// Number of instances.
    pub count: u32,
}

/// Number of lights of each kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightCounts {
    /// Directional lights.
    pub directional: u32,
    /// Point lights.
    pub point: u32,
    /// Spot lights.
    pub spot: u32,
}

impl LightCounts {
    /// All lights.
    pub fn total(&self) -> u32 {
        self.directional + self.point + self.spot
    }
}

/// Everything one frame draws, extracted from the World.
#[derive(Resource, Default, Debug)]
pub struct ExtractedFrame {
    /// The active camera; `None` if the scene has none.
    pub camera: Option<ExtractedCamera>,
    /// Per-frame view uniform.
    pub view: GpuView,
    /// Instances, sorted by mesh.
    pub instances: Vec<GpuInstance>,
    /// Draw batches over `instances`.
    pub batches: Vec<Batch>,
    /// Lights: directional, then point, then spot.
    pub lights: Vec<GpuLight>,
    /// How many of each kind.
    pub light_counts: LightCounts,
    /// Triangles drawn by the G-buffer pass.
    pub triangles: u64,
}

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

fn finite_or(x: f32, fallback: f32) -> f32 {
    if x.is_finite() { x } else { fallback }
}

fn inv_range_squared(range_m: f32) -> f32 {
    if range_m.is_finite() && range_m > 0.0 {
        1.0 / (range_m * range_m)
    } else if range_m.is_finite() {
        // A zero or negative range reaches nothing: the smallest positive range.
        1.0 / (1e-6 * 1e-6)
    } else {
        0.0
    }
}

fn exposed(color: Vec3, intensity: f32, exposure: f32) -> [f32; 3] {
    let intensity = finite_or(intensity, 0.0).max(0.0);
    let v = color * (intensity * exposure);
    // Huge values stay finite in f32; the lighting pass clamps what it writes to f16.
    v.min(Vec3::splat(f32::MAX)).into()
}

/// Extracts the frame from the World (a system of the render schedule).
#[allow(clippy::too_many_arguments)]
pub fn extract_frame(
    cameras: Query<(Entity, &Camera, &GlobalTransform)>,
    drawables: Query<(&Mesh3d, &Material, &GlobalTransform)>,
    directional: Query<(&DirectionalLight, &GlobalTransform)>,
    points: Query<(&PointLight, &GlobalTransform)>,
    spots: Query<(&SpotLight, &GlobalTransform)>,
    meshes: Res<Meshes>,
    output: Res<FrameOutput>,
    mut frame: ResMut<ExtractedFrame>,
    mut errors: ResMut<FrameErrors>,
) {
    let frame = &mut *frame;
    let (width, height) = output.size;
    let aspect = width as f32 / height.max(1) as f32;

    let active = cameras
        .iter()
        .filter(|(_, c, _)| c.active)
        .min_by_key(|(e, _, _)| *e);
    let Some((_, camera, camera_transform)) = active else {
        frame.camera = None;
        errors.0.push(Error::Scene(
            "no active camera: spawn an entity with a Camera component".into(),
        ));
        return;
    };
    let exposure = camera.exposure.multiplier();
    let view_from_world = camera_transform.0.inverse();
    if !view_from_world.is_finite() {
        errors.0.push(Error::Scene(
            "the camera's transform is not invertible".into(),
        ));
        return;
    }
    let clip_from_view = camera.projection.matrix(aspect);
    let clip_from_world = clip_from_view * view_from_world;
    let position = camera_transform.translation();
    frame.camera = Some(ExtractedCamera {
        position,
        view_from_world,
        clip_from_view,
        exposure,
        ev100: camera.exposure.ev100(),
        tonemapper: camera.tonemapper,
    });

    // Instances, sorted by mesh so each mesh is one instanced draw.
    let mut items: Vec<(MeshHandle, GpuInstance)> = Vec::new();
    for (mesh, material, transform) in &drawables {
        if meshes.get(mesh.0).is_none() {
            log::warn!(
                "an entity refers to mesh {} which does not exist; skipped",
                mesh.0.0
            );
            continue;
        }
        let m = transform.0;
        // A degenerate (zero-scale) or non-finite transform draws nothing.
        let (Some(normal), true) = (normal_matrix(&m), m.is_finite()) else {
            continue;
        };
        let base = material.base_color;
        items.push((
            mesh.0,
            GpuInstance {
                world_from_local: m.to_cols_array_2d(),
                normal_matrix: normal,
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
                    finite_or(material.specular_level, 0.5),
                    0.0,
                ],
            },
        ));
    }
    items.sort_by_key(|(mesh, _)| *mesh);
    frame.instances.clear();
    frame.batches.clear();
    frame.triangles = 0;
    for (mesh, instance) in items {
        let index = frame.instances.len() as u32;
        match frame.batches.last_mut() {
            Some(b) if b.mesh == mesh => b.count += 1,
            _ => frame.batches.push(Batch {
                mesh,
                first_instance: index,
                count: 1,
            }),
        }
        frame.instances.push(instance);
        frame.triangles += meshes.get(mesh).map_or(0, |m| m.triangle_count() as u64);
    }

    // Lights: directional, point, spot.
    frame.lights.clear();
    let mut counts = LightCounts::default();
    for (light, transform) in &directional {
        let towards_light = -transform.forward();
        frame.lights.push(GpuLight {
            position: [0.0; 4],
            direction: towards_light.extend(0.0).into(),
            color_inv_range2: {
                let c = exposed(light.color.to_linear_rgb(), light.illuminance_lux, exposure);
                [c[0], c[1], c[2], 0.0]
            },
            spot: [0.0; 4],
        });
        counts.directional += 1;
    }
    for (light, transform) in &points {
        let c = exposed(light.color.to_linear_rgb(), light.candela(), exposure);
        frame.lights.push(GpuLight {
            position: transform.translation().extend(1.0).into(),
            direction: [0.0; 4],
            color_inv_range2: [c[0], c[1], c[2], inv_range_squared(light.range_m)],
            spot: [0.0; 4],
        });
        counts.point += 1;
    }
    for (light, transform) in &spots {
        let c = exposed(light.color.to_linear_rgb(), light.candela(), exposure);
        let (scale, offset) = spot_scale_offset(
            finite_or(light.inner_angle_rad, 0.0),
            finite_or(light.outer_angle_rad, 0.0),
        );
        frame.lights.push(GpuLight {
            position: transform.translation().extend(1.0).into(),
            direction: transform.forward().extend(0.0).into(),
            color_inv_range2: [c[0], c[1], c[2], inv_range_squared(light.range_m)],
            spot: [scale, offset, 0.0, 0.0],
        });
        counts.spot += 1;
    }
    frame.light_counts = counts;

    let background = exposed(camera.background.max(Vec3::ZERO), 1.0, exposure);
    frame.view = GpuView {
        clip_from_world: clip_from_world.to_cols_array_2d(),
        world_from_clip: clip_from_world.inverse().to_cols_array_2d(),
        position_exposure: position.extend(exposure).into(),
        viewport: [
            width as f32,
            height as f32,
            1.0 / width.max(1) as f32,
            1.0 / height.max(1) as f32,
        ],
        background: [background[0], background[1], background[2], 0.0],
        light_counts: [
            counts.directional,
            counts.point,
            counts.spot,
            counts.total(),
        ],
    };
}

//! The camera's extraction: the active camera (or the probe a capture looks from), its
//! resolved exposure and lens, the view uniform, and the camera's motion since the
//! previous frame.

use super::extracted_frame::{ExtractedCamera, ExtractedFrame, TemporalMemory, View, Viewpoint};
use super::values::{exposed, finite_or};
use crate::error::Error;
use crate::quality::Quality;
use crate::render::extract::shadow_views::CameraForShadows;
use crate::render::frame::{CaptureView, FrameErrors, FrameOutput, MeteredExposure};
use crate::render::gpu_types::GpuView;
use crate::render::jitter::Jitter;
use crate::scene::{Camera, GlobalTransform, Projection};
use bevy_ecs::prelude::*;
use glam::Mat4;

/// Extracts the camera into [`ExtractedFrame::camera`] and [`ExtractedFrame::view`] (its
/// light counts are the light extraction's), and hands the view to the later systems
/// through [`Viewpoint`]. Without an active camera, or with one whose transform does not
/// invert, it reports an error and the frame is not extracted.
#[allow(clippy::too_many_arguments)]
pub fn extract_viewpoint(
    cameras: Query<(Entity, &Camera, &GlobalTransform)>,
    quality: Res<Quality>,
    metered: Res<MeteredExposure>,
    output: Res<FrameOutput>,
    capture: Option<Res<CaptureView>>,
    jitter: Option<Res<Jitter>>,
    mut memory: ResMut<TemporalMemory>,
    mut frame: ResMut<ExtractedFrame>,
    mut viewpoint: ResMut<Viewpoint>,
    mut errors: ResMut<FrameErrors>,
) {
    viewpoint.0 = None;
    let frame = &mut *frame;
    let (width, height) = output.size;
    let aspect = width as f32 / height.max(1) as f32;
    let active = cameras
        .iter()
        .filter(|(_, c, _)| c.active)
        .min_by_key(|(e, _, _)| *e);
    let Some((_, camera, main_transform)) = active else {
        frame.camera = None;
        errors.0.push(Error::Scene(
            "no active camera: spawn an entity with a Camera component".into(),
        ));
        return;
    };
    let capture = capture.as_deref();
    // A probe capture looks from the probe, through a centred 90° frustum.
    let capture_transform = capture.map(|c| GlobalTransform(c.world_from_view));
    let camera_transform = capture_transform.as_ref().unwrap_or(main_transform);
    let projection = match capture {
        Some(c) => Projection {
            fov_y_rad: c.fov_y_rad,
            shift: glam::Vec2::ZERO,
            ..camera.projection
        },
        None => camera.projection,
    };
    let resolved = camera.resolve_exposure(metered.ev100);
    let exposure = resolved.multiplier;
    let view_from_world = camera_transform.0.inverse();
    if !view_from_world.is_finite() {
        errors.0.push(Error::Scene(
            "the camera's transform is not invertible".into(),
        ));
        return;
    }
    // Captures look through pixel centres; the frame samples where its jitter says.
    let jitter = match (capture, jitter) {
        (None, Some(j)) => *j,
        _ => Jitter::default(),
    };
    let clip_from_view = projection.matrix(aspect);
    let unjittered = clip_from_view * view_from_world;
    let clip_from_world = jitter.clip_matrix(output.size) * unjittered;
    if capture.is_none() {
        remember_motion(&mut memory, frame, unjittered, quality.aa.temporal());
    }
    let position = camera_transform.translation();
    let fov_y = projection.fov_y_rad;
    let focal_length_m = camera.lens.focal_length_m(fov_y);
    let (lens, mut notes) = camera.lens.clamped(focal_length_m);
    notes.extend(resolved.notes);
    notes.dedup();
    frame.camera = Some(ExtractedCamera {
        position,
        view_from_world,
        clip_from_view,
        exposure,
        ev100: resolved.ev100,
        tonemapper: camera.tonemapper,
        lens,
        focal_length_m,
        fov_y,
        aspect,
        depth_of_field: camera.depth_of_field.map(|d| crate::scene::DepthOfField {
            rings: quality.dof_rings.unwrap_or(d.rings).clamp(1, 5),
            max_coc_px: finite_or(d.max_coc_px, 32.0).clamp(1.0, 128.0),
        }),
        vignette: camera
            .vignette
            .map_or(0.0, |v| finite_or(v.strength, 0.0).clamp(0.0, 1.0)),
        auto_exposure: match camera.exposure {
            crate::scene::Exposure::Auto(a) => Some(a),
            _ => None,
        },
        notes,
    });
    let background = exposed(camera.background.max(glam::Vec3::ZERO), 1.0, exposure);
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
        light_counts: [0; 4],
        shadowed_counts: [0; 4],
        forward: camera_transform.forward().extend(0.0).into(),
        antialiasing: {
            let s = quality.aa.specular;
            [
                finite_or(s.screen_scale(), 0.0).max(0.0),
                finite_or(s.threshold(), 0.0).clamp(0.0, 1.0),
                jitter.offset_px.x,
                jitter.offset_px.y,
            ]
        },
    };
    // Captures fit directional cascades to the camera's frustum, not to theirs: every
    // face of every probe then shares one set of shadow views, drawn once per update.
    let shadow_camera = match capture {
        Some(c) => CameraForShadows {
            world_from_view: main_transform.0,
            fov_y: camera.projection.fov_y_rad,
            aspect: c.camera_aspect,
            near: camera.projection.near_m.max(1e-4),
            far: camera.projection.far_m,
        },
        None => CameraForShadows {
            world_from_view: camera_transform.0,
            fov_y: projection.fov_y_rad,
            aspect,
            near: projection.near_m.max(1e-4),
            far: projection.far_m,
        },
    };
    viewpoint.0 = Some(View {
        clip_from_world,
        position,
        exposure,
        shadow_camera,
        capture: capture.is_some(),
    });
}

/// This frame's and the previous frame's unjittered clip-from-world matrices (the same
/// matrix unless TAA runs, `temporal`), and this one remembered for the next.
fn remember_motion(
    memory: &mut TemporalMemory,
    frame: &mut ExtractedFrame,
    unjittered: Mat4,
    temporal: bool,
) {
    let previous = if temporal {
        memory.clip_from_world.unwrap_or(unjittered)
    } else {
        unjittered
    };
    frame.temporal.clip_from_world = unjittered;
    frame.temporal.previous_clip_from_world = previous;
    memory.clip_from_world = Some(unjittered);
}

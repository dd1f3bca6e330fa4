//! Probe captures: the lit scene seen from a probe, rendered by the frame's own capture
//! passes ([`crate::render::graph::FramePass::CAPTURE`]: shadows, G-buffer, light culling,
//! lighting, sky) into six square 90° views, each reduced into the probe's record
//! ([`crate::render::indirect::irradiance_volume`]).
//!
//! A capture runs the [`ExtractSchedule`] with a [`CaptureView`] in place of the camera,
//! then the [`CaptureSchedule`], into targets of its own (swapped in, so the frame's
//! targets survive), and submits; the GPU works through the faces while the next one is
//! recorded. The camera's exposure pre-exposes the capture as it does the frame, and the
//! reduction divides it out, so probe light is stored in physical units.

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use crate::render::frame::{CaptureView, FrameEncoder, FrameErrors, FrameOutput};
use crate::render::indirect::irradiance_volume::{IrradianceVolumeGpu, grid_for, scene_changed};
use crate::render::shadow::pass::ShadowPass;
use crate::render::targets::RenderTargets;
use crate::render::{CaptureSchedule, ExtractSchedule};
use bevy_ecs::prelude::*;
use glam::{Mat4, UVec3, Vec3};
use std::time::Instant;

/// The six views of a cube capture: the axis each looks along and its up direction.
pub const FACES: [(Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::Y),
    (Vec3::NEG_X, Vec3::Y),
    (Vec3::Y, Vec3::NEG_Z),
    (Vec3::NEG_Y, Vec3::Z),
    (Vec3::Z, Vec3::Y),
    (Vec3::NEG_Z, Vec3::Y),
];

/// What the volume did before a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VolumeStatus {
    /// Probes along each axis (zero without a volume).
    pub counts: UVec3,
    /// Capture passes completed, and how many the volume converges in.
    pub passes: (u32, u32),
    /// Cube faces captured before this frame.
    pub faces_captured: u32,
    /// Time those captures took (ms, CPU and GPU, waited for).
    pub capture_ms: f64,
    /// Why there is no volume, when there is none.
    pub skip_reason: Option<String>,
}

/// Places the scene's irradiance volume, restarts its capture when the scene changed, and
/// captures up to `budget` probes (`None`: until it converges).
pub fn update_irradiance_volume(world: &mut World, budget: Option<u32>) -> Result<VolumeStatus> {
    let start = Instant::now();
    let changed = world.run_system_cached(scene_changed).unwrap_or(true);
    // The atlas may hold views of casters that have moved since the last round.
    world.resource_mut::<ShadowPass>().captured_views = None;
    let camera_aspect = world
        .get_resource::<FrameOutput>()
        .map_or(1.0, |o| o.size.0 as f32 / o.size.1.max(1) as f32);
    let gi = world.resource::<crate::quality::Quality>().gi;
    let grid = grid_for(world, &gi);
    let gpu = world.resource::<Gpu>().clone();
    let mut volume = world.resource_mut::<IrradianceVolumeGpu>();
    let wanted = grid.as_ref().ok().copied();
    if volume.grid != wanted {
        volume.set_grid(&gpu, wanted);
    } else if changed {
        volume.restart();
    }
    if let Err(reason) = grid {
        volume.skip_reason = reason.clone();
        return Ok(VolumeStatus {
            skip_reason: Some(reason),
            ..VolumeStatus::default()
        });
    }
    let mut left = budget.map(|b| b.max(1));
    let mut faces = 0;
    while !world.resource::<IrradianceVolumeGpu>().converged() && left != Some(0) {
        let probe = world.resource::<IrradianceVolumeGpu>().next_probe;
        for face in 0..FACES.len() as u32 {
            capture_face(world, &gpu, probe, face, camera_aspect)?;
            faces += 1;
        }
        let exposure = world
            .resource::<crate::render::extract::ExtractedFrame>()
            .camera
            .as_ref()
            .map_or(1.0, |c| c.exposure);
        world
            .resource_mut::<IrradianceVolumeGpu>()
            .probe_done(&gpu, exposure)?;
        left = left.map(|l| l - 1);
    }
    if faces > 0 {
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| Error::Gpu(format!("waiting for probe captures: {e}")))?;
    }
    let mut volume = world.resource_mut::<IrradianceVolumeGpu>();
    volume.faces_captured += u64::from(faces);
    Ok(VolumeStatus {
        counts: volume.grid.map_or(UVec3::ZERO, |g| g.counts),
        passes: (
            volume.completed_passes,
            volume.grid.map_or(0, |g| g.bounces),
        ),
        faces_captured: faces,
        capture_ms: start.elapsed().as_secs_f64() * 1e3,
        skip_reason: None,
    })
}

/// Renders face `face` of probe `probe` and records its reduction; submits.
fn capture_face(
    world: &mut World,
    gpu: &Gpu,
    probe: u32,
    face: u32,
    camera_aspect: f32,
) -> Result<()> {
    let mut volume = world.resource_mut::<IrradianceVolumeGpu>();
    let Some(grid) = volume.grid else {
        return Ok(());
    };
    let (axis, up) = FACES[face as usize];
    let view_from_world = Mat4::look_to_rh(grid.position(probe), axis, up);
    volume.capturing = Some((probe, face));
    let mut targets = std::mem::take(&mut volume.capture_targets);
    std::mem::swap(&mut targets, &mut *world.resource_mut::<RenderTargets>());
    world.insert_resource(CaptureView {
        world_from_view: view_from_world.inverse(),
        fov_y_rad: std::f32::consts::FRAC_PI_2,
        camera_aspect,
    });
    world.insert_resource(FrameOutput {
        size: (grid.face_size, grid.face_size),
        view: None,
        format: wgpu::TextureFormat::Rgba8Unorm,
    });
    world.resource_mut::<FrameErrors>().0.clear();
    world.run_schedule(ExtractSchedule);
    if world.resource::<FrameErrors>().0.is_empty() {
        world.run_schedule(CaptureSchedule);
    }
    let encoder = world.resource_mut::<FrameEncoder>().encoder.take();
    std::mem::swap(&mut targets, &mut *world.resource_mut::<RenderTargets>());
    let mut volume = world.resource_mut::<IrradianceVolumeGpu>();
    volume.capture_targets = targets;
    volume.capturing = None;
    world.remove_resource::<CaptureView>();
    if let Some(e) = world.resource_mut::<FrameErrors>().0.drain(..).next() {
        return Err(Error::Gpu(format!(
            "capturing probe {probe}, face {face}: {e}"
        )));
    }
    if let Some(encoder) = encoder {
        gpu.checked("probe capture", |_| gpu.queue.submit([encoder.finish()]))?;
    }
    Ok(())
}

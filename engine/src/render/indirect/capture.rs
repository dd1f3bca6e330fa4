//! Probe captures: the lit scene seen from a probe, rendered by the frame's own capture
//! passes ([`crate::render::graph::FramePass::CAPTURE`]: shadows, G-buffer, light culling,
//! lighting, sky) into six square 90° views. Each view is reduced into an irradiance
//! probe's record ([`crate::render::indirect::probe_volume`]) or copied into a
//! reflection probe's cube ([`crate::render::indirect::reflection_probes`]).
//!
//! A capture runs the [`ExtractSchedule`] with a [`CaptureView`] in place of the camera,
//! then the [`CaptureSchedule`], into targets of its own (swapped in, so the frame's
//! targets survive), and submits; the GPU works through a probe's faces while the next
//! ones are recorded, and each probe is waited for before the next begins. The camera's exposure pre-exposes the capture as it does the frame; probe
//! light keeps that exposure beside it, so the frame rescales it to its own.

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{CaptureTarget, CaptureView, FrameEncoder, FrameErrors, FrameOutput};
use crate::render::indirect::environment_maps::{Ibl, face_strip};
use crate::render::indirect::probe_volume::{IrradianceVolumeGpu, grid_for, scene_changed};
use crate::render::indirect::reflection_probes::{CapturedProbe, ReflectionProbesGpu, probes_for};
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

/// What the irradiance volume did before a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VolumeStatus {
    /// Probes along each axis (zero without a volume).
    pub counts: UVec3,
    /// Capture passes completed, and how many the volume converges in.
    pub passes: (u32, u32),
    /// Cube faces captured before this frame.
    pub faces_captured: u32,
    /// Why there is no volume, when there is none.
    pub skip_reason: Option<String>,
}

/// What the reflection probes did before a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReflectionStatus {
    /// Probes placed.
    pub probes: u32,
    /// Probes captured (and prefiltered) before this frame.
    pub captured: u32,
    /// Why there are no probes, when there are none.
    pub skip_reason: Option<String>,
}

/// What the probes did before a frame, and how long it took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProbeStatus {
    /// The irradiance volume.
    pub volume: VolumeStatus,
    /// The reflection probes.
    pub reflections: ReflectionStatus,
    /// Time the captures took (ms, CPU and GPU, waited for).
    pub capture_ms: f64,
}

/// [`update_probes`] within this frame's budget: where the app renders `progressive`ly
/// (a viewer, a frame per call), the quality settings' probes per frame (0: no limit);
/// otherwise everything, so a still image is captured in one call.
pub fn update_probes_for_frame(world: &mut World, progressive: bool) -> Result<ProbeStatus> {
    let per_frame = world
        .get_resource::<crate::quality::Quality>()
        .map_or(0, |q| q.gi.probes_per_frame);
    let budget = (progressive && per_frame > 0).then_some(per_frame);
    update_probes(world, budget)
}

/// Places the scene's irradiance volume and reflection probes, restarts their captures
/// when the scene changed, and captures: up to `budget` irradiance probes and, once the
/// volume has converged, one reflection probe (`None`: everything, until both converge).
pub fn update_probes(world: &mut World, budget: Option<u32>) -> Result<ProbeStatus> {
    let start = Instant::now();
    let changed = world.run_system_cached(scene_changed).unwrap_or(true);
    let camera_aspect = world
        .get_resource::<FrameOutput>()
        .map_or(1.0, |o| o.size.0 as f32 / o.size.1.max(1) as f32);
    let gpu = world.resource::<Gpu>().clone();
    world
        .resource_mut::<IrradianceVolumeGpu>()
        .set_capturing(&gpu, true);
    let updated = update_volume(world, &gpu, changed, budget, camera_aspect).and_then(|volume| {
        Ok((
            volume,
            update_reflections(world, &gpu, changed, budget, camera_aspect)?,
        ))
    });
    world
        .resource_mut::<IrradianceVolumeGpu>()
        .set_capturing(&gpu, false);
    let (volume, reflections) = updated?;
    if volume.faces_captured > 0 || reflections.captured > 0 {
        wait_for_gpu(&gpu)?;
    }
    Ok(ProbeStatus {
        volume,
        reflections,
        capture_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

/// Waits until the GPU has done every submitted capture: once per probe, so that at most
/// six faces are in flight at a time.
fn wait_for_gpu(gpu: &Gpu) -> Result<()> {
    gpu.device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .map(|_| ())
        .map_err(|e| Error::Gpu(format!("waiting for probe captures: {e}")))
}

fn camera_exposure(world: &World) -> f32 {
    world
        .resource::<ExtractedFrame>()
        .camera
        .as_ref()
        .map_or(1.0, |c| c.exposure)
}

fn update_volume(
    world: &mut World,
    gpu: &Gpu,
    changed: bool,
    budget: Option<u32>,
    camera_aspect: f32,
) -> Result<VolumeStatus> {
    let gi = world.resource::<crate::quality::Quality>().gi;
    let grid = grid_for(world, &gi);
    let mut volume = world.resource_mut::<IrradianceVolumeGpu>();
    let wanted = grid.as_ref().ok().copied();
    if volume.grid != wanted {
        volume.set_grid(gpu, wanted);
    } else if changed {
        volume.restart(gpu);
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
        let volume = world.resource::<IrradianceVolumeGpu>();
        let (Some(grid), probe) = (volume.grid, volume.next_probe) else {
            break;
        };
        for face in 0..FACES.len() as u32 {
            let view = capture_view(grid.position(probe), face, camera_aspect);
            capture_face(
                world,
                gpu,
                CaptureView {
                    target: CaptureTarget::IrradianceProbe(probe),
                    ..view
                },
                grid.face_size,
            )?;
            faces += 1;
        }
        wait_for_gpu(gpu)?;
        let exposure = camera_exposure(world);
        world
            .resource_mut::<IrradianceVolumeGpu>()
            .probe_done(gpu, exposure)?;
        left = left.map(|l| l - 1);
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
        skip_reason: None,
    })
}

fn update_reflections(
    world: &mut World,
    gpu: &Gpu,
    changed: bool,
    budget: Option<u32>,
    camera_aspect: f32,
) -> Result<ReflectionStatus> {
    let quality = world.resource::<crate::quality::Quality>().clone();
    let placed = probes_for(world, &quality.reflection_probes);
    let mut probes = world.resource_mut::<ReflectionProbesGpu>();
    match &placed {
        Ok(p) => probes.place(gpu, p.clone()),
        Err(reason) => {
            probes.place(gpu, Vec::new());
            probes.skip_reason = reason.clone();
            return Ok(ReflectionStatus {
                skip_reason: Some(reason.clone()),
                ..ReflectionStatus::default()
            });
        }
    }
    if changed {
        probes.stale.iter_mut().for_each(|s| *s = true);
    }
    let placed_count = probes.placed.len() as u32;
    // Probes see the volume's light: they wait for it to converge.
    if !world.resource::<IrradianceVolumeGpu>().converged() {
        return Ok(ReflectionStatus {
            probes: placed_count,
            ..ReflectionStatus::default()
        });
    }
    let size = quality
        .reflection_probes
        .face_size
        .clamp(16, 256)
        .next_power_of_two();
    let mut captured = 0;
    while let Some(slot) = world.resource::<ReflectionProbesGpu>().next_stale() {
        if budget.is_some() && captured > 0 {
            break;
        }
        let placed = world.resource::<ReflectionProbesGpu>().placed[slot];
        world.resource_mut::<ReflectionProbesGpu>().strip = Some(face_strip(gpu, size));
        for face in 0..FACES.len() as u32 {
            let view = capture_view(placed.position, face, camera_aspect);
            capture_face(
                world,
                gpu,
                CaptureView {
                    target: CaptureTarget::ReflectionProbe(slot as u32),
                    ..view
                },
                size,
            )?;
        }
        let exposure = camera_exposure(world);
        let Some(strip) = world.resource_mut::<ReflectionProbesGpu>().strip.take() else {
            break;
        };
        // The roughest mip keeps faces of 4² texels: at 1² the cube's filtering across
        // faces differs between backends (GL and Vulkan by up to 14/255 on `spheres`).
        let cube = world.resource_mut::<Ibl>().prefilter_strip(
            gpu,
            strip,
            size,
            quality.ibl_samples,
            size.ilog2() - 1,
            None,
        )?;
        world.resource_mut::<ReflectionProbesGpu>().set_captured(
            gpu,
            slot,
            CapturedProbe {
                placed,
                cube,
                exposure,
            },
        );
        captured += 1;
    }
    Ok(ReflectionStatus {
        probes: placed_count,
        captured,
        skip_reason: None,
    })
}

/// The view of cube face `face` from `position`.
fn capture_view(position: Vec3, face: u32, camera_aspect: f32) -> CaptureView {
    let (axis, up) = FACES[face as usize];
    CaptureView {
        world_from_view: Mat4::look_to_rh(position, axis, up).inverse(),
        fov_y_rad: std::f32::consts::FRAC_PI_2,
        camera_aspect,
        target: CaptureTarget::IrradianceProbe(0),
        face,
    }
}

/// Renders one face through the capture schedule (which records its reduction or copy)
/// and submits it.
fn capture_face(world: &mut World, gpu: &Gpu, view: CaptureView, size: u32) -> Result<()> {
    let mut volume = world.resource_mut::<IrradianceVolumeGpu>();
    let mut targets = std::mem::take(&mut volume.capture_targets);
    std::mem::swap(&mut targets, &mut *world.resource_mut::<RenderTargets>());
    world.insert_resource(view);
    world.insert_resource(FrameOutput {
        size: (size, size),
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
    world.resource_mut::<IrradianceVolumeGpu>().capture_targets = targets;
    world.remove_resource::<CaptureView>();
    let error = world.resource_mut::<FrameErrors>().0.drain(..).next();
    if let Some(e) = error {
        // The capture's commands are dropped: its shadow atlas was not drawn.
        world
            .resource_mut::<crate::render::shadow::pass::ShadowPass>()
            .forget();
        return Err(Error::Gpu(format!(
            "capturing {:?}, face {}: {e}",
            view.target, view.face
        )));
    }
    if let Some(encoder) = encoder {
        gpu.checked("probe capture", |_| gpu.queue.submit([encoder.finish()]))?;
    }
    Ok(())
}

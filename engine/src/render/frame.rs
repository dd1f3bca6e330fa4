//! Per-frame state shared by the render systems: the output target, the command encoder,
//! errors raised while building the frame, the time step, and what automatic exposure
//! metered.

use crate::error::Error;
use crate::render::timing::GpuTimer;
use bevy_ecs::prelude::Resource;

/// Where this frame's display image goes.
#[derive(Resource)]
pub struct FrameOutput {
    /// Size in pixels.
    pub size: (u32, u32),
    /// The view to render the display image into (headless texture or window surface).
    pub view: Option<wgpu::TextureView>,
    /// Its format.
    pub format: wgpu::TextureFormat,
}

/// Errors raised by render systems; the frame is abandoned when any is present.
#[derive(Resource, Default, Debug)]
pub struct FrameErrors(pub Vec<Error>);

/// The command encoder of the frame being built, and its timer.
#[derive(Resource)]
pub struct FrameEncoder {
    /// The encoder; `None` outside a frame.
    pub encoder: Option<wgpu::CommandEncoder>,
    /// Per-pass CPU and GPU timing.
    pub timer: GpuTimer,
}

impl FrameEncoder {
    /// Records one timed full-screen draw labelled `name`
    /// ([`crate::render::pipelines::draw_fullscreen`]) while a frame records and
    /// `pipeline` and `group` exist; nothing otherwise (the pass's preparation reported
    /// why).
    pub fn fullscreen(
        &mut self,
        name: &'static str,
        targets: &[&wgpu::TextureView],
        pipeline: Option<&wgpu::RenderPipeline>,
        group: Option<&wgpu::BindGroup>,
    ) {
        if let (Some(encoder), Some(pipeline), Some(group)) =
            (self.encoder.as_mut(), pipeline, group)
        {
            crate::render::pipelines::draw_fullscreen(
                encoder,
                &mut self.timer,
                name,
                targets,
                pipeline,
                group,
            );
        }
    }
}

/// What the meter saw, read back after the last frame.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct MeteredExposure {
    /// The adapted EV100 the next frame uses (automatic exposure only).
    pub ev100: Option<f32>,
    /// The EV100 the meter aims at (clamped to the camera's range).
    pub target_ev100: Option<f32>,
    /// log2 of the metered average scene luminance (cd/m²).
    pub average_log2_luminance: Option<f32>,
}

/// Seconds between frames, for adaptation over time. The app sets it each frame.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct FrameDelta(pub f32);

impl Default for FrameDelta {
    fn default() -> Self {
        FrameDelta(1.0 / 60.0)
    }
}

/// Present while a probe capture renders: extraction uses this view instead of the active
/// camera's (a 90° square frustum looking along one cube-face axis), with the camera's
/// own exposure and clip distances.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct CaptureView {
    /// World from view (the probe's position, looking along the face's axis).
    pub world_from_view: glam::Mat4,
    /// Vertical field of view (rad): π/2 for a cube face.
    pub fov_y_rad: f32,
    /// Width / height of the camera's own frame: directional shadow cascades are fitted
    /// to the camera's frustum, not the capture's.
    pub camera_aspect: f32,
    /// What the capture is for.
    pub target: CaptureTarget,
    /// The cube face, 0–5 (+x, −x, +y, −y, +z, −z).
    pub face: u32,
}

/// What a probe capture feeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CaptureTarget {
    /// Probe `i` of the irradiance volume.
    IrradianceProbe(u32),
    /// Reflection probe slot `i`.
    ReflectionProbe(u32),
}

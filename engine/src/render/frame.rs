//! Per-frame state shared by the render systems: the output target, the command encoder,
//! and errors raised while building the frame.

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

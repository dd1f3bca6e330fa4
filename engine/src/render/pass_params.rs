//! The system parameters most passes' systems take, so that a pass's systems name what
//! they add to them: [`Prepare`] for a preparation (compile, size, bind) and [`Record`]
//! for a recording (encode the draws and dispatches).

use crate::render::device::Gpu;
use crate::render::frame::FrameEncoder;
use crate::render::graph::{FramePass, FramePlan};
use crate::render::targets::RenderTargets;
use bevy_ecs::component::{Component, Mutable};
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;

/// What a pass's preparation takes: the device, this frame's plan (the pass's variant),
/// the frame's targets, and the pass itself, to change.
#[derive(SystemParam)]
pub struct Prepare<'w, P: FramePass + Component<Mutability = Mutable>> {
    /// The device.
    pub gpu: Res<'w, Gpu>,
    /// This frame's plan.
    pub plan: Res<'w, FramePlan>,
    /// The frame's textures and buffers.
    pub targets: Res<'w, RenderTargets>,
    /// The pass.
    pub pass: ResMut<'w, P>,
}

/// What a pass's recording takes: the pass, this frame's plan, the frame's targets and
/// the frame's command encoder.
#[derive(SystemParam)]
pub struct Record<'w, P: FramePass> {
    /// The pass.
    pub pass: Res<'w, P>,
    /// This frame's plan.
    pub plan: Res<'w, FramePlan>,
    /// The frame's textures and buffers.
    pub targets: Res<'w, RenderTargets>,
    /// The frame's encoder and timer.
    pub encoder: ResMut<'w, FrameEncoder>,
}

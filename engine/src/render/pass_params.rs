//! The system parameters most passes' systems take, so that a pass's systems name what
//! they add to them: [`Prepare`] for a preparation (compile, size, bind) and [`Record`]
//! for a recording (encode the draws and dispatches); and the usual pair of systems a
//! pass schedules ([`crate::pass_systems!`]), its preparation's error kept for the frame
//! ([`fallible`]).

use crate::error::Result;
use crate::render::device::Gpu;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::{FramePass, FramePlan, PassSystems};
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

/// `system`, a preparation that returns a [`Result`], as [`PassSystems`]: its error goes
/// to [`FrameErrors`], which abandons the frame.
pub fn fallible<M>(system: impl IntoSystem<(), Result<()>, M>) -> PassSystems {
    system.pipe(report_error).into_configs()
}

/// Keeps a preparation's error for the frame to report.
fn report_error(In(result): In<Result<()>>, mut errors: ResMut<FrameErrors>) {
    if let Err(e) = result {
        errors.0.push(e);
    }
}

/// The usual [`FramePass::prepare`] and [`FramePass::record`]: one system each, the
/// preparation returning a [`Result`]. `lumen::pass_systems!(prepare_x, x_pass);` inside
/// `impl FramePass for XPass` stands for
///
/// ```text
/// fn prepare() -> Option<PassSystems> { Some(fallible(prepare_x)) }
/// fn record() -> PassSystems { systems(x_pass) }
/// ```
#[macro_export]
macro_rules! pass_systems {
    ($prepare:expr, $record:expr) => {
        fn prepare() -> Option<$crate::render::graph::PassSystems> {
            Some($crate::render::pass_params::fallible($prepare))
        }

        fn record() -> $crate::render::graph::PassSystems {
            $crate::render::graph::systems($record)
        }
    };
}

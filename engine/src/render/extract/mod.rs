//! Extraction: ECS components → plain, GPU-ready data for one frame.
//!
//! This is the only place the renderer reads the scene's components. The
//! [`crate::render::ExtractSchedule`] runs one system per domain, in this order:
//!
//! 1. [`viewpoint`]: the active camera (or the probe a capture looks from), its exposure,
//!    the view uniform and the camera's motion since the previous frame;
//! 2. [`instances`]: the drawn instances, their batches and material maps, the shadow
//!    casters, and each instance's previous transform (motion vectors);
//! 3. [`shadow_casting`]: the shadow views of every light that casts;
//! 4. [`lights`]: the lights, in the order the lighting shader loops over them;
//! 5. [`environment_light`]: the environment.
//!
//! [`reflecting`] is no system: it says whether the frame has screen-space reflections to
//! trace, for the passes of several stages that take part in them.
//!
//! Each writes its part of [`ExtractedFrame`]; what a later one needs of an earlier one
//! beyond that travels in [`Viewpoint`], [`InstanceSpheres`] and [`LightShadows`].
//! Skinned and morphed instances are gathered by [`deformed`].
//!
//! Exposure is applied here, in f32, to every light, emissive and background value before
//! anything reaches a 16-bit target (pre-exposure, docs/src/formulas.md#numerical-guards).

pub mod deformed;
pub mod environment_light;
pub mod extracted_frame;
pub mod instances;
pub mod lights;
pub mod reflecting;
pub mod shadow_casting;
pub mod shadow_views;
pub mod values;
pub mod viewpoint;

pub use extracted_frame::*;

use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

/// Inserts what extraction keeps between its systems and across frames.
pub fn init(world: &mut World) {
    world.init_resource::<TemporalMemory>();
    world.init_resource::<Viewpoint>();
    world.init_resource::<InstanceSpheres>();
    world.init_resource::<LightShadows>();
    world.insert_resource(ExtractedFrame::default());
}

/// The extraction systems, in their order.
pub fn systems() -> ScheduleConfigs<ScheduleSystem> {
    (
        viewpoint::extract_viewpoint,
        instances::extract_instances,
        shadow_casting::extract_shadow_views,
        lights::extract_lights,
        environment_light::extract_environment,
    )
        .chain()
}

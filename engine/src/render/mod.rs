//! The renderer: device choice, the frame graph, and one module per pass.
//!
//! A frame runs the [`ExtractSchedule`] (components → [`extract::ExtractedFrame`]) and
//! then the [`RenderSchedule`], which the [`graph::registry::Registry`] builds from the passes'
//! declarations: plan (every pass decides whether it runs, and why), the shared
//! preparation (targets, scene buffers, material maps, the environment), each running
//! pass's prepare systems, then each running pass's record systems in execution order —
//! shadow, G-buffer, light culling, lighting, sky, exposure, depth of field, tone mapping
//! (or a debug view) — each recording into the frame's command encoder with its own
//! timing. The built-in passes are listed in [`passes`].

pub mod bindings;
pub mod device;
pub mod extract;
pub mod frame;
pub mod fullscreen_step;
pub mod geometry;
pub mod gpu_types;
pub mod graph;
pub mod indirect;
pub mod jitter;
pub mod lighting;
pub mod pass_params;
pub mod passes;
pub mod pipeline_cache;
pub mod pipelines;
pub mod post;
pub mod rays;
pub mod readback;
pub mod scaled_output;
pub mod scene_buffers;
pub mod shaders;
pub mod shadow;
pub mod targets;
pub mod timing;
pub mod transparent;

use crate::error::Result;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::{ScheduleConfigs, ScheduleLabel};
use bevy_ecs::system::ScheduleSystem;
use device::Gpu;
use frame::{FrameEncoder, FrameErrors, FrameOutput};
use graph::FramePlan;
use graph::registry::Registry;

/// Reads the scene's components into [`extract::ExtractedFrame`].
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExtractSchedule;

/// Plans, prepares and records the frame's passes.
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct RenderSchedule;

/// Plans, prepares and records one probe capture: the passes that make lit radiance
/// ([`graph::FramePass::CAPTURE`]), then the reduction of the captured face into the
/// probe ([`indirect::probe_volume`]).
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct CaptureSchedule;

/// The output's size and the HDR format, which size the plan's resources.
fn frame_shape(world: &World) -> ((u32, u32), wgpu::TextureFormat) {
    let size = world
        .get_resource::<FrameOutput>()
        .map_or((1, 1), |o| o.size);
    let hdr = world
        .get_resource::<crate::quality::Quality>()
        .map_or(wgpu::TextureFormat::Rgba16Float, |q| {
            q.hdr_precision.format()
        });
    (size, hdr)
}

/// Asks every registered pass whether it runs this frame.
fn plan_frame(world: &mut World) {
    let (size, hdr) = frame_shape(world);
    let plan = world.resource::<Registry>().plan(world, size, hdr);
    *world.resource_mut::<FramePlan>() = plan;
}

/// Asks the capture passes whether they run in this capture.
fn plan_capture(world: &mut World) {
    let (size, hdr) = frame_shape(world);
    let plan = world
        .resource::<Registry>()
        .capture_subset()
        .plan(world, size, hdr);
    *world.resource_mut::<FramePlan>() = plan;
}

/// Allocates the textures and buffers the passes that run this frame use, as the plan
/// assigned them.
fn prepare_targets(
    gpu: Res<Gpu>,
    output: Res<FrameOutput>,
    quality: Res<crate::quality::Quality>,
    plan: Res<FramePlan>,
    mut targets: ResMut<targets::RenderTargets>,
) {
    targets.allocate(
        &gpu,
        output.size,
        quality.hdr_precision.format(),
        &plan.resources,
    );
}

/// Opens the frame's command encoder.
fn begin_frame(gpu: Res<Gpu>, mut encoder: ResMut<FrameEncoder>) {
    encoder.timer.begin_frame();
    encoder.encoder = Some(
        gpu.device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            }),
    );
}

/// Inserts the renderer's resources into `world` and adds the extract and render
/// schedules. Compiles the passes that do not depend on the scene. Called again with a
/// new device (after the old one was lost), it replaces every GPU resource: meshes and
/// textures upload again from the CPU copies the World keeps. The passes are the built-in
/// ones the first time, and those of the world's [`Registry`] afterwards (so passes a
/// script added stay).
pub fn install(world: &mut World, gpu: Gpu) -> Result<()> {
    if !world.contains_resource::<Registry>() {
        world.insert_resource(passes::builtin()?);
    }
    world.insert_resource(geometry::gpu_material_maps::GpuMaterialMaps::new(
        &gpu,
        extension_units_fit(&gpu.device.limits()),
    ));
    world.init_resource::<crate::scene::Textures>();
    world.init_resource::<frame::MeteredExposure>();
    world.init_resource::<frame::FrameDelta>();
    extract::init(world);
    world.init_resource::<post::antialias::taa::TaaState>();
    world.insert_resource(scene_buffers::SceneBuffers::new(&gpu));
    world.insert_resource(FrameEncoder {
        encoder: None,
        timer: timing::GpuTimer::new(&gpu),
    });
    world.insert_resource(targets::RenderTargets::default());
    world.init_resource::<FramePlan>();
    world.init_resource::<graph::slots::KeptSlots>();
    world.init_resource::<FrameErrors>();
    world.init_resource::<post::debug_view::DebugView>();
    insert_passes(world, &gpu)?;
    world.insert_resource(gpu);

    let mut extract = Schedule::new(ExtractSchedule);
    extract.add_systems(extract::systems());
    world.add_schedule(extract);
    build_render_schedule(world);
    Ok(())
}

/// Whether the material maps' extension units fit in the adapter's per-stage limits beside
/// everything else the pass with the most textures binds: the transparent pass (its
/// view group, the lighting pass's groups 1 to 3 and the maps). Where they do not (16
/// textures per stage on OpenGL ES 3, for one), extension textures are not sampled
/// ([`geometry::gpu_material_maps::CORE_BINDINGS`]).
pub fn extension_units_fit(limits: &wgpu::Limits) -> bool {
    let (textures, samplers) = [
        transparent::VIEW,
        lighting::LIGHTS_AND_SHADOWS,
        lighting::ENVIRONMENT,
        lighting::PROBES,
        geometry::gpu_material_maps::BINDINGS,
    ]
    .iter()
    .map(bindings::BindGroupSpec::textures_and_samplers)
    .fold((0, 0), |(t, s), (dt, ds)| (t + dt, s + ds));
    textures <= limits.max_sampled_textures_per_shader_stage
        && samplers <= limits.max_samplers_per_shader_stage
}

/// The systems every pass's preparation needs, after `plan`.
fn shared_preparation(
    plan: ScheduleConfigs<ScheduleSystem>,
) -> Vec<ScheduleConfigs<ScheduleSystem>> {
    vec![
        plan,
        prepare_targets.into_configs(),
        scene_buffers::prepare_scene_buffers.into_configs(),
        geometry::gpu_material_maps::prepare_material_maps.into_configs(),
        indirect::environment_maps::prepare_ibl.into_configs(),
    ]
}

/// (Re)builds the [`RenderSchedule`] and the [`CaptureSchedule`] from the world's
/// [`Registry`].
pub fn build_render_schedule(world: &mut World) {
    let registry = world.resource::<Registry>().clone();
    let mut render = Schedule::new(RenderSchedule);
    registry.add_systems(
        &mut render,
        shared_preparation(plan_frame.into_configs()),
        begin_frame.into_configs(),
        Vec::new(),
    );
    world.add_schedule(render);
    let mut capture = Schedule::new(CaptureSchedule);
    registry.capture_subset().add_systems(
        &mut capture,
        shared_preparation(plan_capture.into_configs()),
        begin_frame.into_configs(),
        vec![
            indirect::probe_volume::record_capture_reduce.into_configs(),
            indirect::reflection_probes::record_face_copy.into_configs(),
        ],
    );
    world.add_schedule(capture);
}

/// (Re)creates every pass from the current sources of `gpu.shaders`, compiling the
/// pipelines that do not depend on the scene; the others compile on the next frame.
/// Uploaded meshes, textures and targets are kept; the environment is prefiltered again.
pub fn insert_passes(world: &mut World, gpu: &Gpu) -> Result<()> {
    let mut ibl = indirect::environment_maps::Ibl::new(gpu)?;
    if let Some(progress) = world
        .get_resource_mut::<indirect::environment_maps::Ibl>()
        .and_then(|mut old| old.take_progress())
    {
        ibl.set_progress(progress);
    }
    let registry = world.resource::<Registry>().clone();
    registry.create_passes(world, gpu)?;
    world.insert_resource(ibl);
    world.insert_resource(indirect::probe_volume::IrradianceVolumeGpu::new(gpu)?);
    world.insert_resource(indirect::reflection_probes::ReflectionProbesGpu::new(gpu)?);
    Ok(())
}

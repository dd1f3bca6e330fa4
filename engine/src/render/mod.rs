//! The renderer: device choice, the frame's schedule of ECS systems, and one module per
//! pass.
//!
//! A frame runs the [`ExtractSchedule`] (components → [`extract::ExtractedFrame`]) and
//! then the [`RenderSchedule`]: plan (which passes run), prepare (targets, buffers,
//! pipelines), then the passes in order — shadow, G-buffer, lighting, sky, exposure,
//! depth of field, tone mapping (or a debug view) — each
//! recording into the frame's command encoder with its own timing.

pub mod debug_view;
pub mod device;
pub mod dof;
pub mod exposure;
pub mod extract;
pub mod frame;
pub mod gbuffer;
pub mod gpu_types;
pub mod ibl;
pub mod light_culling;
pub mod lighting;
pub mod material_maps;
pub mod pipelines;
pub mod plan;
pub mod readback;
pub mod scene_buffers;
pub mod shaders;
pub mod shadow;
pub mod sky;
pub mod targets;
pub mod timing;
pub mod tonemap;

use crate::error::Result;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleLabel;
use device::Gpu;
use frame::{FrameEncoder, FrameErrors, FrameOutput};
use plan::{FramePlan, PassId, pass_runs};

/// Reads the scene's components into [`extract::ExtractedFrame`].
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExtractSchedule;

/// Plans, prepares and records the frame's passes.
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct RenderSchedule;

/// Makes the targets match the output size.
fn prepare_targets(
    gpu: Res<Gpu>,
    output: Res<FrameOutput>,
    quality: Res<crate::quality::Quality>,
    mut targets: ResMut<targets::RenderTargets>,
) {
    targets.ensure(&gpu, output.size, quality.hdr_precision.format());
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
/// textures upload again from the CPU copies the World keeps.
pub fn install(world: &mut World, gpu: Gpu) -> Result<()> {
    world.insert_resource(material_maps::GpuMaterialMaps::new(&gpu));
    insert_passes(world, &gpu)?;
    world.init_resource::<crate::scene::Textures>();
    world.init_resource::<exposure::MeteredExposure>();
    world.init_resource::<exposure::FrameDelta>();
    world.insert_resource(scene_buffers::SceneBuffers::new(&gpu));
    world.insert_resource(FrameEncoder {
        encoder: None,
        timer: timing::GpuTimer::new(&gpu),
    });
    world.insert_resource(gpu);
    world.insert_resource(targets::RenderTargets::default());
    world.insert_resource(extract::ExtractedFrame::default());
    world.init_resource::<FramePlan>();
    world.init_resource::<FrameErrors>();
    world.init_resource::<debug_view::DebugView>();

    let mut extract = Schedule::new(ExtractSchedule);
    extract.add_systems(extract::extract_frame);
    world.add_schedule(extract);

    let mut render = Schedule::new(RenderSchedule);
    render.add_systems(
        (
            (
                plan::plan_frame,
                prepare_targets,
                scene_buffers::prepare_scene_buffers,
                material_maps::prepare_material_maps,
                shadow::pass::prepare_shadows,
                ibl::prepare_ibl,
                gbuffer::prepare_gbuffer,
                light_culling::prepare_light_culling,
                lighting::prepare_lighting,
                sky::prepare_sky,
                exposure::prepare_exposure,
                dof::prepare_dof,
                tonemap::prepare_tonemap.run_if(pass_runs(PassId::Tonemap)),
                debug_view::prepare_debug_view.run_if(pass_runs(PassId::DebugView)),
            )
                .chain(),
            (
                begin_frame,
                shadow::pass::shadow_pass.run_if(pass_runs(PassId::Shadow)),
                gbuffer::gbuffer_pass.run_if(pass_runs(PassId::GBuffer)),
                gbuffer::clear_gbuffer.run_if(not(pass_runs(PassId::GBuffer))),
                light_culling::light_culling_pass.run_if(pass_runs(PassId::LightCulling)),
                lighting::lighting_pass.run_if(pass_runs(PassId::Lighting)),
                sky::sky_pass.run_if(pass_runs(PassId::Sky)),
                exposure::exposure_pass.run_if(pass_runs(PassId::Exposure)),
                dof::dof_pass.run_if(pass_runs(PassId::Dof)),
                tonemap::tonemap_pass.run_if(pass_runs(PassId::Tonemap)),
                debug_view::debug_view_pass.run_if(pass_runs(PassId::DebugView)),
            )
                .chain(),
        )
            .chain(),
    );
    world.add_schedule(render);
    Ok(())
}

/// (Re)creates every pass from the current sources of `gpu.shaders`, compiling the
/// pipelines that do not depend on the scene; the others compile on the next frame.
/// Uploaded meshes, textures and targets are kept; the environment is prefiltered again.
pub fn insert_passes(world: &mut World, gpu: &Gpu) -> Result<()> {
    let gbuffer =
        gbuffer::GBufferPass::new(gpu, world.resource::<material_maps::GpuMaterialMaps>())?;
    let shadow = shadow::pass::ShadowPass::new(gpu)?;
    let mut ibl = ibl::Ibl::new(gpu)?;
    if let Some(progress) = world
        .get_resource_mut::<ibl::Ibl>()
        .and_then(|mut old| old.take_progress())
    {
        ibl.set_progress(progress);
    }
    let exposure = exposure::ExposurePass::new(gpu)?;
    let dof = dof::DofPass::new(gpu)?;
    world.insert_resource(gbuffer);
    world.insert_resource(shadow);
    world.insert_resource(ibl);
    world.insert_resource(exposure);
    world.insert_resource(dof);
    world.insert_resource(lighting::LightingPass::new(gpu));
    world.insert_resource(light_culling::LightCullingPass::new(gpu));
    world.insert_resource(sky::SkyPass::new(gpu));
    world.insert_resource(tonemap::TonemapPass::new(gpu));
    world.insert_resource(debug_view::DebugViewPass::new(gpu));
    Ok(())
}

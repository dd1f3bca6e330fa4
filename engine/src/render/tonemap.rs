//! Tone mapping pass: HDR luminance → display image, with the exact sRGB curve
//! (`shaders/tonemap.wgsl`). Compiled per (output format, tone mapper).

use crate::choice::Choice;
use crate::color::Tonemapper;
use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::debug_view::DebugView;
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors, FrameOutput};
use crate::render::graph::slots::{DISPLAY, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::{draw_fullscreen, fullscreen_variant};
use crate::render::shaders::ShaderDef;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use std::collections::HashMap;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Tone mapping and output encoding.
    pub const Tonemap: PassId = PassId::new("tonemap");
}

/// The tone mapping shader variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TonemapVariant {
    /// The display image's format (sRGB-encoded by the shader unless it is an sRGB format).
    pub format: wgpu::TextureFormat,
    /// The tone mapper.
    pub tonemapper: Tonemapper,
}

impl FramePass for TonemapPass {
    const ID: PassId = PassId::Tonemap;
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[DISPLAY];
    type Variant = TonemapVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(TonemapPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<TonemapVariant> {
        let debug = *world.resource::<DebugView>();
        let debug_view = debug != DebugView::Off;
        PassDecision::new(
            !debug_view,
            if debug_view {
                format!("the {} debug view replaces it", debug.name())
            } else {
                "turns exposed HDR luminance into the display image".into()
            },
            TonemapVariant {
                format: world.resource::<FrameOutput>().format,
                tonemapper: world
                    .resource::<ExtractedFrame>()
                    .camera
                    .as_ref()
                    .map(|c| c.tonemapper)
                    .unwrap_or_default(),
            },
        )
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_tonemap.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        tonemap_pass.into_configs()
    }
}

/// The tone mapping pass's bind group.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "tonemap",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("hdr", Binding::TextureLoad), ("post", Binding::Uniform)],
};

/// The tone mapping pass's pipelines and bindings.
#[derive(Resource)]
pub struct TonemapPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<TonemapVariant, wgpu::RenderPipeline>,
    bind_group: CachedGroup,
    params: wgpu::Buffer,
}

impl TonemapPass {
    /// Creates the bind group layout; pipelines are compiled per variant on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("tonemap"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        TonemapPass {
            layout,
            pipeline_layout,
            pipelines: HashMap::new(),
            bind_group: CachedGroup::default(),
            params: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("post params"),
                size: 16,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    fn pipeline(&mut self, gpu: &Gpu, variant: TonemapVariant) -> Result<()> {
        if self.pipelines.contains_key(&variant) {
            return Ok(());
        }
        let TonemapVariant { format, tonemapper } = variant;
        let pipeline = fullscreen_variant(
            gpu,
            "tonemap",
            &self.pipeline_layout,
            "tonemap.wgsl",
            &[
                ShaderDef::U32("TONEMAPPER", tonemapper as u32),
                ShaderDef::Bool("ENCODE_SRGB", !format.is_srgb()),
            ],
            format,
        )?;
        self.pipelines.insert(variant, pipeline);
        Ok(())
    }
}

/// Compiles this frame's variant if needed and rebuilds the bind group on new targets.
pub fn prepare_tonemap(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    frame: Res<ExtractedFrame>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<TonemapPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(&variant) = plan.variant::<TonemapPass>() else {
        return;
    };
    if let Err(e) = pass.pipeline(&gpu, variant) {
        errors.0.push(e);
        return;
    }
    let Some(hdr) = targets.current.as_ref().and_then(|t| t.view(HDR)) else {
        return;
    };
    let params = frame.camera.as_ref().map_or([0.0; 4], |c| {
        let tan_y = (c.fov_y * 0.5).tan();
        [c.vignette, tan_y * c.aspect, tan_y, 0.0]
    });
    gpu.queue
        .write_buffer(&pass.params, 0, bytemuck::cast_slice(&params));
    let TonemapPass {
        layout,
        bind_group,
        params,
        ..
    } = &mut *pass;
    let resources = vec![
        wgpu::BindingResource::TextureView(hdr),
        params.as_entire_binding(),
    ];
    if let Err(e) = bind_group.get(&gpu, &BINDINGS, layout, resources) {
        errors.0.push(e);
    }
}

/// Records the tone mapping pass into the frame's output view.
pub fn tonemap_pass(
    pass: Res<TonemapPass>,
    plan: Res<FramePlan>,
    output: Res<FrameOutput>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(view), Some(bind_group), Some(pipeline)) = (
        encoder.as_mut(),
        output.view.as_ref(),
        pass.bind_group.group(),
        plan.variant::<TonemapPass>()
            .and_then(|v| pass.pipelines.get(v)),
    ) else {
        return;
    };
    draw_fullscreen(
        encoder,
        timer,
        PassId::Tonemap.name(),
        &[view],
        pipeline,
        bind_group,
    );
}

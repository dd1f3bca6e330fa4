//! Tone mapping pass: HDR luminance → display image, with the exact sRGB curve
//! (`shaders/tonemap.wgsl`). Compiled per (output format, tone mapper).

use crate::choice::Choice;
use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameOutput;
use crate::render::graph::slots::{DISPLAY, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, FullscreenPipelines, ShaderVariant};
use crate::render::post::debug_view::DebugView;
use crate::render::shaders::ShaderDef;
use crate::shading::color::Tonemapper;
use bevy_ecs::prelude::*;

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

    crate::pass_systems!(prepare_tonemap, tonemap_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        let formats = [
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureFormat::Rgba8UnormSrgb,
        ];
        Tonemapper::ALL
            .iter()
            .flat_map(|&tonemapper| formats.map(|format| TonemapVariant { format, tonemapper }))
            .map(|v| ShaderBuild::new("tonemap.wgsl", v.shader_defs(), &[(0, BINDINGS)]))
            .collect()
    }
}

/// The tone mapping pass's bind group.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("tonemap", declared::TONEMAP_0);

impl ShaderVariant for TonemapVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![
            ShaderDef::U32("TONEMAPPER", self.tonemapper as u32),
            ShaderDef::Bool("ENCODE_SRGB", !self.format.is_srgb()),
        ]
    }
}

/// The tone mapping pass's pipelines and bindings.
#[derive(Resource)]
pub struct TonemapPass {
    layout: wgpu::BindGroupLayout,
    pipelines: FullscreenPipelines<TonemapVariant>,
    bind_group: CachedGroup,
    params: wgpu::Buffer,
}

impl TonemapPass {
    /// Creates the bind group layout; pipelines are compiled per variant on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        TonemapPass {
            pipelines: FullscreenPipelines::new(
                gpu,
                Fullscreen::new("tonemap", "tonemap.wgsl"),
                &[&layout],
            ),
            layout,
            bind_group: CachedGroup::default(),
            params: gpu.uniform_buffer("post params", 16),
        }
    }
}

/// Compiles this frame's variant if needed and rebuilds the bind group on new targets.
pub fn prepare_tonemap(mut p: Prepare<TonemapPass>, frame: Res<ExtractedFrame>) -> Result<()> {
    let Some(&variant) = p.plan.variant::<TonemapPass>() else {
        return Ok(());
    };
    p.pass
        .pipelines
        .ensure(&p.gpu, variant, &[variant.format])?;
    let Some(hdr) = p.targets.current.as_ref().and_then(|t| t.view(HDR)) else {
        return Ok(());
    };
    let params = frame.camera.as_ref().map_or([0.0; 4], |c| {
        let tan_y = (c.fov_y * 0.5).tan();
        [c.vignette, tan_y * c.aspect, tan_y, 0.0]
    });
    p.gpu
        .queue
        .write_buffer(&p.pass.params, 0, bytemuck::cast_slice(&params));
    let TonemapPass {
        layout,
        bind_group,
        params,
        ..
    } = &mut *p.pass;
    let resources = vec![
        wgpu::BindingResource::TextureView(hdr),
        params.as_entire_binding(),
    ];
    bind_group
        .get(&p.gpu, &BINDINGS, layout, resources)
        .map(|_| ())
}

/// Records the tone mapping pass into the frame's output view.
pub fn tonemap_pass(mut r: Record<TonemapPass>, output: Res<FrameOutput>) {
    let pipeline = r
        .plan
        .variant::<TonemapPass>()
        .and_then(|v| r.pass.pipelines.get(*v, &[v.format]));
    if let Some(view) = output.view.as_ref() {
        let name = PassId::Tonemap.name();
        r.encoder
            .fullscreen(name, &[view], pipeline, r.pass.bind_group.group());
    }
}

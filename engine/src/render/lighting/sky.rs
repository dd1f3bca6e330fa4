//! Sky pass: draws the environment as the background, only where the G-buffer holds no
//! geometry (a depth test against the cleared depth, so no fragment runs elsewhere).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::indirect::environment_maps::Ibl;
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, FullscreenPipelines, ShaderVariant};
use crate::render::pipelines::{FullscreenDraw, draw_fullscreen_pass};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::targets::{self};
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The environment as the background.
    pub const Sky: PassId = PassId::new("sky");
}

/// The sky shader variant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SkyVariant {
    /// The environment is an image (else a uniform colour).
    pub env_map: bool,
}

impl FramePass for SkyPass {
    const ID: PassId = PassId::Sky;
    const CAPTURE: bool = true;
    const READS: &'static [Slot] = &[DEPTH];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = SkyVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(SkyPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<SkyVariant> {
        let env = world.resource::<ExtractedFrame>().environment.as_ref();
        let reason = match env {
            None => "no environment: the camera's background colour".into(),
            Some(e) if !e.show_background => {
                "the environment is hidden: the camera's background colour".into()
            }
            Some(e) if e.image.is_some() => format!(
                "the environment image, blurred to roughness {:.2}",
                e.background_blur
            ),
            Some(_) => "the uniform environment colour".into(),
        };
        PassDecision::new(
            env.is_some_and(|e| e.show_background),
            reason,
            SkyVariant {
                env_map: env.is_some_and(|e| e.image.is_some()),
            },
        )
    }

    crate::pass_systems!(prepare_sky, sky_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        [false, true]
            .map(|env_map| {
                let defs = SkyVariant { env_map }.shader_defs();
                ShaderBuild::new("sky.wgsl", defs, &[(0, BINDINGS)])
            })
            .to_vec()
    }
}

/// The sky pass's bind group.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("sky", declared::SKY_0);

impl ShaderVariant for SkyVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![ShaderDef::Bool("ENV_MAP", self.env_map)]
    }
}

/// The sky pass's pipelines (image or uniform environment) and bindings.
#[derive(Resource)]
pub struct SkyPass {
    layout: wgpu::BindGroupLayout,
    pipelines: FullscreenPipelines<SkyVariant>,
    bind_group: CachedGroup,
}

impl SkyPass {
    /// Creates the bind group layout; pipelines compile on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        // The full-screen triangle lies at depth 0: it passes only where the G-buffer
        // depth is still the cleared 0 (reversed Z: nothing drawn).
        let depth = wgpu::DepthStencilState {
            format: targets::DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Equal),
            stencil: Default::default(),
            bias: Default::default(),
        };
        SkyPass {
            pipelines: FullscreenPipelines::new(
                gpu,
                Fullscreen::new("sky", "sky.wgsl")
                    .entry("fs_sky")
                    .depth(depth),
                &[&layout],
            ),
            layout,
            bind_group: CachedGroup::default(),
        }
    }
}

/// Compiles the sky pipeline this frame needs and rebuilds its bind group on changes.
pub fn prepare_sky(
    mut p: Prepare<SkyPass>,
    buffers: Res<SceneBuffers>,
    ibl: Res<Ibl>,
) -> Result<()> {
    let (Some(variant), Some(t)) = (p.plan.variant::<SkyPass>(), p.targets.current.as_ref()) else {
        return Ok(());
    };
    p.pass.pipelines.ensure(&p.gpu, *variant, &[t.hdr_format])?;
    let SkyPass {
        layout, bind_group, ..
    } = &mut *p.pass;
    let resources = vec![
        buffers.view.as_entire_binding(),
        ibl.uniform.as_entire_binding(),
        wgpu::BindingResource::TextureView(ibl.cube_view()),
        wgpu::BindingResource::Sampler(&ibl.sampler),
    ];
    bind_group
        .get(&p.gpu, &BINDINGS, layout, resources)
        .map(|_| ())
}

/// Records the sky pass into the HDR target.
pub fn sky_pass(mut r: Record<SkyPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(t), Some(variant)) = (r.targets.current.as_ref(), r.plan.variant::<SkyPass>()) else {
        return;
    };
    let (Some(encoder), Some([hdr, depth]), Some(bind_group), Some(pipeline)) = (
        encoder.as_mut(),
        t.views([HDR, DEPTH]),
        r.pass.bind_group.group(),
        r.pass.pipelines.get(*variant, &[t.hdr_format]),
    ) else {
        return;
    };
    draw_fullscreen_pass(
        encoder,
        timer,
        &FullscreenDraw {
            name: PassId::Sky.name(),
            targets: &[hdr],
            load: wgpu::LoadOp::Load,
            depth: Some((depth, wgpu::LoadOp::Load)),
            pipeline,
            groups: &[bind_group],
        },
    );
}

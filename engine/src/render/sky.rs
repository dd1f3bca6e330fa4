//! Sky pass: draws the environment as the background, only where the G-buffer holds no
//! geometry (a depth test against the cleared depth, so no fragment runs elsewhere).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::ibl::Ibl;
use crate::render::pipelines::{create_module, fullscreen_pipeline};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::targets::{self, RenderTargets};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use std::collections::HashMap;

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

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_sky.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        sky_pass.into_configs()
    }
}

/// The sky pass's bind group.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "sky",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("view", Binding::Uniform),
        ("environment", Binding::Uniform),
        (
            "env_cube",
            Binding::Sampled(wgpu::TextureViewDimension::Cube),
        ),
        ("env_sampler", Binding::Sampler),
    ],
};

/// The sky pass's pipelines (image or uniform environment) and bindings.
#[derive(Resource)]
pub struct SkyPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<(bool, wgpu::TextureFormat), wgpu::RenderPipeline>,
    bind_group: CachedGroup,
}

impl SkyPass {
    /// Creates the bind group layout; pipelines compile on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("sky"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        SkyPass {
            layout,
            pipeline_layout,
            pipelines: HashMap::new(),
            bind_group: CachedGroup::default(),
        }
    }

    fn pipeline(&mut self, gpu: &Gpu, env_map: bool, format: wgpu::TextureFormat) -> Result<()> {
        if self.pipelines.contains_key(&(env_map, format)) {
            return Ok(());
        }
        let source = gpu
            .shaders
            .compose("sky.wgsl", &[ShaderDef::Bool("ENV_MAP", env_map)])?;
        let module = create_module(gpu, "sky", &source)?;
        // The full-screen triangle lies at depth 0: it passes only where the G-buffer
        // depth is still the cleared 0 (reversed Z: nothing drawn).
        let depth = wgpu::DepthStencilState {
            format: targets::DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Equal),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let pipeline = fullscreen_pipeline(
            gpu,
            "sky",
            Some(&self.pipeline_layout),
            &module,
            ("vs_fullscreen", "fs_sky"),
            &[format],
            Some(depth),
        )?;
        self.pipelines.insert((env_map, format), pipeline);
        Ok(())
    }
}

/// Compiles the sky pipeline this frame needs and rebuilds its bind group on changes.
pub fn prepare_sky(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    buffers: Res<SceneBuffers>,
    ibl: Res<Ibl>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<SkyPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let (Some(variant), Some(t)) = (plan.variant::<SkyPass>(), targets.current.as_ref()) else {
        return;
    };
    if let Err(e) = pass.pipeline(&gpu, variant.env_map, t.hdr_format) {
        errors.0.push(e);
        return;
    }
    let SkyPass {
        layout, bind_group, ..
    } = &mut *pass;
    let resources = vec![
        buffers.view.as_entire_binding(),
        ibl.uniform.as_entire_binding(),
        wgpu::BindingResource::TextureView(ibl.cube_view()),
        wgpu::BindingResource::Sampler(&ibl.sampler),
    ];
    if let Err(e) = bind_group.get(&gpu, &BINDINGS, layout, resources) {
        errors.0.push(e);
    }
}

/// Records the sky pass into the HDR target.
pub fn sky_pass(
    pass: Res<SkyPass>,
    plan: Res<FramePlan>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(t), Some(variant)) = (targets.current.as_ref(), plan.variant::<SkyPass>()) else {
        return;
    };
    let (Some(encoder), Some([hdr, depth]), Some(bind_group), Some(pipeline)) = (
        encoder.as_mut(),
        t.views([HDR, DEPTH]),
        pass.bind_group.group(),
        pass.pipelines.get(&(variant.env_map, t.hdr_format)),
    ) else {
        return;
    };
    let scope = timer.begin_pass(PassId::Sky);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sky"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: None,
                stencil_ops: None,
            }),
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(pipeline);
        rp.set_bind_group(0, bind_group, &[]);
        rp.draw(0..3, 0..1);
    }
    timer.end_pass(scope);
}

//! The depth pyramid (`shaders/depth_pyramid.wgsl`): the depth buffer and, above it, mip
//! levels that each hold the nearest depth of the texels they cover (reversed Z: the
//! largest value). Screen-space reflections trace over it hierarchically (Uludag 2014,
//! "Hi-Z Screen-Space Cone-Traced Reflections", GPU Pro 5): a ray skips a whole texel of a
//! high level when it stays in front of that texel's nearest surface.
//!
//! It runs only when screen-space reflections do (the same conditions,
//! [`crate::render::indirect::reflections::skip_reason`]).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::DEPTH;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::indirect::reflections;
use crate::render::pipelines::{create_module, fullscreen_pipeline};
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The hierarchical depth pyramid.
    pub const DepthPyramid: PassId = PassId::new("depth pyramid");
}

/// Format of the pyramid: the depth buffer's 32-bit float.
pub const PYRAMID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The pyramid, which the pass owns and keeps between frames.
pub const DEPTH_PYRAMID: Slot = Slot::owned("depth pyramid");

/// The bindings of both steps: the level they read.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "depth pyramid",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("source", Binding::TextureLoad)],
};

/// The pyramid's texture, its per-level views and the groups that read each level.
pub struct Pyramid {
    /// Size of level 0 (the frame's).
    pub size: (u32, u32),
    /// The texture, every level.
    pub texture: wgpu::Texture,
    /// A view of every level (what the tracer binds).
    pub view: wgpu::TextureView,
    levels: Vec<wgpu::TextureView>,
    groups: Vec<wgpu::BindGroup>,
}

/// The depth pyramid pass.
#[derive(Resource)]
pub struct DepthPyramidPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// The copy and reduce pipelines, compiled on first use: an adapter that cannot
    /// render R32Float (GL) never runs the pass and never compiles them.
    pipelines: Option<[wgpu::RenderPipeline; 2]>,
    /// The pyramid, once a frame has needed it; bumped `generation` when it is remade.
    pub pyramid: Option<Pyramid>,
    /// Bumped when the pyramid or the depth it copies is recreated.
    pub generation: u64,
    depth_generation: u64,
}

impl FramePass for DepthPyramidPass {
    const ID: PassId = PassId::DepthPyramid;
    const READS: &'static [Slot] = &[DEPTH];
    const WRITES: &'static [Slot] = &[DEPTH_PYRAMID];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(DepthPyramidPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        match reflections::skip_reason(world) {
            Some(reason) => {
                PassDecision::new(false, format!("no reflections to trace: {reason}"), ())
            }
            None => PassDecision::new(
                true,
                "nearest depth per level, for the reflection tracer",
                (),
            ),
        }
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_pyramid.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        pyramid_pass.into_configs()
    }
}

impl DepthPyramidPass {
    /// Creates the layouts; the pipelines compile when the pass first runs.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("depth pyramid"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        DepthPyramidPass {
            layout,
            pipeline_layout,
            pipelines: None,
            pyramid: None,
            generation: 0,
            depth_generation: 0,
        }
    }

    fn pipelines(&mut self, gpu: &Gpu) -> Result<()> {
        if self.pipelines.is_some() {
            return Ok(());
        }
        let module = create_module(
            gpu,
            "depth pyramid",
            &gpu.shaders.compose("depth_pyramid.wgsl", &[])?,
        )?;
        let pipeline = |entry: &str| {
            fullscreen_pipeline(
                gpu,
                entry,
                Some(&self.pipeline_layout),
                &module,
                ("vs_fullscreen", entry),
                &[PYRAMID_FORMAT],
                None,
            )
        };
        self.pipelines = Some([pipeline("fs_copy")?, pipeline("fs_reduce")?]);
        Ok(())
    }
}

/// The number of levels of a pyramid over `size`: down to 1×1.
pub fn level_count(size: (u32, u32)) -> u32 {
    32 - size.0.max(size.1).max(1).leading_zeros()
}

/// (Re)creates the pyramid at the frame's size and the groups that read each level.
pub fn prepare_pyramid(
    gpu: Res<Gpu>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<DepthPyramidPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(t) = targets.current.as_ref() else {
        return;
    };
    let Some(depth) = t.view(DEPTH) else {
        return;
    };
    if let Err(e) = pass.pipelines(&gpu) {
        errors.0.push(e);
        return;
    }
    if pass.pyramid.as_ref().is_some_and(|p| p.size == t.size)
        && pass.depth_generation == t.generation
    {
        return;
    }
    let levels = level_count(t.size);
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth pyramid"),
        size: wgpu::Extent3d {
            width: t.size.0,
            height: t.size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: PYRAMID_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let level_views: Vec<wgpu::TextureView> = (0..levels)
        .map(|level| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("depth pyramid level"),
                base_mip_level: level,
                mip_level_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    let mut groups = Vec::with_capacity(levels as usize);
    // Level 0 reads the depth buffer; level k the level below.
    for level in 0..levels as usize {
        let source = if level == 0 {
            depth
        } else {
            &level_views[level - 1]
        };
        match BINDINGS.group(
            &gpu,
            &pass.layout,
            vec![wgpu::BindingResource::TextureView(source)],
        ) {
            Ok(g) => groups.push(g),
            Err(e) => {
                errors.0.push(e);
                return;
            }
        }
    }
    pass.pyramid = Some(Pyramid {
        size: t.size,
        view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
        texture,
        levels: level_views,
        groups,
    });
    pass.depth_generation = t.generation;
    pass.generation += 1;
}

/// Records the copy of the depth buffer into level 0 and one reduction per level above.
pub fn pyramid_pass(pass: Res<DepthPyramidPass>, mut encoder: ResMut<FrameEncoder>) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(p), Some([copy, reduce])) = (
        encoder.as_mut(),
        pass.pyramid.as_ref(),
        pass.pipelines.as_ref(),
    ) else {
        return;
    };
    let scope = timer.begin_pass(PassId::DepthPyramid);
    let last = p.levels.len().saturating_sub(1);
    for (level, (view, group)) in p.levels.iter().zip(&p.groups).enumerate() {
        let pipeline = if level == 0 { copy } else { reduce };
        // The pass's GPU time: from the start of the first level to the end of the last.
        let writes = timer
            .render_writes(&scope)
            .filter(|_| level == 0 || level == last)
            .map(|w| wgpu::RenderPassTimestampWrites {
                query_set: w.query_set,
                beginning_of_pass_write_index: w
                    .beginning_of_pass_write_index
                    .filter(|_| level == 0),
                end_of_pass_write_index: w.end_of_pass_write_index.filter(|_| level == last),
            });
        record_level(encoder, view, pipeline, group, writes);
    }
    timer.end_pass(scope);
}

/// One level: a full-screen triangle into `view`.
fn record_level(
    encoder: &mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("depth pyramid level"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    rp.set_pipeline(pipeline);
    rp.set_bind_group(0, group, &[]);
    rp.draw(0..3, 0..1);
}

//! G-buffer pass: every mesh instance into base colour + AO, normal + roughness +
//! metallic, emissive + specular level, and depth (layout in `shaders/gbuffer.wgsl`);
//! while temporal anti-aliasing runs, also each surface's screen motion since the previous
//! frame (the optional write [`MOTION`]), from the camera's previous unjittered matrix and
//! each instance's previous transform, which extraction keeps; while screen-space
//! reflections run, also the specular level on its own (the optional write
//! [`GBUFFER_SPECULAR_LEVEL`], after the motion vectors when both are written), which the
//! reflection pass reads instead of G-buffer 2.

use crate::choice::Choice;
use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::SPECULAR_AA;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::reflecting::reflections_skip_reason;
use crate::render::extract::{Batch, ExtractedFrame};
use crate::render::frame::FrameEncoder;
use crate::render::geometry::deform_pass::DeformedVertices;
use crate::render::geometry::gpu_material_maps::GpuMaterialMaps;
use crate::render::graph::slots::DEFORMED_VERTICES;
use crate::render::graph::slots::{
    DEPTH, GBUFFER_BASE_COLOR, GBUFFER_EMISSIVE, GBUFFER_NORMAL, GBUFFER_SPECULAR_LEVEL, MOTION,
    MOTION_FORMAT, SPECULAR_LEVEL_FORMAT,
};
use crate::render::graph::{
    Decision, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{PipelineCache, ShaderVariant};
use crate::render::pipelines::create_module;
use crate::render::scene_buffers::{GrowableBuffer, SceneBuffers};
use crate::render::shaders::ShaderDef;
use crate::render::targets::{self, RenderTargets};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use std::collections::HashMap;

/// The G-buffer pass's group 0 (group 1 is [`crate::render::geometry::gpu_material_maps::BINDINGS`]).
pub const VIEW: BindGroupSpec = BindGroupSpec::new(
    "gbuffer",
    wgpu::ShaderStages::VERTEX_FRAGMENT,
    declared::GBUFFER_0,
);

/// The motion variants' group 2: the unjittered matrices of this frame and the previous
/// one, each instance's previous world-from-local transform, and, for a deformed
/// instance, its previous frame's deformed vertices (`motion_source.x` = 1; a placeholder
/// and 0 for the others).
pub const MOTION_BINDINGS: BindGroupSpec = BindGroupSpec::new(
    "gbuffer motion",
    wgpu::ShaderStages::VERTEX,
    declared::GBUFFER_2,
);

#[allow(non_upper_case_globals)]
impl PassId {
    /// Rasterises meshes into the G-buffer.
    pub const GBuffer: PassId = PassId::new("gbuffer");
}

/// The G-buffer variants this frame's batches draw with.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GBufferVariants {
    /// Each distinct variant, in the order batches first need it.
    pub variants: Vec<GBufferVariant>,
    /// Geometric specular anti-aliasing widens the stored roughness (every variant).
    pub specular_aa: bool,
    /// Motion vectors are written (every variant).
    pub motion: bool,
    /// The specular level is written to its own target for the reflection pass (every
    /// variant).
    pub specular_level: bool,
}

impl FramePass for GBufferPass {
    const ID: PassId = PassId::GBuffer;
    const CAPTURE: bool = true;
    const READS: &'static [Slot] = &[DEFORMED_VERTICES];
    const WRITES: &'static [Slot] = &[GBUFFER_BASE_COLOR, GBUFFER_NORMAL, GBUFFER_EMISSIVE, DEPTH];
    const OPTIONAL_WRITES: &'static [Slot] = &[MOTION, GBUFFER_SPECULAR_LEVEL];
    type Variant = GBufferVariants;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        GBufferPass::new(gpu, world.resource::<GpuMaterialMaps>())
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<GBufferVariants> {
        let frame = world.resource::<ExtractedFrame>();
        let instances = frame.instances.len();
        let aa = &world.resource::<crate::quality::Quality>().aa;
        let specular_aa = aa.specular.enabled;
        // Probe captures have no previous frame: only the frame itself writes motion.
        let capture = world.contains_resource::<crate::render::frame::CaptureView>();
        let motion = aa.temporal() && !capture;
        // The reflections run exactly where this writes the level (the depth pyramid and the
        // reflection pass follow this decision); captures do not reflect.
        let specular_level = !capture && reflections_skip_reason(world).is_none();
        let mut variants = GBufferVariants {
            variants: Vec::new(),
            specular_aa,
            motion,
            specular_level,
        };
        for v in frame
            .drawn_batches()
            .map(|b| variant(b, specular_aa, motion, specular_level))
        {
            if !variants.variants.contains(&v) {
                variants.variants.push(v);
            }
        }
        let visible = frame.visible_instances();
        let reason = if visible > 0 {
            format!(
                "{visible} of {instances} instance(s) in view, {} draw(s), {} triangles",
                frame.draws(),
                frame.triangles
            )
        } else if instances > 0 {
            format!("none of {instances} instance(s) in view: the G-buffer stays cleared")
        } else {
            "no mesh in view: the G-buffer stays cleared".into()
        };
        let mut decision = PassDecision::new(visible > 0, reason, variants)
            .writing(MOTION, motion)
            .writing(GBUFFER_SPECULAR_LEVEL, specular_level);
        decision.features.push(Decision::new(
            "motion vectors",
            motion,
            if motion {
                format!(
                    "temporal anti-aliasing reprojects its history; {} instance(s) moved",
                    frame.temporal.moved
                )
            } else {
                "only temporal anti-aliasing reads them".into()
            },
        ));
        decision.features.push(Decision::new(
            "specular level target",
            specular_level,
            if specular_level {
                "screen-space reflections read it (so G-buffer 2 is free after lighting)"
            } else {
                "only screen-space reflections read it"
            },
        ));
        decision.features.push(Decision::new(
            "specular anti-aliasing",
            specular_aa,
            if specular_aa {
                format!(
                    "the normal's screen-space variation widens the stored roughness \
                     ({} form, σ² {:.3}, κ {:.3})",
                    aa.specular.form.name(),
                    aa.specular.variance(),
                    aa.specular.threshold()
                )
            } else {
                format!("off ({})", SPECULAR_AA.setting(Value::Bool(false)))
            },
        ));
        decision
    }

    crate::pass_systems!(prepare_gbuffer, gbuffer_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        [false, true]
            .map(|specular_aa| {
                ShaderBuild::new(
                    "gbuffer.wgsl",
                    GBufferShader { specular_aa }.shader_defs(),
                    &[
                        (0, VIEW),
                        (1, crate::render::geometry::gpu_material_maps::CORE_BINDINGS),
                        (2, MOTION_BINDINGS),
                    ],
                )
            })
            .to_vec()
    }

    fn skipped() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(clear_gbuffer.into_configs())
    }
}

/// The depth attachment of the G-buffer pass, cleared to 0 (the far plane in reversed Z).
fn cleared_depth(view: &wgpu::TextureView) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(0.0),
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// A colour attachment of the G-buffer pass, cleared to 0.
fn cleared_color(view: &wgpu::TextureView) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// Which G-buffer pipeline draws a batch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GBufferVariant {
    /// Material maps (textures, vertex colours, alpha mask): `vs_textured`/`fs_textured`
    /// with the maps' bind group as group 1.
    pub textured: bool,
    /// Back faces drawn (no culling).
    pub double_sided: bool,
    /// Geometric specular anti-aliasing (the shader constant `SPECULAR_AA`).
    pub specular_aa: bool,
    /// Motion vectors as the fourth target (the `*_motion` entry points, with group 2).
    pub motion: bool,
    /// The specular level's target after them (without it, that output is discarded).
    pub specular_level: bool,
}

/// What the motion variants bind: the matrices, the previous transforms and their group,
/// and one group per deformed instance of the frame (its previous deformed vertices).
struct MotionBindings {
    layout: wgpu::BindGroupLayout,
    matrices: wgpu::Buffer,
    previous_world: GrowableBuffer,
    /// `motion_source` of rigid draws (0) and deformed ones (1).
    sources: [wgpu::Buffer; 2],
    /// Bound as the previous vertices of rigid draws, which do not read them.
    placeholder: wgpu::Buffer,
    group: CachedGroup,
    /// By deformed instance index (`None` where its vertices do not exist).
    deformed_groups: Vec<Option<wgpu::BindGroup>>,
}

/// The G-buffer pass's pipelines (the plain one compiled up front, the others when a
/// frame first needs them) and bindings.
#[derive(Resource)]
pub struct GBufferPass {
    /// The shader, compiled without and with `SPECULAR_AA` as variants first need it.
    modules: PipelineCache<GBufferShader, wgpu::ShaderModule>,
    layout: wgpu::BindGroupLayout,
    /// Pipeline layouts by (textured, motion).
    layouts: HashMap<(bool, bool), wgpu::PipelineLayout>,
    pipelines: PipelineCache<GBufferVariant>,
    bind_group: CachedGroup,
    motion: MotionBindings,
}

impl GBufferPass {
    /// Compiles the pass's plain variant.
    pub fn new(gpu: &Gpu, maps: &GpuMaterialMaps) -> Result<Self> {
        let layout = VIEW.layout(gpu);
        let motion_layout = MOTION_BINDINGS.layout(gpu);
        let mut layouts = HashMap::new();
        for textured in [false, true] {
            for motion in [false, true] {
                let maps = textured.then_some(&maps.layout);
                let groups: &[Option<&wgpu::BindGroupLayout>] = if motion {
                    &[Some(&layout), maps, Some(&motion_layout)]
                } else if textured {
                    &[Some(&layout), maps]
                } else {
                    &[Some(&layout)]
                };
                let descriptor = wgpu::PipelineLayoutDescriptor {
                    label: Some("gbuffer"),
                    bind_group_layouts: groups,
                    immediate_size: 0,
                };
                layouts.insert(
                    (textured, motion),
                    gpu.device.create_pipeline_layout(&descriptor),
                );
            }
        }
        let mut pass = GBufferPass {
            modules: PipelineCache::default(),
            layout,
            layouts,
            pipelines: PipelineCache::default(),
            bind_group: CachedGroup::default(),
            motion: MotionBindings {
                layout: motion_layout,
                matrices: gpu.uniform_buffer("gbuffer motion matrices", 128),
                previous_world: GrowableBuffer::new(gpu, "previous transforms", 256),
                sources: [0u32, 1].map(|source| {
                    use wgpu::util::DeviceExt;
                    gpu.device
                        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                            label: Some("gbuffer motion source"),
                            contents: bytemuck::cast_slice(&[source, 0, 0, 0]),
                            usage: wgpu::BufferUsages::UNIFORM,
                        })
                }),
                placeholder: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("no previous vertices"),
                    size: 64,
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: false,
                }),
                group: CachedGroup::default(),
                deformed_groups: Vec::new(),
            },
        };
        pass.ensure(
            gpu,
            GBufferVariant {
                textured: false,
                double_sided: false,
                specular_aa: crate::quality::SpecularAaSettings::default().enabled,
                motion: false,
                specular_level: crate::quality::SsrSettings::default().enabled,
            },
        )?;
        Ok(pass)
    }

    /// Compiles `variant` unless it exists.
    pub fn ensure(&mut self, gpu: &Gpu, variant: GBufferVariant) -> Result<()> {
        let GBufferPass {
            modules,
            layouts,
            pipelines,
            ..
        } = self;
        let Some(layout) = layouts.get(&(variant.textured, variant.motion)) else {
            return Ok(());
        };
        pipelines.ensure_with(&variant, || {
            let shader = GBufferShader {
                specular_aa: variant.specular_aa,
            };
            let module = modules.ensure(&shader, |defs| {
                create_module(gpu, "gbuffer", &gpu.shaders.compose("gbuffer.wgsl", defs)?)
            })?;
            compile(gpu, variant, layout, module)
        })?;
        Ok(())
    }
}

/// What the G-buffer shader is compiled with: a module serves every variant of the same
/// `specular_aa`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct GBufferShader {
    specular_aa: bool,
}

/// `SPECULAR_AA`, and the material maps as group 1.
impl ShaderVariant for GBufferShader {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![
            ShaderDef::Bool("SPECULAR_AA", self.specular_aa),
            crate::render::geometry::gpu_material_maps::group_def(1),
        ]
    }
}

/// The pipeline of `variant` from `module`: the entry points of its (textured, motion)
/// pair, its culling, and the motion target where it has one.
fn compile(
    gpu: &Gpu,
    variant: GBufferVariant,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
) -> Result<wgpu::RenderPipeline> {
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    let (vs, fs) = match (variant.textured, variant.motion) {
        (false, false) => ("vs_main", "fs_main"),
        (true, false) => ("vs_textured", "fs_textured"),
        (false, true) => ("vs_main_motion", "fs_main_motion"),
        (true, true) => ("vs_textured_motion", "fs_textured_motion"),
    };
    let mut color_targets = vec![
        target(targets::GBUFFER0_FORMAT),
        target(targets::GBUFFER1_FORMAT),
        target(targets::GBUFFER2_FORMAT),
    ];
    if variant.motion {
        color_targets.push(target(MOTION_FORMAT));
    }
    if variant.specular_level {
        color_targets.push(target(SPECULAR_LEVEL_FORMAT));
    }
    gpu.checked("gbuffer pipeline", |device| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("gbuffer"),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &crate::render::geometry::mesh_vertex::buffers(),
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: if variant.double_sided {
                    None
                } else {
                    Some(wgpu::Face::Back)
                },
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: targets::DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &color_targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    })
}

/// The variant that draws `batch`.
fn variant(batch: &Batch, specular_aa: bool, motion: bool, specular_level: bool) -> GBufferVariant {
    GBufferVariant {
        textured: batch.textured,
        double_sided: batch.double_sided,
        specular_aa,
        motion,
        specular_level,
    }
}

/// Compiles the variants this frame's batches need, rebuilds the pass's bind group when
/// the scene buffers were recreated, and writes what the motion variants read.
pub fn prepare_gbuffer(
    mut p: Prepare<GBufferPass>,
    buffers: Res<SceneBuffers>,
    frame: Res<ExtractedFrame>,
    deform: Res<DeformedVertices>,
) -> Result<()> {
    let decided = p.plan.variant::<GBufferPass>();
    for &v in decided.map(|v| v.variants.as_slice()).unwrap_or_default() {
        p.pass.ensure(&p.gpu, v)?;
    }
    if decided.is_some_and(|v| v.motion) {
        p.pass.motion.prepare(&p.gpu, &frame, &deform)?;
    }
    let GBufferPass {
        layout, bind_group, ..
    } = &mut *p.pass;
    bind_group
        .get(
            &p.gpu,
            &VIEW,
            layout,
            vec![buffers.view.as_entire_binding()],
        )
        .map(|_| ())
}

impl MotionBindings {
    /// Writes this frame's matrices and previous transforms, rebuilds the group when the
    /// transforms' buffer grew, and builds each deformed instance's group (its previous
    /// vertices alternate between two buffers, so these are rebuilt every frame).
    fn prepare(
        &mut self,
        gpu: &Gpu,
        frame: &ExtractedFrame,
        deform: &DeformedVertices,
    ) -> Result<()> {
        let temporal = &frame.temporal;
        let matrices = [
            temporal.clip_from_world.to_cols_array(),
            temporal.previous_clip_from_world.to_cols_array(),
        ];
        gpu.queue
            .write_buffer(&self.matrices, 0, bytemuck::cast_slice(&matrices));
        self.previous_world
            .write(gpu, bytemuck::cast_slice(&temporal.previous_world));
        self.group.get(
            gpu,
            &MOTION_BINDINGS,
            &self.layout,
            vec![
                self.matrices.as_entire_binding(),
                self.previous_world.buffer.as_entire_binding(),
                self.placeholder.as_entire_binding(),
                self.sources[0].as_entire_binding(),
            ],
        )?;
        self.deformed_groups.clear();
        for d in &frame.deformed.instances {
            let group = match deform.previous_vertices(d.entity) {
                Some(previous) => Some(MOTION_BINDINGS.group(
                    gpu,
                    &self.layout,
                    vec![
                        self.matrices.as_entire_binding(),
                        self.previous_world.buffer.as_entire_binding(),
                        previous.as_entire_binding(),
                        self.sources[1].as_entire_binding(),
                    ],
                )?),
                None => None,
            };
            self.deformed_groups.push(group);
        }
        Ok(())
    }
}

/// Records the G-buffer pass.
#[allow(clippy::too_many_arguments)]
pub fn gbuffer_pass(
    mut r: Record<GBufferPass>,
    maps: Res<GpuMaterialMaps>,
    buffers: Res<SceneBuffers>,
    frame: Res<ExtractedFrame>,
    deform: Res<DeformedVertices>,
) {
    let Some(&GBufferVariants {
        specular_aa,
        motion,
        specular_level,
        ..
    }) = r.plan.variant::<GBufferPass>()
    else {
        return;
    };
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(t), Some(bind_group)) = (
        encoder.as_mut(),
        r.targets.current.as_ref(),
        r.pass.bind_group.group(),
    ) else {
        return;
    };
    let Some([base_color, normal, emissive, depth]) =
        t.views([GBUFFER_BASE_COLOR, GBUFFER_NORMAL, GBUFFER_EMISSIVE, DEPTH])
    else {
        return;
    };
    // With motion vectors: their target and the group that holds the previous transforms.
    let motion = match (motion, t.view(MOTION), r.pass.motion.group.group()) {
        (false, _, _) => None,
        (true, Some(view), Some(group)) => Some((view, group)),
        (true, _, _) => return,
    };
    // The specular level's target, where the reflection pass reads it.
    let level = match (specular_level, t.view(GBUFFER_SPECULAR_LEVEL)) {
        (false, _) => None,
        (true, Some(view)) => Some(view),
        (true, None) => return,
    };
    let scope = timer.begin_pass(PassId::GBuffer);
    {
        let mut attachments = vec![
            cleared_color(base_color),
            cleared_color(normal),
            cleared_color(emissive),
        ];
        attachments.extend(motion.map(|(view, _)| cleared_color(view)));
        attachments.extend(level.map(cleared_color));
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(cleared_depth(depth)),
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_bind_group(0, bind_group, &[]);
        // Group 2 of the motion variants: the shared one, or a deformed instance's.
        let mut motion_group: Option<Option<u32>> = None;
        rp.set_vertex_buffer(1, buffers.instances.buffer.slice(..));
        let mut current = None;
        for batch in frame.drawn_batches() {
            let Some(mesh) = buffers.meshes.get(&batch.mesh) else {
                continue;
            };
            let Some(vertices) = deform.draw_vertices(&frame, mesh, batch.deformed) else {
                continue;
            };
            if let Some((_, shared)) = motion
                && motion_group != Some(batch.deformed)
            {
                let group = match batch.deformed {
                    None => Some(shared),
                    Some(d) => r
                        .pass
                        .motion
                        .deformed_groups
                        .get(d as usize)
                        .and_then(Option::as_ref),
                };
                let Some(group) = group else {
                    continue;
                };
                rp.set_bind_group(2, group, &[]);
                motion_group = Some(batch.deformed);
            }
            let v = variant(batch, specular_aa, motion.is_some(), specular_level);
            let Some(pipeline) = r.pass.pipelines.get(&v) else {
                continue;
            };
            if let Some(m) = batch.maps.filter(|_| batch.textured) {
                let Some(group) = maps.group(m) else {
                    continue;
                };
                rp.set_bind_group(1, group, &[]);
            }
            if current != Some(v) {
                rp.set_pipeline(pipeline);
                current = Some(v);
            }
            rp.set_vertex_buffer(0, vertices.slice(..));
            rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            rp.draw_indexed(
                0..mesh.index_count,
                0,
                batch.first_instance..batch.first_instance + batch.visible,
            );
        }
    }
    timer.end_pass(scope);
}

/// When the G-buffer pass is skipped (no mesh in view), clears depth so lighting sees background,
/// and the motion vectors where TAA reads them.
pub fn clear_gbuffer(targets: Res<RenderTargets>, mut encoder: ResMut<FrameEncoder>) {
    let (Some(encoder), Some(t)) = (encoder.encoder.as_mut(), targets.current.as_ref()) else {
        return;
    };
    let Some(depth) = t.view(DEPTH) else {
        return;
    };
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear depth"),
        color_attachments: &[t.view(MOTION).and_then(cleared_color)],
        depth_stencil_attachment: Some(cleared_depth(depth)),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
}

//! Motion vectors for temporal anti-aliasing: each pixel's screen motion, in pixels, from
//! the previous frame to this one, without the camera's jitter (`motion.wgsl`).
//!
//! Two steps. A full-screen step gives every pixel the motion of the surface its depth
//! shows as if only the camera moved. Then the instances whose transform changed since
//! the previous frame (extraction keeps every drawn entity's previous transform) are
//! drawn again over their own depth, with an equal depth test, and write the motion of
//! their previous transform. A still scene costs one full-screen step.
//!
//! Why a pass of its own rather than a fourth G-buffer target: a pass's targets are
//! fixed declarations in the frame graph, so a motion target written by the G-buffer
//! would be allocated and written in every frame. As its own pass it runs only when TAA
//! does, and the G-buffer stays as it was.

use crate::error::Result;
use crate::quality::Quality;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::DEPTH;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot, TargetFormat};
use crate::render::pipelines::{create_module, fullscreen_pipeline, one_group_layout};
use crate::render::scene_buffers::{GrowableBuffer, SceneBuffers};
use crate::scene::Vertex;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Screen motion since the previous frame.
    pub const Motion: PassId = PassId::new("motion");
}

/// Format of the motion target: two f16 channels of pixels (0.03 px steps up to 64 px).
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

/// Screen motion in pixels since the previous frame (rg), without jitter.
pub const MOTION: Slot = Slot::target("motion vectors", TargetFormat::Fixed(MOTION_FORMAT));

impl FramePass for MotionPass {
    const ID: PassId = PassId::Motion;
    const READS: &'static [Slot] = &[DEPTH];
    const WRITES: &'static [Slot] = &[MOTION];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        MotionPass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        let taa = world.resource::<Quality>().aa.temporal();
        let moved = world.resource::<ExtractedFrame>().temporal.moved.len();
        PassDecision::new(
            taa,
            if taa {
                format!(
                    "camera motion for every pixel, object motion for {moved} moved instance(s)"
                )
            } else {
                "only temporal anti-aliasing reads motion vectors".into()
            },
            (),
        )
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_motion.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        motion_pass.into_configs()
    }
}

/// Both steps: the frame's view and the unjittered matrices.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "motion",
    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
    bindings: &[("view", Binding::Uniform), ("motion", Binding::Uniform)],
};

/// The camera step's depth.
pub const DEPTH_BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "motion depth",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("depth", Binding::TextureLoad)],
};

/// One moved instance: its transform now and in the previous frame (per-instance
/// attributes 4–11 of `vs_object`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct MovedInstance {
    world: [[f32; 4]; 4],
    previous: [[f32; 4]; 4],
}

/// The motion pass's pipelines, buffers and bindings.
#[derive(Resource)]
pub struct MotionPass {
    layout: wgpu::BindGroupLayout,
    depth_layout: wgpu::BindGroupLayout,
    camera: wgpu::RenderPipeline,
    object: wgpu::RenderPipeline,
    uniform: wgpu::Buffer,
    moved: GrowableBuffer,
    /// The view and matrices, built once.
    group: Option<wgpu::BindGroup>,
    /// The depth, per generation of the frame's targets.
    depth_group: Option<(u64, wgpu::BindGroup)>,
    /// Moved instances and the mesh each draws.
    draws: Vec<crate::scene::MeshHandle>,
}

impl MotionPass {
    /// Compiles both steps.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let layout = BINDINGS.layout(gpu);
        let depth_layout = DEPTH_BINDINGS.layout(gpu);
        let module = create_module(gpu, "motion", &gpu.shaders.compose("motion.wgsl", &[])?)?;
        let camera_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("motion (camera)"),
                bind_group_layouts: &[Some(&layout), Some(&depth_layout)],
                immediate_size: 0,
            });
        let camera = fullscreen_pipeline(
            gpu,
            "motion (camera)",
            Some(&camera_layout),
            &module,
            ("vs_fullscreen", "fs_camera"),
            &[MOTION_FORMAT],
            None,
        )?;
        let object_layout = one_group_layout(gpu, "motion (objects)", &layout);
        let instance_attributes = wgpu::vertex_attr_array![
            4 => Float32x4, 5 => Float32x4, 6 => Float32x4, 7 => Float32x4,
            8 => Float32x4, 9 => Float32x4, 10 => Float32x4, 11 => Float32x4
        ];
        let object = gpu.checked("motion (objects) pipeline", |device| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("motion (objects)"),
                layout: Some(&object_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_object"),
                    compilation_options: Default::default(),
                    buffers: &[
                        Some(wgpu::VertexBufferLayout {
                            array_stride: std::mem::size_of::<Vertex>() as u64,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                        }),
                        Some(wgpu::VertexBufferLayout {
                            array_stride: std::mem::size_of::<MovedInstance>() as u64,
                            step_mode: wgpu::VertexStepMode::Instance,
                            attributes: &instance_attributes,
                        }),
                    ],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: crate::render::graph::slots::DEPTH_FORMAT,
                    depth_write_enabled: Some(false),
                    depth_compare: Some(wgpu::CompareFunction::Equal),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_object"),
                    compilation_options: Default::default(),
                    targets: &[Some(MOTION_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        })?;
        Ok(MotionPass {
            layout,
            depth_layout,
            camera,
            object,
            uniform: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("motion view"),
                size: 128,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            moved: GrowableBuffer::new(gpu, "moved instances", 256),
            group: None,
            depth_group: None,
            draws: Vec::new(),
        })
    }
}

/// Writes the matrices and the moved instances, and (re)builds the bind groups.
pub fn prepare_motion(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    buffers: Res<SceneBuffers>,
    targets: Res<crate::render::targets::RenderTargets>,
    mut pass: ResMut<MotionPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let pass = &mut *pass;
    let t = &frame.temporal;
    let matrices = [
        t.clip_from_world.to_cols_array(),
        t.previous_clip_from_world.to_cols_array(),
    ];
    gpu.queue
        .write_buffer(&pass.uniform, 0, bytemuck::cast_slice(&matrices));
    let mut moved = Vec::with_capacity(t.moved.len());
    pass.draws.clear();
    for &(i, mesh) in &t.moved {
        let (Some(instance), Some(previous)) = (
            frame.instances.get(i as usize),
            t.previous_world.get(i as usize),
        ) else {
            continue;
        };
        moved.push(MovedInstance {
            world: instance.world_from_local,
            previous: *previous,
        });
        pass.draws.push(mesh);
    }
    pass.moved.write(&gpu, bytemuck::cast_slice(&moved));
    if pass.group.is_none() {
        match BINDINGS.group(
            &gpu,
            &pass.layout,
            vec![
                buffers.view.as_entire_binding(),
                pass.uniform.as_entire_binding(),
            ],
        ) {
            Ok(g) => pass.group = Some(g),
            Err(e) => {
                errors.0.push(e);
                return;
            }
        }
    }
    let Some((generation, depth)) = targets
        .current
        .as_ref()
        .and_then(|t| Some((t.generation, t.view(DEPTH)?)))
    else {
        return;
    };
    if pass
        .depth_group
        .as_ref()
        .is_none_or(|(g, _)| *g != generation)
    {
        match DEPTH_BINDINGS.group(
            &gpu,
            &pass.depth_layout,
            vec![wgpu::BindingResource::TextureView(depth)],
        ) {
            Ok(g) => pass.depth_group = Some((generation, g)),
            Err(e) => errors.0.push(e),
        }
    }
}

/// Records the camera step, then the moved instances.
pub fn motion_pass(
    pass: Res<MotionPass>,
    buffers: Res<SceneBuffers>,
    targets: Res<crate::render::targets::RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(t), Some(group), Some((_, depth_group))) = (
        encoder.as_mut(),
        targets.current.as_ref(),
        pass.group.as_ref(),
        pass.depth_group.as_ref(),
    ) else {
        return;
    };
    let (Some(motion), Some(depth)) = (t.view(MOTION), t.view(DEPTH)) else {
        return;
    };
    let scope = timer.begin_pass(PassId::Motion);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("motion (camera)"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: motion,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(&pass.camera);
        rp.set_bind_group(0, group, &[]);
        rp.set_bind_group(1, depth_group, &[]);
        rp.draw(0..3, 0..1);
    }
    if !pass.draws.is_empty() {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("motion (objects)"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: motion,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(&pass.object);
        rp.set_bind_group(0, group, &[]);
        rp.set_vertex_buffer(1, pass.moved.buffer.slice(..));
        for (i, mesh) in pass.draws.iter().enumerate() {
            let Some(mesh) = buffers.meshes.get(mesh) else {
                continue;
            };
            rp.set_vertex_buffer(0, mesh.vertices.slice(..));
            rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            rp.draw_indexed(0..mesh.index_count, 0, i as u32..i as u32 + 1);
        }
    }
    timer.end_pass(scope);
}

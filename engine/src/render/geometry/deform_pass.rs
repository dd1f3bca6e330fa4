//! The deformation pass (`shaders/deform.wgsl`): a compute pass that morphs and skins
//! the vertices of every deformed instance of the frame ([`DeformedFrame`]) into a vertex
//! buffer of the instance's own, which the shadow, G-buffer and transparent passes then
//! draw in place of the mesh's vertices (the formulas are in [`crate::scene::deform`]).
//! It runs only in frames that have a skinned or morphed instance.
//!
//! Each instance keeps two output buffers and writes them in turn, so the previous
//! frame's deformed vertices stay available to the G-buffer's motion vectors. A probe
//! capture recomputes the current buffer without turning them.

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::extract::deformed::DeformedFrame;
use crate::render::frame::{CaptureView, FrameEncoder};
use crate::render::graph::slots::DEFORMED_VERTICES;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::pass_params::Record;
use crate::render::pipeline_cache::ComputePipelines;
use crate::render::scene_buffers::{GpuMesh, GrowableBuffer, SceneBuffers};
use crate::scene::{MeshHandle, Meshes, Vertex};
use bevy_ecs::prelude::*;
use std::collections::HashMap;

/// Invocations per workgroup (`WORKGROUP_SIZE` in `deform.wgsl`).
const WORKGROUP_SIZE: u32 = 64;
/// Floats per morph target and vertex (`TARGET_FLOATS`): position, normal, tangent.
const TARGET_FLOATS: usize = 9;
/// The most workgroups along one dispatch dimension (WebGPU's guaranteed limit).
const MAX_GROUPS_X: u32 = 65_535;

/// The frame's inputs: each instance's parameters (at a dynamic offset), every joint
/// matrix and every morph weight.
pub const FRAME_BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "deform frame",
    visibility: wgpu::ShaderStages::COMPUTE,
    bindings: &[
        (
            "params",
            Binding::DynamicUniform(std::mem::size_of::<GpuDeformParams>() as u64),
        ),
        ("joint_matrices", Binding::Storage),
        ("morph_weights", Binding::Storage),
    ],
};

/// One instance's mesh data and output.
pub const INSTANCE_BINDINGS: BindGroupSpec =
    BindGroupSpec::compute("deform instance", declared::DEFORM_1);

#[allow(non_upper_case_globals)]
impl PassId {
    /// Skins and morphs the deformed instances' vertices.
    pub const Deform: PassId = PassId::new("deform");
}

/// `DeformParams` in `deform.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuDeformParams {
    /// Vertices of the mesh.
    pub vertex_count: u32,
    /// The instance's first joint matrix.
    pub joint_offset: u32,
    /// Its joint matrices.
    pub joint_count: u32,
    /// Its first morph weight.
    pub weight_offset: u32,
    /// Its mesh's morph targets.
    pub target_count: u32,
    /// 1 when skinned.
    pub skinned: u32,
    /// Padding to 32 bytes.
    pub pad: [u32; 2],
}

/// The deformation pass has one shader variant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeformVariant;

impl FramePass for DeformPass {
    const ID: PassId = PassId::Deform;
    const CAPTURE: bool = true;
    const READS: &'static [Slot] = &[];
    const WRITES: &'static [Slot] = &[DEFORMED_VERTICES];
    type Variant = DeformVariant;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        world.init_resource::<DeformedVertices>();
        Ok(DeformPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<DeformVariant> {
        let deformed = &world.resource::<ExtractedFrame>().deformed;
        let skinned = deformed.instances.iter().filter(|d| d.skinned).count();
        let morphed = deformed.instances.len() - skinned;
        let reason = if deformed.instances.is_empty() {
            "no skinned or morphed mesh".to_string()
        } else {
            format!(
                "{skinned} skinned and {morphed} morphed-only instance(s), {} joint(s)",
                deformed.joint_matrices.len()
            )
        };
        PassDecision::new(!deformed.instances.is_empty(), reason, DeformVariant)
    }

    crate::pass_systems!(prepare_deform, deform_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![ShaderBuild::new(
            "deform.wgsl",
            Vec::new(),
            &[(0, FRAME_BINDINGS), (1, INSTANCE_BINDINGS)],
        )]
    }
}

/// A mesh's joints, weights and morph offsets on the GPU.
struct MeshInputs {
    influences: wgpu::Buffer,
    targets: wgpu::Buffer,
}

/// One instance's two output buffers and the bind groups that write each.
struct Outputs {
    mesh: MeshHandle,
    buffers: [wgpu::Buffer; 2],
    groups: [wgpu::BindGroup; 2],
    /// The buffer this frame writes (and the passes draw).
    current: usize,
    /// Never written: the first write is copied into the other buffer too, so the
    /// previous frame's vertices equal this frame's.
    fresh: bool,
}

/// One dispatch of this frame.
struct Dispatch {
    entity: Entity,
    params_offset: u32,
    vertex_count: u32,
}

/// Each deformed entity's output vertex buffers: what the deform pass writes and the
/// passes that draw deformed meshes read.
#[derive(Resource, Default)]
pub struct DeformedVertices {
    outputs: HashMap<Entity, Outputs>,
}

impl DeformedVertices {
    /// The vertex buffer the passes draw for deformed `entity` this frame: its mesh's
    /// vertices morphed and skinned (in world space when skinned).
    pub fn vertices(&self, entity: Entity) -> Option<&wgpu::Buffer> {
        self.outputs.get(&entity).map(|o| &o.buffers[o.current])
    }

    /// The same, as the previous frame computed it (equal to
    /// [`DeformedVertices::vertices`] in the instance's first frame).
    pub fn previous_vertices(&self, entity: Entity) -> Option<&wgpu::Buffer> {
        self.outputs.get(&entity).map(|o| &o.buffers[1 - o.current])
    }

    /// The vertices to draw for an instance of `mesh`: those of deformed instance
    /// `deformed` (an index into the frame's [`DeformedFrame::instances`]), or the mesh's
    /// own. `None` where the deformed vertices do not exist.
    pub fn draw_vertices<'a>(
        &'a self,
        frame: &ExtractedFrame,
        mesh: &'a GpuMesh,
        deformed: Option<u32>,
    ) -> Option<&'a wgpu::Buffer> {
        match deformed {
            None => Some(&mesh.vertices),
            Some(i) => self.vertices(frame.deformed.instances.get(i as usize)?.entity),
        }
    }
}

/// The pipeline and the frame's input buffers.
#[derive(Resource)]
pub struct DeformPass {
    frame_layout: wgpu::BindGroupLayout,
    instance_layout: wgpu::BindGroupLayout,
    pipeline: ComputePipelines,
    params: GrowableBuffer,
    params_stride: u32,
    joints: GrowableBuffer,
    weights: GrowableBuffer,
    frame_group: CachedGroup,
    meshes: HashMap<MeshHandle, MeshInputs>,
    dispatches: Vec<Dispatch>,
}

impl DeformPass {
    /// Layouts and empty buffers; the pipeline compiles on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let frame_layout = FRAME_BINDINGS.layout(gpu);
        let instance_layout = INSTANCE_BINDINGS.layout(gpu);
        let pipeline = ComputePipelines::new(
            gpu,
            ("deform", "deform.wgsl", "cs_deform"),
            &[&frame_layout, &instance_layout],
        );
        let align = gpu.device.limits().min_uniform_buffer_offset_alignment;
        let size = std::mem::size_of::<GpuDeformParams>() as u32;
        DeformPass {
            frame_layout,
            instance_layout,
            pipeline,
            params: GrowableBuffer::with_usage(
                gpu,
                "deform params",
                256,
                wgpu::BufferUsages::UNIFORM,
            ),
            params_stride: size.div_ceil(align) * align,
            joints: GrowableBuffer::new(gpu, "joint matrices", 256),
            weights: GrowableBuffer::new(gpu, "morph weights", 256),
            frame_group: CachedGroup::default(),
            meshes: HashMap::new(),
            dispatches: Vec::new(),
        }
    }
}

/// A storage buffer holding `data` (at least 64 bytes, zeros past the data).
fn storage_buffer(gpu: &Gpu, label: &str, data: &[u8]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    let mut bytes = data.to_vec();
    bytes.resize(bytes.len().max(64), 0);
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &bytes,
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// The GPU form of `mesh`'s deformation: per vertex its four joints then its four weights
/// (`Influence`), and per target and vertex the nine offsets (`TARGET_FLOATS`).
fn mesh_inputs(gpu: &Gpu, meshes: &Meshes, mesh: MeshHandle) -> Option<MeshInputs> {
    let d = meshes.deformation(mesh)?;
    let vertices = meshes.get(mesh)?.vertices.len();
    let mut influences: Vec<u32> = Vec::with_capacity(d.joints().len() * 8);
    for (j, w) in d.joints().iter().zip(d.weights()) {
        influences.extend_from_slice(j);
        influences.extend(w.iter().map(|w| w.to_bits()));
    }
    let mut targets: Vec<f32> = Vec::with_capacity(d.targets().len() * vertices * TARGET_FLOATS);
    for t in d.targets() {
        for i in 0..vertices {
            for list in [&t.positions, &t.normals, &t.tangents] {
                targets.extend_from_slice(list.get(i).unwrap_or(&[0.0; 3]));
            }
        }
    }
    Some(MeshInputs {
        influences: storage_buffer(gpu, "joint influences", bytemuck::cast_slice(&influences)),
        targets: storage_buffer(gpu, "morph targets", bytemuck::cast_slice(&targets)),
    })
}

/// What deformation reads: the device, the frame's deformed instances, the meshes and their
/// vertex buffers.
#[derive(bevy_ecs::system::SystemParam)]
pub struct DeformSources<'w> {
    gpu: Res<'w, Gpu>,
    frame: Res<'w, ExtractedFrame>,
    meshes: Res<'w, Meshes>,
    buffers: Res<'w, SceneBuffers>,
}

/// Uploads the frame's parameters, joint matrices and weights; creates the inputs of
/// meshes and the outputs of instances met for the first time; turns each instance's
/// outputs (not in a probe capture); forgets instances that left the scene.
pub fn prepare_deform(
    sources: DeformSources,
    capture: Option<Res<CaptureView>>,
    mut pass: ResMut<DeformPass>,
    mut deformed_vertices: ResMut<DeformedVertices>,
) -> Result<()> {
    let DeformSources {
        gpu,
        frame,
        meshes,
        buffers,
    } = sources;
    let pass = &mut *pass;
    let outputs = &mut deformed_vertices.outputs;
    pass.pipeline.ensure(&gpu, &())?;
    let deformed: &DeformedFrame = &frame.deformed;
    let stride = pass.params_stride as usize;
    let mut params = vec![0u8; deformed.instances.len().max(1) * stride];
    pass.dispatches.clear();
    for (k, d) in deformed.instances.iter().enumerate() {
        let (Some(mesh), Some(gpu_mesh)) = (meshes.get(d.mesh), buffers.meshes.get(&d.mesh)) else {
            continue;
        };
        let inputs = match pass.meshes.entry(d.mesh) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => {
                let Some(inputs) = mesh_inputs(&gpu, &meshes, d.mesh) else {
                    continue;
                };
                e.insert(inputs)
            }
        };
        let inputs = &*inputs;
        let vertex_count = mesh.vertices.len() as u32;
        let stale = outputs.get(&d.entity).is_none_or(|o| o.mesh != d.mesh);
        if stale {
            let size = u64::from(vertex_count) * std::mem::size_of::<Vertex>() as u64;
            let buffer = |label| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: size.max(64),
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::VERTEX
                        | wgpu::BufferUsages::COPY_SRC
                        | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            let out = [buffer("deformed vertices a"), buffer("deformed vertices b")];
            let group = |target: &wgpu::Buffer| {
                INSTANCE_BINDINGS.group(
                    &gpu,
                    &pass.instance_layout,
                    vec![
                        gpu_mesh.vertices.as_entire_binding(),
                        inputs.influences.as_entire_binding(),
                        inputs.targets.as_entire_binding(),
                        target.as_entire_binding(),
                    ],
                )
            };
            let groups = match (group(&out[0]), group(&out[1])) {
                (Ok(a), Ok(b)) => [a, b],
                (Err(e), _) | (_, Err(e)) => return Err(e),
            };
            outputs.insert(
                d.entity,
                Outputs {
                    mesh: d.mesh,
                    buffers: out,
                    groups,
                    current: 0,
                    fresh: true,
                },
            );
        } else if capture.is_none()
            && let Some(o) = outputs.get_mut(&d.entity)
        {
            o.current = 1 - o.current;
        }
        let p = GpuDeformParams {
            vertex_count,
            joint_offset: d.joint_offset,
            joint_count: d.joint_count,
            weight_offset: d.weight_offset,
            target_count: d.weight_count,
            skinned: u32::from(d.skinned),
            pad: [0; 2],
        };
        params[k * stride..k * stride + std::mem::size_of::<GpuDeformParams>()]
            .copy_from_slice(bytemuck::bytes_of(&p));
        pass.dispatches.push(Dispatch {
            entity: d.entity,
            params_offset: (k * stride) as u32,
            vertex_count,
        });
    }
    if capture.is_none() {
        outputs.retain(|e, _| deformed.instances.iter().any(|d| d.entity == *e));
    }
    pass.params.write(&gpu, &params);
    let joints: &[u8] = if deformed.joint_matrices.is_empty() {
        &[0; 64]
    } else {
        bytemuck::cast_slice(&deformed.joint_matrices)
    };
    pass.joints.write(&gpu, joints);
    let weights: &[u8] = if deformed.morph_weights.is_empty() {
        &[0; 4]
    } else {
        bytemuck::cast_slice(&deformed.morph_weights)
    };
    pass.weights.write(&gpu, weights);
    let resources = vec![
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &pass.params.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(std::mem::size_of::<GpuDeformParams>() as u64),
        }),
        pass.joints.buffer.as_entire_binding(),
        pass.weights.buffer.as_entire_binding(),
    ];
    pass.frame_group
        .get(&gpu, &FRAME_BINDINGS, &pass.frame_layout, resources)
        .map(|_| ())
}

/// Records one dispatch per deformed instance (64 vertices per workgroup), then copies
/// the first output of new instances into their other buffer.
pub fn deform_pass(mut r: Record<DeformPass>, mut deformed_vertices: ResMut<DeformedVertices>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let outputs = &mut deformed_vertices.outputs;
    let (Some(encoder), Some(frame_group), Some(pipeline)) = (
        encoder.as_mut(),
        r.pass.frame_group.group(),
        r.pass.pipeline.get(&()),
    ) else {
        return;
    };
    let scope = timer.begin_pass(PassId::Deform);
    {
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("deform"),
            timestamp_writes: timer.compute_writes(&scope),
        });
        cp.set_pipeline(pipeline);
        for d in &r.pass.dispatches {
            let Some(out) = outputs.get(&d.entity) else {
                continue;
            };
            let groups = d.vertex_count.div_ceil(WORKGROUP_SIZE);
            cp.set_bind_group(0, frame_group, &[d.params_offset]);
            cp.set_bind_group(1, &out.groups[out.current], &[]);
            cp.dispatch_workgroups(groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X), 1);
        }
    }
    for d in &r.pass.dispatches {
        if let Some(out) = outputs.get_mut(&d.entity)
            && out.fresh
        {
            let [a, b] = &out.buffers;
            let (from, to) = if out.current == 0 { (a, b) } else { (b, a) };
            encoder.copy_buffer_to_buffer(from, 0, to, 0, None);
            out.fresh = false;
        }
    }
    timer.end_pass(scope);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        crate::assert_wgsl_twin!(GpuDeformParams, "deform.wgsl", &[], "DeformParams", [
            vertex_count, joint_offset, joint_count, weight_offset, target_count, skinned,
            pad => "pad0",
        ]);
    }
}

//! Traces a batch of rays against the frame's acceleration structure on the GPU
//! (`shaders/ray_batch.wgsl`): the traversal's throughput for `lumen bench --rays`, and
//! its agreement with the CPU traversal in the tests.

use super::scene_rays::{RAYS, SceneRays};
use crate::error::{Error, Result};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use crate::render::shaders::ShaderDef;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// The batch's own group: rays in, hits out.
const BATCH: BindGroupSpec = BindGroupSpec::compute("ray batch", declared::RAY_BATCH_0);
/// Invocations per workgroup (`@workgroup_size` of `cs_trace`).
const WORKGROUP: u32 = 64;

/// One ray (`BatchRay` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BatchRay {
    /// Origin (m) and t_min (m).
    pub origin: [f32; 4],
    /// Unit direction and t_max (m); a negative t_max asks the any-hit question with
    /// limit |t_max|.
    pub dir: [f32; 4],
}

impl BatchRay {
    /// A closest-hit ray (`any` false) or a shadow ray (`any` true) over `t_min .. t_max`.
    pub fn new(origin: Vec3, dir: Vec3, (t_min, t_max): (f32, f32), any: bool) -> BatchRay {
        BatchRay {
            origin: origin.extend(t_min).into(),
            dir: dir.extend(if any { -t_max } else { t_max }).into(),
        }
    }
}

/// One result (`BatchHit` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BatchHit {
    /// Distance (m).
    pub t: f32,
    /// Barycentric weight of corner B.
    pub b: f32,
    /// Barycentric weight of corner C.
    pub c: f32,
    /// Frame instance; `u32::MAX` for a miss.
    pub instance: u32,
    /// Triangle in its mesh.
    pub primitive: u32,
    /// 1 when the walk overflowed its step or stack bound.
    pub overflow: u32,
    /// Padding.
    pub pad: [u32; 2],
}

/// The test pattern of `ray_hit_counts` in `ray_batch.wgsl`: a hit on a masked or
/// blended instance counts where corner B's weight is below one half.
pub fn pattern_counts(b: f32) -> bool {
    b < 0.5
}

/// Traces `rays` against `scene` (updated for a frame) and returns each one's hit, and the
/// seconds the dispatch took from submission to completion.
pub fn trace_batch(
    gpu: &Gpu,
    scene: &SceneRays,
    rays: &[BatchRay],
) -> Result<(Vec<BatchHit>, f64)> {
    let resources = scene
        .resources()
        .ok_or_else(|| Error::Gpu("the ray scene was never built".into()))?;
    if rays.is_empty() {
        return Ok((Vec::new(), 0.0));
    }
    let composed = gpu
        .shaders
        .compose("ray_batch.wgsl", &[ShaderDef::U32("RAYS_GROUP", 1)])?;
    let module = create_module(gpu, "ray batch", &composed)?;
    let (batch_layout, rays_layout) = (BATCH.layout(gpu), RAYS.layout(gpu));
    let layout = pipeline_layout(gpu, "ray batch", &[&batch_layout, &rays_layout]);
    let pipeline = compute_pipeline(gpu, "ray batch", Some(&layout), &module, "cs_trace")?;
    let input = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ray batch: rays"),
            contents: bytemuck::cast_slice(rays),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let output = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("ray batch: hits"),
        size: std::mem::size_of_val(rays) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let batch_group = BATCH.group(
        gpu,
        &batch_layout,
        vec![input.as_entire_binding(), output.as_entire_binding()],
    )?;
    let rays_group = RAYS.group(gpu, &rays_layout, resources)?;
    let groups = (rays.len() as u32).div_ceil(WORKGROUP);
    let limit = gpu.device.limits().max_compute_workgroups_per_dimension;
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("ray batch"),
        });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ray batch"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &batch_group, &[]);
        pass.set_bind_group(1, &rays_group, &[]);
        pass.dispatch_workgroups(groups.min(limit), groups.div_ceil(limit), 1);
    }
    let start = std::time::Instant::now();
    let bytes = crate::render::readback::read_buffer(gpu, encoder, &output)?;
    let seconds = start.elapsed().as_secs_f64();
    Ok((bytemuck::cast_slice(&bytes).to_vec(), seconds))
}

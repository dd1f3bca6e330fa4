//! Traces a batch of rays against the frame's acceleration structure on the GPU
//! (`shaders/ray_batch.wgsl`): the traversal's throughput for `lumen bench --rays`, and
//! its agreement with the CPU traversal in the tests.

use super::scene_rays::{RAYS, RAYS_GROUP, SceneRays};
use crate::error::{Error, Result};
use crate::rays::tlas::RayScene;
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use crate::render::shaders::ShaderDef;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// The batch's own group (0): rays in, hits out.
pub const BATCH: BindGroupSpec = BindGroupSpec::compute("ray batch", declared::RAY_BATCH_0);
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
    let composed = gpu.shaders.compose(
        "ray_batch.wgsl",
        &[ShaderDef::U32("RAYS_GROUP", RAYS_GROUP)],
    )?;
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

/// `n` rays through the scene's box (deterministic for a `seed`): from points in and
/// around the box (padded by a quarter of its size) towards points in it, so that most
/// hit something; unit directions, the interval (10⁻⁴ m, ∞). What `lumen bench --rays`
/// traces, and the traversal's tests.
pub fn sample_rays(scene: &RayScene, n: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let root = scene.tlas_nodes.first().copied().unwrap_or_default();
    let (lo, hi) = (root.lo(), root.hi());
    let pad = (hi - lo).max(Vec3::splat(0.1)) * 0.25;
    let mut state = seed | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut in_box = move |lo: Vec3, hi: Vec3| lo + (hi - lo) * Vec3::new(next(), next(), next());
    (0..n)
        .map(|_| {
            let o = in_box(lo - pad, hi + pad);
            let target = in_box(lo, hi);
            (o, (target - o).normalize_or(Vec3::Y))
        })
        .collect()
}

/// What `lumen bench --rays` measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayThroughput {
    /// Rays traced.
    pub rays: usize,
    /// Of them, rays that hit.
    pub hits: usize,
    /// Closest-hit rays per second on the GPU (software traversal, dispatch to readback).
    pub gpu_rays_per_s: f64,
    /// Closest-hit rays per second of the CPU traversal on every core.
    pub cpu_rays_per_s: f64,
}

/// Traces `n` sampled rays on the GPU (after one warm-up dispatch) and on the CPU.
pub fn measure_throughput(gpu: &Gpu, scene: &SceneRays, n: usize) -> Result<RayThroughput> {
    use rayon::prelude::*;
    let rays = sample_rays(scene.scene(), n.max(1), 0x5eed);
    let batch: Vec<BatchRay> = rays
        .iter()
        .map(|&(o, d)| BatchRay::new(o, d, (1e-4, f32::INFINITY), false))
        .collect();
    trace_batch(gpu, scene, &batch[..batch.len().min(4096)])?;
    let (hits, gpu_s) = trace_batch(gpu, scene, &batch)?;
    let start = std::time::Instant::now();
    let cpu_hits = rays
        .par_iter()
        .filter(|&&(o, d)| {
            scene
                .scene()
                .trace(o, d, (1e-4, f32::INFINITY), false, &mut |i, _, h| {
                    i.surface == crate::rays::tlas::SURFACE_OPAQUE || pattern_counts(h.b)
                })
                .is_some()
        })
        .count();
    let cpu_s = start.elapsed().as_secs_f64();
    let gpu_hits = hits.iter().filter(|h| h.instance != u32::MAX).count();
    if gpu_hits != cpu_hits {
        return Err(Error::Gpu(format!(
            "the GPU traversal hit {gpu_hits} of {} rays, the CPU {cpu_hits}",
            rays.len()
        )));
    }
    Ok(RayThroughput {
        rays: rays.len(),
        hits: gpu_hits,
        gpu_rays_per_s: rays.len() as f64 / gpu_s.max(1e-9),
        cpu_rays_per_s: rays.len() as f64 / cpu_s.max(1e-9),
    })
}

//! Per-pass timing: CPU time to encode each pass, always; GPU time from timestamp queries
//! written at the start and end of each pass, where the adapter supports them.

use crate::render::device::Gpu;
use crate::render::graph::PassId;
use std::time::Instant;

/// Most passes one frame can time.
pub const MAX_TIMED_PASSES: u32 = 32;

/// How long one pass took.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTiming {
    /// Pass name (`gbuffer`, `lighting`, `tonemap`, …).
    pub name: &'static str,
    /// CPU time spent recording the pass, in milliseconds.
    pub cpu_ms: f64,
    /// GPU time between the pass's start and end timestamps, in milliseconds; `None`
    /// without timestamp queries.
    pub gpu_ms: Option<f64>,
}

/// An open pass: created by [`GpuTimer::begin_pass`], closed by [`GpuTimer::end_pass`].
#[derive(Debug)]
pub struct PassScope {
    index: u32,
    start: Instant,
}

struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

/// Timestamps and CPU spans of one frame's passes.
pub struct GpuTimer {
    queries: Option<Queries>,
    period_ns: f64,
    passes: Vec<PassTiming>,
}

impl GpuTimer {
    /// A timer; GPU timing only when `gpu.timestamps`.
    pub fn new(gpu: &Gpu) -> GpuTimer {
        let queries = gpu.timestamps.then(|| {
            let count = MAX_TIMED_PASSES * 2;
            let size = u64::from(count) * 8;
            Queries {
                set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                }),
                resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp resolve"),
                    size,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                readback: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp readback"),
                    size,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
            }
        });
        GpuTimer {
            queries,
            period_ns: f64::from(gpu.queue.get_timestamp_period()),
            passes: Vec::new(),
        }
    }

    /// Forgets the previous frame's passes.
    pub fn begin_frame(&mut self) {
        self.passes.clear();
    }

    /// Starts timing pass `id` (labelled with its name).
    pub fn begin_pass(&mut self, id: PassId) -> PassScope {
        self.begin_step(id.name())
    }

    /// Starts timing one step of a pass that records several (`dof blur`, …).
    pub fn begin_step(&mut self, name: &'static str) -> PassScope {
        let index = self.passes.len() as u32;
        self.passes.push(PassTiming {
            name,
            cpu_ms: 0.0,
            gpu_ms: None,
        });
        PassScope {
            index,
            start: Instant::now(),
        }
    }

    /// Timestamp writes for a render pass, if this pass can be timed on the GPU.
    pub fn render_writes(&self, scope: &PassScope) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let q = self.queries.as_ref()?;
        (scope.index < MAX_TIMED_PASSES).then(|| wgpu::RenderPassTimestampWrites {
            query_set: &q.set,
            beginning_of_pass_write_index: Some(scope.index * 2),
            end_of_pass_write_index: Some(scope.index * 2 + 1),
        })
    }

    /// Timestamp writes for a compute pass, if this pass can be timed on the GPU.
    pub fn compute_writes(
        &self,
        scope: &PassScope,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let q = self.queries.as_ref()?;
        (scope.index < MAX_TIMED_PASSES).then(|| wgpu::ComputePassTimestampWrites {
            query_set: &q.set,
            beginning_of_pass_write_index: Some(scope.index * 2),
            end_of_pass_write_index: Some(scope.index * 2 + 1),
        })
    }

    /// Ends a pass: records its CPU time.
    pub fn end_pass(&mut self, scope: PassScope) {
        if let Some(p) = self.passes.get_mut(scope.index as usize) {
            p.cpu_ms = scope.start.elapsed().as_secs_f64() * 1e3;
        }
    }

    /// Records the copy of this frame's timestamps into the readback buffer.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let Some(q) = &self.queries else { return };
        let used = (self.passes.len() as u32).min(MAX_TIMED_PASSES) * 2;
        if used == 0 {
            return;
        }
        encoder.resolve_query_set(&q.set, 0..used, &q.resolve, 0);
        encoder.copy_buffer_to_buffer(&q.resolve, 0, &q.readback, 0, u64::from(used) * 8);
    }

    /// After the frame's submission has completed: reads the GPU times back and returns
    /// every pass's timing.
    pub fn collect(&mut self, gpu: &Gpu) -> Vec<PassTiming> {
        let used = (self.passes.len() as u32).min(MAX_TIMED_PASSES) as usize;
        if let (Some(q), true) = (&self.queries, used > 0) {
            let slice = q.readback.slice(0..(used as u64 * 16));
            let (tx, rx) = std::sync::mpsc::channel();
            slice.map_async(wgpu::MapMode::Read, move |r| {
                let _ = tx.send(r);
            });
            let _ = gpu.device.poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            });
            if let Ok(Ok(())) = rx.recv() {
                if let Ok(data) = slice.get_mapped_range() {
                    let stamps: &[u64] = bytemuck::cast_slice(&data);
                    for (i, pass) in self.passes.iter_mut().take(used).enumerate() {
                        let (start, end) = (stamps[2 * i], stamps[2 * i + 1]);
                        // Some drivers leave unwritten or out-of-order stamps: no GPU time then.
                        pass.gpu_ms = (end >= start && start > 0)
                            .then(|| (end - start) as f64 * self.period_ns / 1e6);
                    }
                }
                q.readback.unmap();
            }
        }
        self.passes.clone()
    }
}

//! Automatic exposure: a luminance histogram of the frame on the GPU, metered and adapted
//! over time (`shaders/exposure.wgsl`). The adapted EV100 is read back after each frame and
//! exposes the next one (pre-exposure happens on the CPU, before anything is drawn).

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
pub use crate::render::frame::{FrameDelta, MeteredExposure};
use crate::render::graph::slots::HDR;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::create_module;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use wgpu::util::DeviceExt;

/// The metered exposure state, read back after the frame and exposing the next one
/// (owned by [`ExposurePass`]).
pub const EXPOSURE_STATE: Slot = Slot::owned("exposure state");

#[allow(non_upper_case_globals)]
impl PassId {
    /// Automatic exposure: luminance histogram and metering.
    pub const Exposure: PassId = PassId::new("exposure");
}

/// The exposure pass compiles the same two pipelines for every frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExposureVariant;

impl FramePass for ExposurePass {
    const ID: PassId = PassId::Exposure;
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[EXPOSURE_STATE];
    type Variant = ExposureVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        ExposurePass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<ExposureVariant> {
        let camera = world.resource::<ExtractedFrame>().camera.as_ref();
        let reason = match camera.and_then(|c| c.auto_exposure) {
            Some(a) => format!(
                "automatic exposure, EV100 {:.1}..{:.1}",
                a.min_ev100, a.max_ev100
            ),
            None => "manual, physical or linear exposure: nothing to meter".into(),
        };
        PassDecision::new(
            camera.is_some_and(|c| c.auto_exposure.is_some()),
            reason,
            ExposureVariant,
        )
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_exposure.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        exposure_pass.into_configs()
    }
}

/// log2 of the darkest luminance (cd/m²) the histogram resolves; darker is "black".
pub const HISTOGRAM_MIN_LOG2: f32 = -12.0;
/// The log2 luminance range the histogram spans (2⁻¹² … 2²⁰ cd/m²: 254 bins of 0.126 EV).
pub const HISTOGRAM_LOG2_RANGE: f32 = 32.0;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    exposure: f32,
    min_log2: f32,
    log2_range: f32,
    delta_s: f32,
    rate_per_s: f32,
    min_ev100: f32,
    max_ev100: f32,
    low_percentile: f32,
    high_percentile: f32,
    initial_ev100: f32,
    pad: [f32; 2],
}

/// The automatic exposure pass.
#[derive(Resource)]
pub struct ExposurePass {
    histogram_pipeline: wgpu::ComputePipeline,
    average_pipeline: wgpu::ComputePipeline,
    histogram: wgpu::Buffer,
    state: wgpu::Buffer,
    readback: wgpu::Buffer,
    params: wgpu::Buffer,
    bind_groups: Option<(u64, wgpu::BindGroup, wgpu::BindGroup)>,
    /// Whether the pass recorded work in the frame it last ran in (so the app, when the
    /// plan says it ran, reads the state back).
    pub ran: bool,
}

impl ExposurePass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let module = create_module(gpu, "exposure", &gpu.shaders.compose("exposure.wgsl", &[])?)?;
        let pipeline = |entry: &str| {
            gpu.checked(&format!("{entry} pipeline"), |device| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
        };
        let storage = |label, size| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        Ok(ExposurePass {
            histogram_pipeline: pipeline("cs_histogram")?,
            average_pipeline: pipeline("cs_average")?,
            histogram: storage("exposure histogram", 256 * 4),
            state: storage("exposure state", 16),
            readback: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("exposure readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            params: gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("exposure params"),
                    contents: &[0; std::mem::size_of::<Params>()],
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                }),
            bind_groups: None,
            ran: false,
        })
    }

    /// Forgets the adapted state: the next metered frame starts from the initial EV100.
    pub fn reset(&self, gpu: &Gpu) {
        gpu.queue.write_buffer(&self.state, 0, &[0; 16]);
    }

    /// After the frame's submission completed: reads the adapted state back.
    pub fn read_state(&self, gpu: &Gpu) -> Result<MeteredExposure> {
        let slice = self.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| Error::Gpu(format!("reading the exposure back: {e}")))?;
        rx.recv()
            .map_err(|e| Error::Gpu(e.to_string()))?
            .map_err(|e| Error::Gpu(format!("cannot map the exposure state: {e}")))?;
        let state: [f32; 4] = {
            let data = slice
                .get_mapped_range()
                .map_err(|e| Error::Gpu(format!("cannot read the exposure state: {e}")))?;
            *bytemuck::from_bytes(&data[..16])
        };
        self.readback.unmap();
        let valid = state[3] > 0.5 && state[0].is_finite();
        Ok(MeteredExposure {
            ev100: valid.then_some(state[0]),
            target_ev100: valid.then_some(state[1]),
            average_log2_luminance: valid.then_some(state[2]),
        })
    }
}

/// Writes the pass's parameters and binds the HDR target.
pub fn prepare_exposure(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    targets: Res<RenderTargets>,
    delta: Res<FrameDelta>,
    mut pass: ResMut<ExposurePass>,
) {
    pass.ran = false;
    let (Some(camera), Some(t)) = (frame.camera.as_ref(), targets.current.as_ref()) else {
        return;
    };
    let (Some(auto), Some(hdr)) = (camera.auto_exposure, t.view(HDR)) else {
        return;
    };
    let params = Params {
        exposure: camera.exposure,
        min_log2: HISTOGRAM_MIN_LOG2,
        log2_range: HISTOGRAM_LOG2_RANGE,
        delta_s: delta.0.clamp(0.0, 1.0),
        rate_per_s: auto.rate_per_s.max(0.0),
        min_ev100: auto.min_ev100,
        max_ev100: auto.max_ev100.max(auto.min_ev100),
        low_percentile: auto.low_percentile.clamp(0.0, 0.5),
        high_percentile: auto.high_percentile.clamp(0.5, 1.0),
        initial_ev100: auto.initial_ev100,
        pad: [0.0; 2],
    };
    gpu.queue
        .write_buffer(&pass.params, 0, bytemuck::bytes_of(&params));
    if pass
        .bind_groups
        .as_ref()
        .is_some_and(|(g, _, _)| *g == t.generation)
    {
        return;
    }
    let group = |pipeline: &wgpu::ComputePipeline, with_hdr: bool, with_state: bool| {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 2,
            resource: pass.histogram.as_entire_binding(),
        }];
        if with_hdr {
            entries.push(wgpu::BindGroupEntry {
                binding: 0,
                resource: pass.params.as_entire_binding(),
            });
            entries.push(wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(hdr),
            });
        }
        if with_state {
            entries.push(wgpu::BindGroupEntry {
                binding: 0,
                resource: pass.params.as_entire_binding(),
            });
            entries.push(wgpu::BindGroupEntry {
                binding: 3,
                resource: pass.state.as_entire_binding(),
            });
        }
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("exposure"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        })
    };
    let histogram = group(&pass.histogram_pipeline, true, false);
    let average = group(&pass.average_pipeline, false, true);
    pass.bind_groups = Some((t.generation, histogram, average));
}

/// Records the histogram and the metering.
pub fn exposure_pass(
    mut pass: ResMut<ExposurePass>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(t), Some((_, histogram, average))) = (
        encoder.as_mut(),
        targets.current.as_ref(),
        pass.bind_groups.as_ref(),
    ) else {
        return;
    };
    let scope = timer.begin_pass(PassId::Exposure);
    {
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("exposure"),
            timestamp_writes: timer.compute_writes(&scope),
        });
        cp.set_pipeline(&pass.histogram_pipeline);
        cp.set_bind_group(0, histogram, &[]);
        cp.dispatch_workgroups(t.size.0.div_ceil(16), t.size.1.div_ceil(16), 1);
        cp.set_pipeline(&pass.average_pipeline);
        cp.set_bind_group(0, average, &[]);
        cp.dispatch_workgroups(1, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&pass.state, 0, &pass.readback, 0, 16);
    timer.end_pass(scope);
    pass.ran = true;
}

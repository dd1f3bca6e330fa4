//! Automatic exposure: a luminance histogram of the frame on the GPU, metered and adapted
//! over time (`shaders/exposure.wgsl`). The adapted EV100 is read back after each frame and
//! exposes the next one (pre-exposure happens on the CPU, before anything is drawn).

use crate::error::{Error, Result};
use crate::render::bindings::CachedGroup;
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
pub use crate::render::frame::{FrameDelta, MeteredExposure};
use crate::render::graph::slots::HDR;
use crate::render::graph::{
    BufferDesc, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing, Slot,
};
use crate::render::pass_params::Prepare;
use crate::render::pipelines::{compute_pipeline, create_module};
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;

/// The metered exposure state (16 bytes), kept across frames, read back after each frame
/// and exposing the next one.
pub const EXPOSURE_STATE: Slot = Slot::buffer(
    "exposure state",
    BufferDesc {
        usage: wgpu::BufferUsages::STORAGE,
        history: true,
    },
);

/// The frame's luminance histogram: 256 bins of 4 bytes.
pub const EXPOSURE_HISTOGRAM: Slot = Slot::buffer(
    "exposure histogram",
    BufferDesc {
        usage: wgpu::BufferUsages::STORAGE,
        history: false,
    },
);

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
    const WRITES: &'static [Slot] = &[EXPOSURE_STATE, EXPOSURE_HISTOGRAM];
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
        .sized(EXPOSURE_STATE, Sizing::Buffer(16))
        .sized(EXPOSURE_HISTOGRAM, Sizing::Buffer(256 * 4))
    }

    crate::pass_systems!(prepare_exposure, exposure_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![ShaderBuild::new("exposure.wgsl", Vec::new(), &[])]
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
    readback: wgpu::Buffer,
    params: wgpu::Buffer,
    /// The two pipelines' bind group layouts (derived from the shader).
    layouts: [wgpu::BindGroupLayout; 2],
    histogram_group: CachedGroup,
    average_group: CachedGroup,
    /// Whether the pass recorded work in the frame it last ran in (so the app, when the
    /// plan says it ran, reads the state back).
    pub ran: bool,
}

impl ExposurePass {
    /// Compiles the pass.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let module = create_module(gpu, "exposure", &gpu.shaders.compose("exposure.wgsl", &[])?)?;
        let pipeline = |entry: &str| compute_pipeline(gpu, entry, None, &module, entry);
        let histogram_pipeline = pipeline("cs_histogram")?;
        let average_pipeline = pipeline("cs_average")?;
        Ok(ExposurePass {
            layouts: [
                histogram_pipeline.get_bind_group_layout(0),
                average_pipeline.get_bind_group_layout(0),
            ],
            histogram_pipeline,
            average_pipeline,
            readback: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("exposure readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            params: gpu.uniform_buffer("exposure params", std::mem::size_of::<Params>() as u64),
            histogram_group: CachedGroup::default(),
            average_group: CachedGroup::default(),
            ran: false,
        })
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

/// After the frame's submission completed: where the pass ran, reads the adapted state
/// back into [`MeteredExposure`], which the next frame's exposure starts from.
pub fn feed_back(world: &mut World, gpu: &Gpu) -> Result<()> {
    let ran = world.resource::<FramePlan>().runs(PassId::Exposure)
        && world.get_resource::<ExposurePass>().is_some_and(|p| p.ran);
    if ran {
        let metered = world.resource::<ExposurePass>().read_state(gpu)?;
        world.insert_resource(metered);
    }
    Ok(())
}

/// Writes the pass's parameters and binds the HDR target, the histogram and the state.
pub fn prepare_exposure(
    mut p: Prepare<ExposurePass>,
    frame: Res<ExtractedFrame>,
    delta: Res<FrameDelta>,
) -> Result<()> {
    p.pass.ran = false;
    let (Some(camera), Some(t)) = (frame.camera.as_ref(), p.targets.current.as_ref()) else {
        return Ok(());
    };
    let (Some(auto), Some(hdr), Some(histogram), Some(state)) = (
        camera.auto_exposure,
        t.view(HDR),
        t.buffer(EXPOSURE_HISTOGRAM),
        t.buffer(EXPOSURE_STATE),
    ) else {
        return Ok(());
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
    p.gpu
        .queue
        .write_buffer(&p.pass.params, 0, bytemuck::bytes_of(&params));
    let ExposurePass {
        layouts,
        params,
        histogram_group,
        average_group,
        ..
    } = &mut *p.pass;
    let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
    histogram_group.entries(
        &p.gpu,
        "exposure histogram",
        &layouts[0],
        vec![
            entry(0, params.as_entire_binding()),
            entry(1, wgpu::BindingResource::TextureView(hdr)),
            entry(2, histogram.as_entire_binding()),
        ],
    );
    average_group.entries(
        &p.gpu,
        "exposure average",
        &layouts[1],
        vec![
            entry(0, params.as_entire_binding()),
            entry(2, histogram.as_entire_binding()),
            entry(3, state.as_entire_binding()),
        ],
    );
    Ok(())
}

/// Records the histogram and the metering.
pub fn exposure_pass(
    mut pass: ResMut<ExposurePass>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(t), Some(histogram), Some(average)) = (
        encoder.as_mut(),
        targets.current.as_ref(),
        pass.histogram_group.group(),
        pass.average_group.group(),
    ) else {
        return;
    };
    let Some(state) = t.buffer(EXPOSURE_STATE) else {
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
    encoder.copy_buffer_to_buffer(state, 0, &pass.readback, 0, 16);
    timer.end_pass(scope);
    pass.ran = true;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        crate::assert_wgsl_twin!(Params, "exposure.wgsl", &[], "ExposureParams", [
            exposure, min_log2, log2_range, delta_s, rate_per_s, min_ev100, max_ev100,
            low_percentile, high_percentile, initial_ev100, pad => "pad0",
        ]);
    }
}

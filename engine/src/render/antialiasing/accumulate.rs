//! Accumulation (`--accumulate N`): the frame is rendered N times with the camera
//! jittered inside the pixel ([`crate::render::jitter::Jitter::halton`]), and this pass keeps the
//! running mean of the HDR images ([`crate::antialiasing::running_mean`], in an f32
//! target) and writes it back into the HDR target for the passes after it. Equal weights
//! over sample positions spread evenly over the pixel make the box pixel filter that
//! `lumen reference` uses, so N → ∞ converges to the reference's pixel footprint.
//!
//! `accumulate.wgsl` updates the mean (ping-ponging between two targets), and
//! [`CopyToHdr`] writes it into the HDR target.

use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::ACCUMULATE;
use crate::render::antialiasing::copy::CopyToHdr;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::HDR;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::{draw_fullscreen, fullscreen_variant, one_group_layout};
use crate::render::targets::{RenderTargets, Target};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The running mean of jittered frames.
    pub const Accumulate: PassId = PassId::new("accumulate");
}

/// The running mean of the frame's jittered renders (two f32 targets the pass owns).
pub const ACCUMULATION: Slot = Slot::owned("accumulation (running mean)");

/// Format of the running mean: f32, so a mean of a thousand frames keeps 24 bits, where
/// the adapter can render to it; else f16 (GL on llvmpipe), whose 11 bits hold a mean of
/// about 16 renders before later ones stop moving it (the plan says so).
pub fn mean_format(gpu: &Gpu) -> wgpu::TextureFormat {
    let f32_renderable = gpu
        .adapter
        .get_texture_format_features(wgpu::TextureFormat::Rgba32Float)
        .allowed_usages
        .contains(wgpu::TextureUsages::RENDER_ATTACHMENT);
    if f32_renderable {
        wgpu::TextureFormat::Rgba32Float
    } else {
        wgpu::TextureFormat::Rgba16Float
    }
}

/// Which of an image's jittered renders this frame is; [`crate::App`] sets it before
/// each one. `count` 1 is an ordinary frame.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubFrame {
    /// This render, from 0.
    pub index: u32,
    /// Renders averaged into the image.
    pub count: u32,
}

impl Default for SubFrame {
    fn default() -> Self {
        SubFrame { index: 0, count: 1 }
    }
}

impl FramePass for AccumulatePass {
    const ID: PassId = PassId::Accumulate;
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[HDR, ACCUMULATION];
    type Variant = wgpu::TextureFormat;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        AccumulatePass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<wgpu::TextureFormat> {
        let sub = world
            .get_resource::<SubFrame>()
            .copied()
            .unwrap_or_default();
        let format = world
            .resource::<crate::quality::Quality>()
            .hdr_precision
            .format();
        let precision = match world.get_resource::<AccumulatePass>() {
            Some(p) if p.mean_format == wgpu::TextureFormat::Rgba16Float => {
                ", an f16 mean: this adapter cannot render to f32"
            }
            _ => "",
        };
        PassDecision::new(
            sub.count > 1,
            if sub.count > 1 {
                format!(
                    "render {} of {} jittered renders averaged (box pixel filter){precision}",
                    sub.index + 1,
                    sub.count
                )
            } else {
                format!(
                    "one render per image ({})",
                    ACCUMULATE.setting(Value::Int(1))
                )
            },
            format,
        )
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_accumulate.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        accumulate_pass.into_configs()
    }
}

/// The mean's update: this render, the mean so far, and the weight.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "accumulate",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("hdr", Binding::TextureLoad),
        ("previous", Binding::TextureLoad),
        ("params", Binding::Uniform),
    ],
};

/// The two means (ping-pong), and their bind groups for even and odd renders.
struct Means {
    targets: [Target; 2],
    key: u64,
    /// Per parity: the update's group and the copy's group.
    groups: [(wgpu::BindGroup, wgpu::BindGroup); 2],
}

/// The accumulation's pipelines, targets and bindings.
#[derive(Resource)]
pub struct AccumulatePass {
    layout: wgpu::BindGroupLayout,
    update: wgpu::RenderPipeline,
    mean_format: wgpu::TextureFormat,
    copy: CopyToHdr,
    params: wgpu::Buffer,
    means: Option<Means>,
    parity: usize,
}

impl AccumulatePass {
    /// Creates the layouts and the update pipeline; the copy compiles per HDR format.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let layout = BINDINGS.layout(gpu);
        let update_layout = one_group_layout(gpu, "accumulate", &layout);
        let mean_format = mean_format(gpu);
        let update = fullscreen_variant(
            gpu,
            "accumulate",
            &update_layout,
            "accumulate.wgsl",
            &[],
            mean_format,
        )?;
        Ok(AccumulatePass {
            layout,
            update,
            mean_format,
            copy: CopyToHdr::new(gpu),
            params: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accumulate params"),
                size: 16,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            means: None,
            parity: 0,
        })
    }
}

/// Compiles the copy for this frame's HDR format, (re)creates the means at the frame's
/// size, and writes this render's weight 1/(index + 1).
pub fn prepare_accumulate(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    sub: Option<Res<SubFrame>>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<AccumulatePass>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(&format) = plan.variant::<AccumulatePass>() else {
        return;
    };
    let pass = &mut *pass;
    if let Err(e) = pass.copy.ensure(&gpu, format) {
        errors.0.push(e);
        return;
    }
    let Some((t, hdr)) = targets
        .current
        .as_ref()
        .and_then(|t| Some((t, t.view(HDR)?)))
    else {
        return;
    };
    if pass.means.as_ref().is_none_or(|m| m.key != t.generation) {
        let targets = [0, 1].map(|_| Target::new(&gpu, "accumulation", t.size, pass.mean_format));
        let mut groups = Vec::with_capacity(2);
        for parity in 0..2 {
            let (write, read) = (&targets[parity], &targets[1 - parity]);
            let update = BINDINGS.group(
                &gpu,
                &pass.layout,
                vec![
                    wgpu::BindingResource::TextureView(hdr),
                    wgpu::BindingResource::TextureView(&read.view),
                    pass.params.as_entire_binding(),
                ],
            );
            let copy = pass.copy.group(&gpu, &write.view);
            match (update, copy) {
                (Ok(u), Ok(c)) => groups.push((u, c)),
                (Err(e), _) | (_, Err(e)) => {
                    errors.0.push(e);
                    return;
                }
            }
        }
        let Ok(groups) = <[_; 2]>::try_from(groups) else {
            return;
        };
        pass.means = Some(Means {
            targets,
            key: t.generation,
            groups,
        });
    }
    let index = sub.map_or(0, |s| s.index);
    pass.parity = (index % 2) as usize;
    let weight = 1.0 / (f64::from(index) + 1.0) as f32;
    gpu.queue.write_buffer(
        &pass.params,
        0,
        bytemuck::cast_slice(&[weight, 0.0, 0.0, 0.0]),
    );
}

/// Records the mean's update and its copy into the HDR target.
pub fn accumulate_pass(
    pass: Res<AccumulatePass>,
    plan: Res<FramePlan>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(means), Some(hdr), Some(copy)) = (
        encoder.as_mut(),
        pass.means.as_ref(),
        targets.current.as_ref().and_then(|t| t.view(HDR)),
        plan.variant::<AccumulatePass>()
            .and_then(|f| pass.copy.pipeline(*f)),
    ) else {
        return;
    };
    let (update_group, copy_group) = &means.groups[pass.parity];
    draw_fullscreen(
        encoder,
        timer,
        PassId::Accumulate.name(),
        &[&means.targets[pass.parity].view],
        &pass.update,
        update_group,
    );
    draw_fullscreen(encoder, timer, "accumulate copy", &[hdr], copy, copy_group);
}

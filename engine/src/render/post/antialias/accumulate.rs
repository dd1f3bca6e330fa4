//! Accumulation (`--accumulate N`): the frame is rendered N times with the camera
//! jittered inside the pixel ([`crate::render::jitter::Jitter::halton`]), and this pass keeps the
//! running mean of the HDR images ([`crate::shading::antialiasing::running_mean`], in an f32
//! target) and writes it back into the HDR target for the passes after it. Equal weights
//! over sample positions spread evenly over the pixel make the box pixel filter that
//! `lumen reference` uses, so N → ∞ converges to the reference's pixel footprint.
//!
//! `accumulate.wgsl` updates the mean (ping-ponging between two targets), and
//! [`CopyToHdr`] writes it into the HDR target.

use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::ACCUMULATE;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::HDR;
use crate::render::graph::{
    Extent, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing, Slot, TargetFormat,
    TextureDesc,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::Fullscreen;
use crate::render::post::antialias::copy::CopyToHdr;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The running mean of jittered frames.
    pub const Accumulate: PassId = PassId::new("accumulate");
}

/// The running mean of an image's jittered renders, ping-ponged between two histories
/// (kept from one render to the next) in the [`mean_format`].
pub const ACCUMULATION: [Slot; 2] = [
    Slot::texture("accumulation (running mean) a", MEAN),
    Slot::texture("accumulation (running mean) b", MEAN),
];

/// A running mean: a history at the output's size, in the format the decision gives.
const MEAN: TextureDesc = TextureDesc::full(TargetFormat::Decided).history();

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
    const WRITES: &'static [Slot] = &[HDR, ACCUMULATION[0], ACCUMULATION[1]];
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
        let mean = world
            .get_resource::<AccumulatePass>()
            .map_or(wgpu::TextureFormat::Rgba32Float, |p| p.mean_format);
        let precision = if mean == wgpu::TextureFormat::Rgba16Float {
            ", an f16 mean: this adapter cannot render to f32"
        } else {
            ""
        };
        let sizing = Sizing::Texture(Extent::Full, Some(mean));
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
        .sized(ACCUMULATION[0], sizing)
        .sized(ACCUMULATION[1], sizing)
    }

    crate::pass_systems!(prepare_accumulate, accumulate_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![
            ShaderBuild::new("accumulate.wgsl", Vec::new(), &[(0, BINDINGS)]),
            crate::render::post::antialias::copy::build(),
        ]
    }
}

/// The mean's update: this render, the mean so far, and the weight.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("accumulate", declared::ACCUMULATE_0);

/// The accumulation's pipelines, targets and bindings.
#[derive(Resource)]
pub struct AccumulatePass {
    update: FullscreenStep,
    mean_format: wgpu::TextureFormat,
    copy: CopyToHdr,
    params: wgpu::Buffer,
    /// Per parity: the update's group (it writes mean `parity`, reading the other) and
    /// the copy's group (it copies mean `parity` into the HDR target).
    groups: [[CachedGroup; 2]; 2],
    parity: usize,
}

impl AccumulatePass {
    /// Creates the layouts and the update pipeline; the copy compiles per HDR format.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let mean_format = mean_format(gpu);
        let mut update = FullscreenStep::new(
            gpu,
            Fullscreen::new("accumulate", "accumulate.wgsl"),
            &BINDINGS,
        );
        update.ensure(gpu, (), &[mean_format])?;
        Ok(AccumulatePass {
            update,
            mean_format,
            copy: CopyToHdr::new(gpu),
            params: gpu.uniform_buffer("accumulate params", 16),
            groups: Default::default(),
            parity: 0,
        })
    }
}

/// Compiles the copy for this frame's HDR format, (re)creates the means at the frame's
/// size, and writes this render's weight 1/(index + 1).
pub fn prepare_accumulate(
    mut p: Prepare<AccumulatePass>,
    sub: Option<Res<SubFrame>>,
) -> Result<()> {
    let Some(&format) = p.plan.variant::<AccumulatePass>() else {
        return Ok(());
    };
    let pass = &mut *p.pass;
    pass.copy.0.ensure(&p.gpu, (), &[format])?;
    let Some(t) = p.targets.current.as_ref() else {
        return Ok(());
    };
    let (Some(hdr), Some(means)) = (t.view(HDR), t.views(ACCUMULATION)) else {
        return Ok(());
    };
    for (parity, [update, copy]) in pass.groups.iter_mut().enumerate() {
        let made = pass
            .update
            .bind_in(
                update,
                &p.gpu,
                vec![
                    wgpu::BindingResource::TextureView(hdr),
                    wgpu::BindingResource::TextureView(means[1 - parity]),
                    pass.params.as_entire_binding(),
                ],
            )
            .map(|_| ())
            .and_then(|()| pass.copy.group(copy, &p.gpu, means[parity]).map(|_| ()));
        made?;
    }
    let index = sub.map_or(0, |s| s.index);
    pass.parity = (index % 2) as usize;
    let weight = 1.0 / (f64::from(index) + 1.0) as f32;
    p.gpu.queue.write_buffer(
        &pass.params,
        0,
        bytemuck::cast_slice(&[weight, 0.0, 0.0, 0.0]),
    );
    Ok(())
}

/// Records the mean's update and its copy into the HDR target.
pub fn accumulate_pass(mut r: Record<AccumulatePass>) {
    let t = r.targets.current.as_ref();
    let [update_group, copy_group] = &r.pass.groups[r.pass.parity];
    let (Some(mean), Some(hdr), Some(&format)) = (
        t.and_then(|t| t.view(ACCUMULATION[r.pass.parity])),
        t.and_then(|t| t.view(HDR)),
        r.plan.variant::<AccumulatePass>(),
    ) else {
        return;
    };
    let update = r.pass.update.pipeline((), &[r.pass.mean_format]);
    let name = PassId::Accumulate.name();
    r.encoder
        .fullscreen(name, &[mean], update, update_group.group());
    let copy = r.pass.copy.0.pipeline((), &[format]);
    r.encoder
        .fullscreen("accumulate copy", &[hdr], copy, copy_group.group());
}

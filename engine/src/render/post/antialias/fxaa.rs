//! FXAA (`--aa fxaa`, Lottes 2009): one frame's edges found from luma contrast, kept
//! where a silhouette or a crease crosses them (the depth buffer and the G-buffer's
//! normals, [`crate::shading::antialiasing::depth_bend`] and [`crate::shading::antialiasing::creased`]), and
//! blended across, in three steps: the HDR image is copied with its perceptual luma
//! ([`super::prepare`]); `fxaa.wgsl`'s `fs_mark` writes depth 1 into a mask where the luma
//! has an edge; and its `fs_main`, depth-tested against the mask so that no other pixel
//! is shaded, filters the image and writes the result into the HDR target. It runs after
//! depth of field, on the image tone mapping will show.

use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::AA;
use crate::quality::{AaMethod, Quality};
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::{DEPTH, GBUFFER_NORMAL, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, FullscreenPipelines};
use crate::render::pipelines::{FullscreenDraw, MaskDepth, draw_fullscreen_pass, mask_depth_state};
use crate::render::post::antialias::prepare::{AA_PREPARED, MASK, Preparation};
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Fast approximate anti-aliasing.
    pub const Fxaa: PassId = PassId::new("fxaa");
}

impl FramePass for FxaaPass {
    const ID: PassId = PassId::Fxaa;
    const READS: &'static [Slot] = &[HDR, DEPTH, GBUFFER_NORMAL];
    const WRITES: &'static [Slot] = &[HDR, AA_PREPARED, FXAA_MASK];
    type Variant = wgpu::TextureFormat;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        FxaaPass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<wgpu::TextureFormat> {
        let quality = world.resource::<Quality>();
        let accumulating = quality.aa.accumulate > 1;
        let (runs, reason) = match quality.aa.method {
            AaMethod::None => (false, AA.setting(Value::Name("none"))),
            AaMethod::Smaa => (
                false,
                format!("SMAA instead ({})", AA.setting(Value::Name("smaa"))),
            ),
            AaMethod::Taa => (
                false,
                format!(
                    "temporal anti-aliasing instead ({})",
                    AA.setting(Value::Name("taa"))
                ),
            ),
            AaMethod::Fxaa if accumulating => (
                false,
                "the accumulation of jittered renders already filters every pixel".into(),
            ),
            AaMethod::Fxaa => (
                true,
                format!(
                    "blends luma edges across on silhouettes and creases ({})",
                    AA.setting(Value::Name("fxaa"))
                ),
            ),
        };
        PassDecision::new(runs, reason, quality.hdr_precision.format())
    }

    crate::pass_systems!(prepare_fxaa, fxaa_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![
            ShaderBuild::new("fxaa.wgsl", Vec::new(), &[(0, BINDINGS)]),
            crate::render::post::antialias::prepare::build(),
        ]
    }
}

/// The filter's input.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("fxaa", declared::FXAA_0);

/// Depth 1 where the luma has an edge, 0 elsewhere: the pixels the filter shades.
pub const FXAA_MASK: Slot = Slot::texture("fxaa mask", MASK);

/// FXAA's pipelines, target and bindings.
#[derive(Resource)]
pub struct FxaaPass {
    preparation: Preparation,
    layout: wgpu::BindGroupLayout,
    /// Writes the mask (no colour target).
    mark: FullscreenPipelines,
    /// Filters the image, per HDR format.
    filters: FullscreenPipelines,
    sampler: wgpu::Sampler,
    filter: CachedGroup,
}

impl FxaaPass {
    /// Creates the layouts and the preparation pipeline; the filter compiles per HDR
    /// format.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let layout = BINDINGS.layout(gpu);
        Ok(FxaaPass {
            preparation: Preparation::new(gpu)?,
            mark: FullscreenPipelines::new(
                gpu,
                Fullscreen::new("fxaa mark", "fxaa.wgsl")
                    .entry("fs_mark")
                    .depth(mask_depth_state(MaskDepth::Mark)),
                &[&layout],
            ),
            filters: FullscreenPipelines::new(
                gpu,
                Fullscreen::new("fxaa", "fxaa.wgsl").depth(mask_depth_state(MaskDepth::Test)),
                &[&layout],
            ),
            layout,
            sampler: gpu.sampler("fxaa", wgpu::FilterMode::Linear),
            filter: CachedGroup::default(),
        })
    }
}

/// Compiles the filter for this frame's HDR format (and the mark, once) and (re)creates
/// the prepared image at the frame's size.
pub fn prepare_fxaa(mut p: Prepare<FxaaPass>) -> Result<()> {
    let Some(&format) = p.plan.variant::<FxaaPass>() else {
        return Ok(());
    };
    let pass = &mut *p.pass;
    (pass.filters.ensure(&p.gpu, (), &[format]).map(|_| ()))
        .and_then(|()| pass.mark.ensure(&p.gpu, (), &[]).map(|_| ()))?;
    let Some(t) = p.targets.current.as_ref() else {
        return Ok(());
    };
    let Some([hdr, prepared, depth, normal]) = t.views([HDR, AA_PREPARED, DEPTH, GBUFFER_NORMAL])
    else {
        return Ok(());
    };
    pass.preparation.prepare(&p.gpu, hdr).and_then(|()| {
        pass.filter
            .get(
                &p.gpu,
                &BINDINGS,
                &pass.layout,
                vec![
                    wgpu::BindingResource::TextureView(prepared),
                    wgpu::BindingResource::Sampler(&pass.sampler),
                    wgpu::BindingResource::TextureView(depth),
                    wgpu::BindingResource::TextureView(normal),
                ],
            )
            .map(|_| ())
    })
}

/// Records the preparation, the mark and the filter.
pub fn fxaa_pass(mut r: Record<FxaaPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(group), Some(mark), Some([hdr, prepared, mask]), Some(filter)) = (
        encoder.as_mut(),
        r.pass.filter.group(),
        r.pass.mark.get((), &[]),
        r.targets
            .current
            .as_ref()
            .and_then(|t| t.views([HDR, AA_PREPARED, FXAA_MASK])),
        r.plan
            .variant::<FxaaPass>()
            .and_then(|f| r.pass.filters.get((), &[*f])),
    ) else {
        return;
    };
    r.pass
        .preparation
        .record(encoder, timer, "fxaa prepare", prepared);
    // The filter shades only the pixels the mark step marked; the others keep the HDR
    // target's exact value.
    draw_fullscreen_pass(
        encoder,
        timer,
        &FullscreenDraw {
            name: "fxaa mark",
            targets: &[],
            load: wgpu::LoadOp::Load,
            depth: Some((mask, wgpu::LoadOp::Clear(0.0))),
            pipeline: mark,
            groups: &[group],
        },
    );
    draw_fullscreen_pass(
        encoder,
        timer,
        &FullscreenDraw {
            name: PassId::Fxaa.name(),
            targets: &[hdr],
            load: wgpu::LoadOp::Load,
            depth: Some((mask, wgpu::LoadOp::Load)),
            pipeline: filter,
            groups: &[group],
        },
    );
}

//! SMAA 1x (`--aa smaa`; Jimenez, Echevarria, Sousa & Gutierrez 2012, "SMAA: Enhanced
//! Subpixel Morphological Antialiasing", after Reshetov 2009's morphological AA), on one
//! frame, in four steps:
//! 1. the HDR image is copied with its perceptual luma ([`super::prepare`]);
//! 2. `smaa_edges.wgsl` marks each pixel's left and top edges where the perceptual luma
//!    steps ([`crate::shading::antialiasing::smaa_edge`]);
//! 3. `smaa_weights.wgsl`, on edge pixels only (depth-tested against a mask the edge step
//!    writes, so that no other pixel is shaded), follows each edge to both ends (up to
//!    [`MAX_SEARCH`] pixels each way), reads the crossing edges there, and evaluates the
//!    coverage of the revectorized silhouette ([`crate::shading::antialiasing::smaa_coverage`]);
//! 4. `smaa_blend.wgsl` mixes every pixel with its neighbours across its edges by those
//!    coverages, in linear colour (the mean a pixel filter takes), and writes the result
//!    into the HDR target.
//!
//! It handles the orthogonal patterns; SMAA's diagonal patterns and corner rounding are
//! not built (the paper's medium preset has neither). The coverage is evaluated in the
//! shader rather than read from a precomputed area texture, and the search reads the
//! edges pixel by pixel rather than through SMAA's bilinear search texture.

use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::AA;
use crate::quality::{AaMethod, Quality};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::frame::FrameEncoder;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::HDR;
use crate::render::graph::{
    FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot, TargetFormat,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, ShaderVariant};
use crate::render::pipelines::{
    FullscreenDraw, MaskDepth, draw_fullscreen_pass, draw_fullscreen_with, mask_depth_state,
};
use crate::render::post::antialias::prepare::{AA_PREPARED, MASK, Preparation};
use crate::render::shaders::ShaderDef;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Subpixel morphological anti-aliasing.
    pub const Smaa: PassId = PassId::new("smaa");
}

/// Farthest an edge is followed each way, in pixels: SMAA's high preset reaches 32
/// pixels. A longer segment is treated as ending there without a step, which leaves its
/// middle unblended, as a straight edge should be.
pub const MAX_SEARCH: u32 = 32;

/// The coverage step's one build: it searches up to [`MAX_SEARCH`] pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SearchLength;

impl ShaderVariant for SearchLength {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![ShaderDef::U32("MAX_SEARCH", MAX_SEARCH)]
    }
}

/// The edges: left (r) and top (g), 0 or 1.
const EDGES_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg8Unorm;
/// The coverages, each in [0, ½]: 8 bits step by 1/255 of a pixel (rounding error at
/// most 1/510).
const WEIGHTS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl FramePass for SmaaPass {
    const ID: PassId = PassId::Smaa;
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[HDR, AA_PREPARED, SMAA_EDGES, SMAA_MASK, SMAA_WEIGHTS];
    type Variant = wgpu::TextureFormat;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        SmaaPass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<wgpu::TextureFormat> {
        let quality = world.resource::<Quality>();
        let (runs, reason) = match quality.aa.method {
            AaMethod::Smaa if quality.aa.accumulate > 1 => (
                false,
                "the accumulation of jittered renders already filters every pixel".to_string(),
            ),
            AaMethod::Smaa => (
                true,
                format!(
                    "blends across luma edges' patterns ({})",
                    AA.setting(Value::Name("smaa"))
                ),
            ),
            AaMethod::None => (false, AA.setting(Value::Name("none"))),
            AaMethod::Fxaa => (
                false,
                format!("FXAA instead ({})", AA.setting(Value::Name("fxaa"))),
            ),
            AaMethod::Taa => (
                false,
                format!(
                    "temporal anti-aliasing instead ({})",
                    AA.setting(Value::Name("taa"))
                ),
            ),
        };
        PassDecision::new(runs, reason, quality.hdr_precision.format())
    }

    crate::pass_systems!(prepare_smaa, smaa_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![
            ShaderBuild::new("smaa_edges.wgsl", Vec::new(), &[(0, EDGES_BINDINGS)]),
            ShaderBuild::new(
                "smaa_weights.wgsl",
                SearchLength.shader_defs(),
                &[(0, WEIGHTS_BINDINGS)],
            ),
            ShaderBuild::new("smaa_blend.wgsl", Vec::new(), &[(0, BLEND_BINDINGS)]),
            crate::render::post::antialias::prepare::build(),
        ]
    }
}

/// The edge step's input.
pub const EDGES_BINDINGS: BindGroupSpec =
    BindGroupSpec::fragment("smaa edges", declared::SMAA_EDGES_0);

/// The coverage step's input.
pub const WEIGHTS_BINDINGS: BindGroupSpec =
    BindGroupSpec::fragment("smaa weights", declared::SMAA_WEIGHTS_0);

/// The blend's inputs.
pub const BLEND_BINDINGS: BindGroupSpec =
    BindGroupSpec::fragment("smaa blend", declared::SMAA_BLEND_0);

/// The edges found from luma.
pub const SMAA_EDGES: Slot = Slot::target("smaa edges", TargetFormat::Fixed(EDGES_FORMAT));

/// Depth 1 on the pixels with an edge, 0 elsewhere.
pub const SMAA_MASK: Slot = Slot::texture("smaa mask", MASK);

/// The coverages the blend mixes each edge pixel with.
pub const SMAA_WEIGHTS: Slot = Slot::target("smaa weights", TargetFormat::Fixed(WEIGHTS_FORMAT));

/// SMAA's steps.
#[derive(Resource)]
pub struct SmaaPass {
    preparation: Preparation,
    /// Writes the edges and marks the mask.
    edges: FullscreenStep,
    /// Shades the marked pixels only.
    weights: FullscreenStep<SearchLength>,
    /// Compiled per HDR format.
    blend: FullscreenStep,
}

impl SmaaPass {
    /// Compiles the preparation, edge and coverage steps; the blend compiles per HDR
    /// format.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        // The edge step writes the mask (depth 1 on edge pixels); the coverage step is
        // tested against it and shades only those.
        let mut edges = FullscreenStep::new(
            gpu,
            Fullscreen::new("smaa edges", "smaa_edges.wgsl")
                .depth(mask_depth_state(MaskDepth::Mark)),
            &EDGES_BINDINGS,
        );
        edges.ensure(gpu, (), &[EDGES_FORMAT])?;
        let mut weights = FullscreenStep::new(
            gpu,
            Fullscreen::new("smaa weights", "smaa_weights.wgsl")
                .depth(mask_depth_state(MaskDepth::Test)),
            &WEIGHTS_BINDINGS,
        );
        weights.ensure(gpu, SearchLength, &[WEIGHTS_FORMAT])?;
        Ok(SmaaPass {
            preparation: Preparation::new(gpu)?,
            edges,
            weights,
            blend: FullscreenStep::new(
                gpu,
                Fullscreen::new("smaa blend", "smaa_blend.wgsl"),
                &BLEND_BINDINGS,
            ),
        })
    }
}

/// Compiles the blend for this frame's HDR format and (re)creates the images at the
/// frame's size.
pub fn prepare_smaa(mut p: Prepare<SmaaPass>) -> Result<()> {
    let Some(&format) = p.plan.variant::<SmaaPass>() else {
        return Ok(());
    };
    let pass = &mut *p.pass;
    pass.blend.ensure(&p.gpu, (), &[format])?;
    let Some([hdr, prepared, edges, weights]) = p
        .targets
        .current
        .as_ref()
        .and_then(|t| t.views([HDR, AA_PREPARED, SMAA_EDGES, SMAA_WEIGHTS]))
    else {
        return Ok(());
    };
    let view = wgpu::BindingResource::TextureView;
    (pass.preparation.prepare(&p.gpu, hdr))
        .and_then(|()| pass.edges.bind(&p.gpu, vec![view(prepared)]))
        .and_then(|()| pass.weights.bind(&p.gpu, vec![view(edges)]))
        .and_then(|()| pass.blend.bind(&p.gpu, vec![view(prepared), view(weights)]))
}

/// Records the four steps.
pub fn smaa_pass(mut r: Record<SmaaPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(views), Some(format)) = (
        encoder.as_mut(),
        r.targets
            .current
            .as_ref()
            .and_then(|t| t.views([HDR, AA_PREPARED, SMAA_EDGES, SMAA_MASK, SMAA_WEIGHTS])),
        r.plan.variant::<SmaaPass>(),
    ) else {
        return;
    };
    let (
        Some(edges_pipeline),
        Some(weights_pipeline),
        Some(blend),
        Some(edges_group),
        Some(weights_group),
        Some(blend_group),
    ) = (
        r.pass.edges.pipeline((), &[EDGES_FORMAT]),
        r.pass.weights.pipeline(SearchLength, &[WEIGHTS_FORMAT]),
        r.pass.blend.pipeline((), &[*format]),
        r.pass.edges.group(),
        r.pass.weights.group(),
        r.pass.blend.group(),
    )
    else {
        return;
    };
    let [hdr, prepared, edges, mask, weights] = views;
    r.pass
        .preparation
        .record(encoder, timer, "smaa prepare", prepared);
    // Pixels without an edge are discarded and stay 0 in both images; the coverage step
    // shades only the pixels the edge step marked.
    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
    draw_fullscreen_pass(
        encoder,
        timer,
        &FullscreenDraw {
            name: "smaa edges",
            targets: &[edges],
            load: clear,
            depth: Some((mask, wgpu::LoadOp::Clear(0.0))),
            pipeline: edges_pipeline,
            groups: &[edges_group],
        },
    );
    draw_fullscreen_pass(
        encoder,
        timer,
        &FullscreenDraw {
            name: "smaa weights",
            targets: &[weights],
            load: clear,
            depth: Some((mask, wgpu::LoadOp::Load)),
            pipeline: weights_pipeline,
            groups: &[weights_group],
        },
    );
    // Pixels no coverage reaches are discarded and keep the HDR target's exact value.
    draw_fullscreen_with(
        encoder,
        timer,
        PassId::Smaa.name(),
        &[hdr],
        blend,
        blend_group,
        wgpu::LoadOp::Load,
    );
}

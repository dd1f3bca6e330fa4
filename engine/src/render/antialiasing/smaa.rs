//! SMAA 1x (`--aa smaa`; Jimenez, Echevarria, Sousa & Gutierrez 2012, "SMAA: Enhanced
//! Subpixel Morphological Antialiasing", after Reshetov 2009's morphological AA), on one
//! frame, in four steps:
//! 1. the HDR image is copied with its perceptual luma ([`super::prepare`]);
//! 2. `smaa_edges.wgsl` marks each pixel's left and top edges where the perceptual luma
//!    steps ([`crate::antialiasing::smaa_edge`]);
//! 3. `smaa_weights.wgsl`, on edge pixels only (depth-tested against a mask the edge step
//!    writes, so that no other pixel is shaded), follows each edge to both ends (up to
//!    [`MAX_SEARCH`] pixels each way), reads the crossing edges there, and evaluates the
//!    coverage of the revectorized silhouette ([`crate::antialiasing::smaa_coverage`]);
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
use crate::render::antialiasing::prepare::{AA_PREPARED, MASK, Preparation};
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::HDR;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot, TargetFormat};
use crate::render::pipelines::{
    FullscreenDraw, MaskDepth, PerFormat, draw_fullscreen_pass, draw_fullscreen_with,
    fullscreen_masked_variant, mask_depth_state, one_group_layout,
};
use crate::render::shaders::ShaderDef;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Subpixel morphological anti-aliasing.
    pub const Smaa: PassId = PassId::new("smaa");
}

/// Farthest an edge is followed each way, in pixels: SMAA's high preset reaches 32
/// pixels. A longer segment is treated as ending there without a step, which leaves its
/// middle unblended, as a straight edge should be.
pub const MAX_SEARCH: u32 = 32;

/// The coverage step's header constants: `MAX_SEARCH`.
pub const WEIGHTS_DEFS: &[ShaderDef] = &[ShaderDef::U32("MAX_SEARCH", MAX_SEARCH)];

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

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_smaa.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        smaa_pass.into_configs()
    }
}

/// The edge step's input.
pub const EDGES_BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "smaa edges",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("prepared", Binding::TextureLoad)],
};

/// The coverage step's input.
pub const WEIGHTS_BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "smaa weights",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("edges", Binding::TextureLoad)],
};

/// The blend's inputs.
pub const BLEND_BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "smaa blend",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("prepared", Binding::TextureLoad),
        ("weights", Binding::TextureLoad),
    ],
};

/// The edges found from luma.
pub const SMAA_EDGES: Slot = Slot::target("smaa edges", TargetFormat::Fixed(EDGES_FORMAT));

/// Depth 1 on the pixels with an edge, 0 elsewhere.
pub const SMAA_MASK: Slot = Slot::texture("smaa mask", MASK);

/// The coverages the blend mixes each edge pixel with.
pub const SMAA_WEIGHTS: Slot = Slot::target("smaa weights", TargetFormat::Fixed(WEIGHTS_FORMAT));

/// SMAA's pipelines and images.
#[derive(Resource)]
pub struct SmaaPass {
    preparation: Preparation,
    edges_layout: wgpu::BindGroupLayout,
    weights_layout: wgpu::BindGroupLayout,
    blend_layout: wgpu::BindGroupLayout,
    edges: wgpu::RenderPipeline,
    weights: wgpu::RenderPipeline,
    blends: PerFormat,
    /// The edge, coverage and blend steps' groups.
    groups: [CachedGroup; 3],
}

impl SmaaPass {
    /// Compiles the preparation, edge and coverage steps; the blend compiles per HDR
    /// format.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let edges_layout = EDGES_BINDINGS.layout(gpu);
        let weights_layout = WEIGHTS_BINDINGS.layout(gpu);
        let blend_layout = BLEND_BINDINGS.layout(gpu);
        // The edge step writes the mask (depth 1 on edge pixels); the coverage step is
        // tested against it and shades only those.
        let step = |label: &str, layout, source, format, depth| {
            fullscreen_masked_variant(
                gpu,
                label,
                &one_group_layout(gpu, label, layout),
                source,
                format,
                depth,
            )
        };
        Ok(SmaaPass {
            preparation: Preparation::new(gpu)?,
            edges: step(
                "smaa edges",
                &edges_layout,
                ("smaa_edges.wgsl", &[]),
                EDGES_FORMAT,
                mask_depth_state(MaskDepth::Mark),
            )?,
            weights: step(
                "smaa weights",
                &weights_layout,
                ("smaa_weights.wgsl", WEIGHTS_DEFS),
                WEIGHTS_FORMAT,
                mask_depth_state(MaskDepth::Test),
            )?,
            blends: PerFormat::new(gpu, "smaa blend", "smaa_blend.wgsl", &blend_layout),
            edges_layout,
            weights_layout,
            blend_layout,
            groups: Default::default(),
        })
    }
}
/// Compiles the blend for this frame's HDR format and (re)creates the images at the
/// frame's size.
pub fn prepare_smaa(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<SmaaPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(&format) = plan.variant::<SmaaPass>() else {
        return;
    };
    let pass = &mut *pass;
    if let Err(e) = pass.blends.ensure(&gpu, format) {
        errors.0.push(e);
        return;
    }
    let Some([hdr, prepared, edges, weights]) = targets
        .current
        .as_ref()
        .and_then(|t| t.views([HDR, AA_PREPARED, SMAA_EDGES, SMAA_WEIGHTS]))
    else {
        return;
    };
    let view = wgpu::BindingResource::TextureView;
    let [edges_group, weights_group, blend_group] = &mut pass.groups;
    let made = pass
        .preparation
        .prepare(&gpu, hdr)
        .and_then(|()| {
            edges_group
                .get(
                    &gpu,
                    &EDGES_BINDINGS,
                    &pass.edges_layout,
                    vec![view(prepared)],
                )
                .map(|_| ())
        })
        .and_then(|()| {
            weights_group
                .get(
                    &gpu,
                    &WEIGHTS_BINDINGS,
                    &pass.weights_layout,
                    vec![view(edges)],
                )
                .map(|_| ())
        })
        .and_then(|()| {
            blend_group
                .get(
                    &gpu,
                    &BLEND_BINDINGS,
                    &pass.blend_layout,
                    vec![view(prepared), view(weights)],
                )
                .map(|_| ())
        });
    if let Err(e) = made {
        errors.0.push(e);
    }
}

/// Records the four steps.
pub fn smaa_pass(
    pass: Res<SmaaPass>,
    plan: Res<FramePlan>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let [edges_group, weights_group, blend_group] = &pass.groups;
    let (Some(encoder), Some(views), Some(blend)) = (
        encoder.as_mut(),
        targets
            .current
            .as_ref()
            .and_then(|t| t.views([HDR, AA_PREPARED, SMAA_EDGES, SMAA_MASK, SMAA_WEIGHTS])),
        plan.variant::<SmaaPass>().and_then(|f| pass.blends.get(*f)),
    ) else {
        return;
    };
    let (Some(edges_group), Some(weights_group), Some(blend_group)) = (
        edges_group.group(),
        weights_group.group(),
        blend_group.group(),
    ) else {
        return;
    };
    let [hdr, prepared, edges, mask, weights] = views;
    pass.preparation
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
            pipeline: &pass.edges,
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
            pipeline: &pass.weights,
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

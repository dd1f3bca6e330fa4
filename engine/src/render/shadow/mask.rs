//! Screen-space shadow mask (`shaders/shadow_mask.wgsl`): the visibility of each shadowed
//! directional light, filtered from the shadow atlas once per mask texel in its own pass,
//! at full resolution or at half (one texel per 2 × 2 pixels). The lighting pass then
//! reads one value per light instead of running the shadow filter in its light loop; at
//! half resolution it upsamples with depth-aware weights
//! ([`crate::shading::shadow_kernel::shadow_mask_weight`]).
//!
//! It runs when [`crate::quality::Quality::shadow_mask`] is not `off`, the frame has a
//! shadowed directional light, no more of them than the mask has channels
//! ([`MASK_LIGHTS`]), and something is drawn. Point and spot lights keep their lookups in
//! the light loop, as do the transparent and layer passes, and probe captures.

use crate::choice::Choice;
use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs;
use crate::quality::{Quality, ShadowMask};
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::LIGHT_TILES;
use crate::render::graph::slots::SHADOW_ATLAS;
use crate::render::graph::slots::{DEPTH, GBUFFER_BASE_COLOR, GBUFFER_NORMAL};
use crate::render::graph::{
    Fact, FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, FullscreenPipelines, ShaderVariant};
use crate::render::pipelines::{MaskDepth, mask_depth_state};
use crate::render::scaled_output;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::shadow::atlas::ShadowAtlas;
use crate::render::shadow::lookups::{
    LIGHTS_AND_SHADOWS, lights_and_shadows, lookup_defs, views_fit_uniform,
};
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The shadowed directional lights' visibility, once per mask texel.
    pub const ShadowMask: PassId = PassId::new("shadow mask");
}

/// The shadowed directional lights one mask holds, one per colour channel (`a` holds the
/// view depth).
pub const MASK_LIGHTS: u32 = 3;

/// Format of the mask: visibility (0..1) of shadowed directional lights 0 to 2, and the
/// view depth (m) of the pixel each texel was shaded at (16-bit floats: 0.05 % of the
/// depth, well inside the upsample's 5 % tolerance).
pub const MASK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The shadow mask, one texel per `scale` × `scale` pixels (⌈width/scale⌉ ×
/// ⌈height/scale⌉; 1×1 while the pass does not run).
pub const SHADOW_MASK: Slot = Slot::texture("shadow mask", scaled_output::scaled(MASK_FORMAT));

/// The depth of each mask texel's pixel, which the lookups are depth-tested against.
pub const SHADOW_MASK_DEPTH: Slot = Slot::texture("shadow mask depth", scaled_output::DEPTH_COPY);

/// The shape of the mask the lighting pass upsamples, while the mask pass runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaskShape {
    /// Pixels per mask texel along each axis.
    pub scale: u32,
    /// The shadowed directional lights it holds.
    pub lights: u32,
}

/// The mask the lighting pass reads this frame: `None` while the mask pass does not run.
pub const MASK: Fact<Option<MaskShape>> = Fact::new("shadow mask");

/// Group 0: the view, depth and the G-buffer channels the lookups need (the normal, and
/// whether the surface receives shadows); group 1 is the lighting pass's
/// [`LIGHTS_AND_SHADOWS`].
pub const VIEW_AND_GBUFFER: BindGroupSpec =
    BindGroupSpec::fragment("shadow mask: view and G-buffer", declared::SHADOW_MASK_0);

/// Why the mask pass does not run this frame, if it does not.
pub fn skip_reason(mask: ShadowMask, frame: &ExtractedFrame) -> Option<String> {
    let directional = frame.shadowed_counts[0];
    if mask == ShadowMask::Off {
        Some(format!(
            "off ({}): the light loop filters the shadow map",
            knobs::SHADOW_MASK.setting(Value::Name("off"))
        ))
    } else if frame.instances.is_empty() {
        Some("nothing is drawn".into())
    } else if frame.shadow_views.is_empty() || directional == 0 {
        Some("no shadowed directional light".into())
    } else if directional > MASK_LIGHTS {
        Some(format!(
            "{directional} shadowed directional lights, more than the mask's {MASK_LIGHTS}: the light loop filters them"
        ))
    } else {
        None
    }
}

/// The mask pass's variant: the lighting pass's (its shadow filter and light copies) and
/// the mask's scale.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaskVariant {
    /// Pixels per mask texel along each axis (1 or 2).
    pub scale: u32,
    /// The shadowed directional lights it holds (1 to [`MASK_LIGHTS`]): a shader
    /// constant, so the loop over them unrolls.
    pub lights: u32,
    /// The shadow filter.
    pub filter: crate::quality::ShadowFilter,
    /// Every light fits the uniform copy of the light array.
    pub uniform_lights: bool,
    /// Every shadow view fits the uniform copy of the view array.
    pub uniform_shadow_views: bool,
    /// Lights the uniform copy of the light array holds.
    pub uniform_capacity: u32,
}

impl ShaderVariant for MaskVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        let mut defs = vec![
            ShaderDef::U32("SHADOW_MASK_SCALE", self.scale),
            ShaderDef::U32("SHADOW_MASK_LIGHTS", self.lights),
        ];
        defs.extend(lookup_defs(
            self.filter,
            self.uniform_lights,
            self.uniform_shadow_views,
            self.uniform_capacity,
        ));
        defs
    }
}

impl FramePass for ShadowMaskPass {
    const ID: PassId = PassId::ShadowMask;
    const READS: &'static [Slot] = &[
        DEPTH,
        GBUFFER_BASE_COLOR,
        GBUFFER_NORMAL,
        SHADOW_ATLAS,
        LIGHT_TILES,
    ];
    const WRITES: &'static [Slot] = &[SHADOW_MASK, SHADOW_MASK_DEPTH];
    const PUBLISHES: &'static [FactId] = &[MASK.id];
    type Variant = MaskVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(ShadowMaskPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<MaskVariant> {
        let quality = world.resource::<Quality>();
        let frame = world.resource::<ExtractedFrame>();
        let buffers = world.resource::<SceneBuffers>();
        let variant = MaskVariant {
            scale: quality.shadow_mask.scale().max(1),
            lights: frame.shadowed_counts[0].clamp(1, MASK_LIGHTS),
            filter: quality.shadow_filter,
            uniform_lights: buffers.lights_fit_uniform(frame),
            uniform_shadow_views: views_fit_uniform(frame),
            uniform_capacity: buffers.uniform_light_capacity,
        };
        let skip = skip_reason(quality.shadow_mask, frame);
        let reason = skip.clone().unwrap_or_else(|| {
            format!(
                "{} shadowed directional light(s) at {} resolution, {} filter",
                frame.shadowed_counts[0],
                quality.shadow_mask.name(),
                quality.shadow_filter.name()
            )
        });
        let runs = skip.is_none();
        let shape = runs.then_some(MaskShape {
            scale: variant.scale,
            lights: variant.lights,
        });
        PassDecision::new(runs, reason, variant)
            .sized(SHADOW_MASK, scaled_output::sizing(runs, variant.scale))
            .sized(
                SHADOW_MASK_DEPTH,
                scaled_output::sizing(runs, variant.scale),
            )
            .publishing(&MASK, shape)
    }

    crate::pass_systems!(prepare_shadow_mask, shadow_mask_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        crate::quality::ShadowFilter::ALL
            .iter()
            .zip(
                [(1, 1, false), (2, 3, true), (1, 2, true), (2, 1, false)]
                    .iter()
                    .cycle(),
            )
            .map(|(&filter, &(scale, lights, uniform))| {
                let variant = MaskVariant {
                    scale,
                    lights,
                    filter,
                    uniform_lights: uniform,
                    uniform_shadow_views: uniform,
                    uniform_capacity: 8,
                };
                ShaderBuild::new(
                    "shadow_mask.wgsl",
                    variant.shader_defs(),
                    &[(0, VIEW_AND_GBUFFER), (1, LIGHTS_AND_SHADOWS)],
                )
            })
            .collect()
    }
}

/// The depth test that keeps the lookups off the background: the mask's texels are
/// shaded only where the depth at their pixel holds geometry (reversed Z: the full-screen
/// triangle at depth 0 passes `Less` where the stored depth is above 0).
fn depth_test() -> wgpu::DepthStencilState {
    mask_depth_state(MaskDepth::Test)
}

/// The mask pass's steps (per variant: the depth copy at mask resolution, and the mask
/// itself) and its bind groups.
#[derive(Resource)]
pub struct ShadowMaskPass {
    /// The depth copy, which owns group 0 ([`VIEW_AND_GBUFFER`]).
    depth: FullscreenStep<MaskVariant>,
    /// The lookups, over the same groups.
    mask: FullscreenPipelines<MaskVariant>,
    /// Group 1's layout and group.
    lights_layout: wgpu::BindGroupLayout,
    lights: CachedGroup,
}

impl ShadowMaskPass {
    /// Creates the layouts; pipelines compile per variant on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let lights_layout = LIGHTS_AND_SHADOWS.layout(gpu);
        let depth = FullscreenStep::with_groups(
            gpu,
            Fullscreen::new("shadow mask depth", "shadow_mask.wgsl")
                .entry("fs_depth")
                .depth(mask_depth_state(MaskDepth::Mark)),
            &VIEW_AND_GBUFFER,
            &[&lights_layout],
        );
        let mask = FullscreenPipelines::new(
            gpu,
            Fullscreen::new("shadow mask", "shadow_mask.wgsl").depth(depth_test()),
            &[depth.layout(), &lights_layout],
        );
        ShadowMaskPass {
            depth,
            mask,
            lights_layout,
            lights: CachedGroup::default(),
        }
    }
}

/// Compiles the variant and builds the bind groups.
pub fn prepare_shadow_mask(
    mut p: Prepare<ShadowMaskPass>,
    buffers: Res<SceneBuffers>,
    atlas: Res<ShadowAtlas>,
) -> Result<()> {
    let (Some(&variant), Some(t)) = (
        p.plan.variant::<ShadowMaskPass>(),
        p.targets.current.as_ref(),
    ) else {
        return Ok(());
    };
    (p.pass.depth.ensure(&p.gpu, variant, &[])).and_then(|()| {
        p.pass
            .mask
            .ensure(&p.gpu, variant, &[MASK_FORMAT])
            .map(|_| ())
    })?;
    let (Some([depth, base_color, normal]), Some(tiles)) = (
        t.views([DEPTH, GBUFFER_BASE_COLOR, GBUFFER_NORMAL]),
        t.buffer(LIGHT_TILES),
    ) else {
        return Ok(());
    };
    use wgpu::BindingResource::TextureView;
    let ShadowMaskPass {
        depth: depth_step,
        lights_layout,
        lights,
        ..
    } = &mut *p.pass;
    depth_step
        .bind(
            &p.gpu,
            vec![
                buffers.view.as_entire_binding(),
                TextureView(depth),
                TextureView(base_color),
                TextureView(normal),
            ],
        )
        .and_then(|()| {
            lights
                .get(
                    &p.gpu,
                    &LIGHTS_AND_SHADOWS,
                    lights_layout,
                    lights_and_shadows(&buffers, &atlas, tiles),
                )
                .map(|_| ())
        })
}

/// Records the mask: the depth of each texel's pixel, then the lookups, depth-tested
/// against it.
pub fn shadow_mask_pass(mut r: Record<ShadowMaskPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(g0), Some(g1), Some([output, depth])) = (
        encoder.as_mut(),
        r.pass.depth.group(),
        r.pass.lights.group(),
        r.targets
            .current
            .as_ref()
            .and_then(|t| t.views([SHADOW_MASK, SHADOW_MASK_DEPTH])),
    ) else {
        return;
    };
    let Some(&variant) = r.plan.variant::<ShadowMaskPass>() else {
        return;
    };
    let (Some(depth_pipeline), Some(mask_pipeline)) = (
        r.pass.depth.pipeline(variant, &[]),
        r.pass.mask.get(variant, &[MASK_FORMAT]),
    ) else {
        return;
    };
    // The background keeps (1, 1, 1, −1): lit, no depth.
    let background = wgpu::Color {
        r: 1.0,
        g: 1.0,
        b: 1.0,
        a: -1.0,
    };
    scaled_output::record(
        encoder,
        timer,
        ["shadow mask depth", "shadow mask"],
        output,
        depth,
        [depth_pipeline, mask_pipeline],
        &[g0, g1],
        background,
    );
}

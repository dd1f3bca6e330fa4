//! The lighting stage: the passes that shade the G-buffer and draw what it does not
//! hold. Point and spot lights are binned per screen tile first ([`light_culling`]);
//! this module is the deferred lighting pass; [`layers`] draws the layered materials
//! forward over it (lighting some bases again; what forward passes share is
//! [`forward`]), [`sky`] the background, and
//! [`lobe_tables`] holds the lobes' tables on the GPU.
//!
//! The deferred lighting pass reads the G-buffer and depth, evaluates Cook-Torrance for
//! each light, and writes pre-exposed HDR luminance (`shaders/lighting.wgsl`).
//!
//! The shader is compiled per [`LightingVariant`]: a light kind the scene doesn't have is
//! not compiled in.

pub mod forward;
pub mod layers;
pub mod light_culling;
pub mod lobe_tables;
pub mod sky;

use crate::choice::Choice;
use crate::error::Result;
use crate::quality::{Quality, ShadowFilter};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::AMBIENT_OCCLUSION;
use crate::render::graph::slots::LIGHT_TILES;
use crate::render::graph::slots::SHADOW_ATLAS;
use crate::render::graph::slots::{
    DEPTH, GBUFFER_BASE_COLOR, GBUFFER_EMISSIVE, GBUFFER_NORMAL, HDR,
};
use crate::render::graph::{
    Decision, Fact, FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot,
};
use crate::render::indirect::environment_maps::Ibl;
use crate::render::indirect::gtao::SCREEN_AO;
use crate::render::indirect::light_groups::LightGroups;
use crate::render::indirect::probe_volume::IrradianceVolumeGpu;
use crate::render::indirect::reflection_probes::ReflectionProbesGpu;
use crate::render::indirect::volume_irradiance::{HALF_VOLUME, VOLUME_IRRADIANCE};
use crate::render::lighting::light_culling::LIGHTS_CULLED;
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, ShaderVariant};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::shadow::atlas::ShadowAtlas;
use crate::render::shadow::mask::{MASK, SHADOW_MASK};
use crate::render::targets::{self, RenderTargets};
use crate::shading::brdf::VisibilityModel;
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Full-screen deferred lighting into the HDR target.
    pub const Lighting: PassId = PassId::new("lighting");
}

/// The most shadowed lights of one kind whose count is a shader constant: their loop
/// unrolls and every read of a light or a shadow view in it has a constant index, which
/// on lavapipe makes the sun's lookups in the light loop about half as costly
/// (`docs/src/measured.md`, "Constant shadowed-light counts"). More are counted at run time,
/// so that a scene with many shadowed lights does not compile one copy of the lookup per
/// light.
pub const UNROLLED_SHADOWED_LIGHTS: u32 = 4;

/// The shader constant that stands for "read the count from `view.shadowed_counts`".
pub const SHADOWED_AT_RUN_TIME: u32 = u32::MAX;

/// The shader constant of a kind's shadowed-light count: the count where its lookups are
/// compiled in and it is at most [`UNROLLED_SHADOWED_LIGHTS`], else
/// [`SHADOWED_AT_RUN_TIME`].
pub fn shadowed_count_constant(compiled: bool, count: u32) -> u32 {
    if compiled && count <= UNROLLED_SHADOWED_LIGHTS {
        count
    } else {
        SHADOWED_AT_RUN_TIME
    }
}

/// The shader variant of the lighting pass: which light kinds it loops over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightingVariant {
    /// Directional-light loop compiled in.
    pub directional: bool,
    /// Point-light loop compiled in.
    pub point: bool,
    /// Spot-light loop compiled in.
    pub spot: bool,
    /// Visibility term.
    pub visibility: VisibilityModel,
    /// Shadow lookups compiled in for directional, point and spot lights.
    pub shadows: [bool; 3],
    /// The shadowed lights of each kind as shader constants (`DIRECTIONAL_SHADOWED`,
    /// `POINT_SHADOWED`, `SPOT_SHADOWED`; [`shadowed_count_constant`]).
    pub shadowed_counts: [u32; 3],
    /// Shadow filter.
    pub shadow_filter: ShadowFilter,
    /// Image-based lighting compiled in.
    pub environment: bool,
    /// From an image (else a uniform colour).
    pub env_map: bool,
    /// Multiple-scattering energy compensation compiled in.
    pub energy_compensation: bool,
    /// The AO pass's occlusion applied to environment light.
    pub screen_ao: bool,
    /// Its multiple-bounce fit.
    pub ao_multi_bounce: bool,
    /// Diffuse indirect light from the irradiance volume's probes.
    pub irradiance_volume: bool,
    /// Specular indirect light from reflection probes: the probe slots looked up
    /// ([`ReflectionProbesGpu::slots`]), 0 for none.
    pub reflection_probes: u32,
    /// Unshadowed point and spot lights come from the tile lists of the culling pass.
    pub light_culling: bool,
    /// Every light fits the uniform copy of the light array (read from it, not from the
    /// storage buffer).
    pub uniform_lights: bool,
    /// Every shadow view fits the uniform copy of the view array.
    pub uniform_shadow_views: bool,
    /// Pixels per texel of the shadow mask the shadowed directional lights' visibility
    /// is read from (1 or 2), or 0 where the light loop filters the shadow map itself.
    pub shadow_mask: u32,
    /// The shadowed directional lights the mask holds (1 to 3; 0 without a mask).
    pub shadow_mask_lights: u32,
    /// The irradiance volume's light comes from the half-resolution volume pass
    /// (upsampled), not from a lookup per pixel.
    pub half_volume: bool,
    /// Lights the uniform copy of the light array holds (the device's limit,
    /// [`SceneBuffers::uniform_light_capacity`]).
    pub uniform_capacity: u32,
}

impl LightingVariant {
    /// Every feature compiled in, with the PCSS filter, two reflection probes and the
    /// half-resolution shadow mask: the shader's largest build.
    pub fn everything() -> LightingVariant {
        LightingVariant {
            directional: true,
            point: true,
            spot: true,
            visibility: VisibilityModel::default(),
            shadows: [true; 3],
            shadowed_counts: [2, 1, 1],
            shadow_filter: ShadowFilter::Pcss,
            environment: true,
            env_map: true,
            energy_compensation: true,
            screen_ao: true,
            ao_multi_bounce: true,
            irradiance_volume: true,
            reflection_probes: 2,
            light_culling: true,
            uniform_lights: true,
            uniform_shadow_views: true,
            shadow_mask: 2,
            shadow_mask_lights: 3,
            half_volume: true,
            uniform_capacity: 8,
        }
    }

    /// No light and no indirect term: the build that writes only emission and the
    /// background.
    pub fn nothing() -> LightingVariant {
        LightingVariant {
            directional: false,
            point: false,
            spot: false,
            visibility: VisibilityModel::default(),
            shadows: [false; 3],
            shadowed_counts: [0; 3],
            shadow_filter: ShadowFilter::Hardware2x2,
            environment: false,
            env_map: false,
            energy_compensation: false,
            screen_ao: false,
            ao_multi_bounce: false,
            irradiance_volume: false,
            reflection_probes: 0,
            light_culling: false,
            uniform_lights: false,
            uniform_shadow_views: false,
            shadow_mask: 0,
            shadow_mask_lights: 0,
            half_volume: false,
            uniform_capacity: 1,
        }
    }
}

impl ShaderVariant for LightingVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        let mut defs = vec![
            ShaderDef::Bool("HAS_DIRECTIONAL", self.directional),
            ShaderDef::Bool("HAS_POINT", self.point),
            ShaderDef::Bool("HAS_SPOT", self.spot),
            ShaderDef::U32("VISIBILITY_MODEL", self.visibility as u32),
            ShaderDef::Bool("DIRECTIONAL_SHADOWS", self.shadows[0]),
            ShaderDef::Bool("POINT_SHADOWS", self.shadows[1]),
            ShaderDef::Bool("SPOT_SHADOWS", self.shadows[2]),
            ShaderDef::U32("DIRECTIONAL_SHADOWED", self.shadowed_counts[0]),
            ShaderDef::U32("POINT_SHADOWED", self.shadowed_counts[1]),
            ShaderDef::U32("SPOT_SHADOWED", self.shadowed_counts[2]),
            ShaderDef::Bool("HAS_ENVIRONMENT", self.environment),
            ShaderDef::Bool("ENV_MAP", self.env_map),
            ShaderDef::Bool("ENERGY_COMPENSATION", self.energy_compensation),
            ShaderDef::Bool("SCREEN_AO", self.screen_ao),
            ShaderDef::Bool("AO_MULTI_BOUNCE", self.ao_multi_bounce),
            ShaderDef::Bool("IRRADIANCE_VOLUME", self.irradiance_volume),
            ShaderDef::U32("REFLECTION_PROBE_SLOTS", self.reflection_probes),
            ShaderDef::Bool("LIGHT_CULLING", self.light_culling),
            ShaderDef::Bool("SHEEN_LOBE", false),
            ShaderDef::Bool("RELIT_BASE", false),
            ShaderDef::U32("SHADOW_MASK_SCALE", self.shadow_mask),
            ShaderDef::U32("SHADOW_MASK_LIGHTS", self.shadow_mask_lights),
            ShaderDef::Bool("HALF_VOLUME", self.half_volume),
        ];
        defs.extend(lookup_defs(
            self.shadow_filter,
            self.uniform_lights,
            self.uniform_shadow_views,
            self.uniform_capacity,
        ));
        defs
    }
}

impl FramePass for LightingPass {
    const ID: PassId = PassId::Lighting;
    const CAPTURE: bool = true;
    const READS: &'static [Slot] = &[
        GBUFFER_BASE_COLOR,
        GBUFFER_NORMAL,
        GBUFFER_EMISSIVE,
        DEPTH,
        SHADOW_ATLAS,
        SHADOW_MASK,
        LIGHT_TILES,
        AMBIENT_OCCLUSION,
        VOLUME_IRRADIANCE,
    ];
    const WRITES: &'static [Slot] = &[HDR];
    const CONSULTS: &'static [FactId] = &[MASK.id, SCREEN_AO.id, LIGHTS_CULLED.id, HALF_VOLUME.id];
    const PUBLISHES: &'static [FactId] = &[LIGHTING.id];
    type Variant = LightingVariant;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        let groups = LightGroups::new(gpu);
        let pass = LightingPass::new(gpu, &groups);
        world.insert_resource(groups);
        Ok(pass)
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<LightingVariant> {
        let frame = world.resource::<ExtractedFrame>();
        let quality = world.resource::<Quality>();
        let buffers = world.resource::<SceneBuffers>();
        let instances = frame.instances.len();
        let counts = frame.light_counts;
        let views = frame.shadow_views.len();
        let reason = if instances > 0 {
            format!(
                "shades the G-buffer with {} light(s) and writes the background",
                counts.total()
            )
        } else {
            "writes the background".into()
        };
        let kind = |name: &'static str, n: u32| {
            Decision::new(
                name,
                n > 0 && instances > 0,
                match (n, instances) {
                    (0, _) => "no light of this kind".into(),
                    (_, 0) => "nothing to light".into(),
                    (n, _) => format!("{n} light(s)"),
                },
            )
        };
        let directional = kind("directional lights", counts.directional);
        let point = kind("point lights", counts.point);
        let spot = kind("spot lights", counts.spot);
        let visibility = Decision::new("visibility term", true, quality.visibility.name());
        let (shadow_mask, shadow_mask_lights) = plan
            .fact(&MASK)
            .copied()
            .flatten()
            .map_or((0, 0), |m| (m.scale, m.lights));
        let shadow_lookups = Decision::new(
            "shadow lookups",
            views > 0 && instances > 0,
            match (views, shadow_mask) {
                (0, _) => "no shadow pass".into(),
                (_, 0) => format!("{} filter", quality.shadow_filter.name()),
                (_, scale) => format!(
                    "{} filter; directional lights from the shadow mask (1 texel per {scale}×{scale} pixels)",
                    quality.shadow_filter.name()
                ),
            },
        );
        let env = frame.environment.as_ref();
        let environment = Decision::new(
            "environment lighting",
            env.is_some() && instances > 0,
            match env {
                None => "no environment".to_string(),
                Some(e) if e.image.is_some() => {
                    "image: SH irradiance + GGX-prefiltered cube".into()
                }
                Some(_) => "uniform colour".into(),
            },
        );
        let energy_compensation = Decision::new(
            "energy compensation",
            quality.energy_compensation && instances > 0,
            if quality.energy_compensation {
                "multiple scattering (Kulla-Conty)"
            } else {
                "off: single-scattering GGX"
            },
        );
        let irradiance_volume = volume_decision(world, instances);
        let (reflection_probes, probe_slots) = probes_decision(world, instances);
        let screen_ao = plan.fact(&SCREEN_AO).copied().unwrap_or(false) && environment.enabled;
        let ambient_occlusion = Decision::new(
            "ambient occlusion",
            screen_ao,
            if screen_ao {
                if quality.ao.multi_bounce {
                    "the AO pass's, with the multiple-bounce fit, on environment light"
                } else {
                    "the AO pass's, single bounce, on environment light"
                }
            } else {
                "no AO pass: materials' occlusion only"
            },
        );
        let shadows = [0, 1, 2].map(|k| shadow_lookups.enabled && frame.shadowed_counts[k] > 0);
        let variant = LightingVariant {
            directional: directional.enabled,
            point: point.enabled,
            spot: spot.enabled,
            visibility: quality.visibility,
            shadows,
            shadowed_counts: [0, 1, 2]
                .map(|k| shadowed_count_constant(shadows[k], frame.shadowed_counts[k])),
            shadow_filter: quality.shadow_filter,
            environment: environment.enabled,
            env_map: environment.enabled && env.is_some_and(|e| e.image.is_some()),
            energy_compensation: energy_compensation.enabled,
            screen_ao,
            ao_multi_bounce: screen_ao && quality.ao.multi_bounce,
            irradiance_volume: irradiance_volume.enabled,
            reflection_probes: if reflection_probes.enabled {
                probe_slots
            } else {
                0
            },
            light_culling: plan.fact(&LIGHTS_CULLED).copied().unwrap_or(false),
            uniform_lights: buffers.lights_fit_uniform(frame),
            uniform_shadow_views: views_fit_uniform(frame),
            shadow_mask,
            shadow_mask_lights,
            half_volume: irradiance_volume.enabled
                && plan.fact(&HALF_VOLUME).copied().unwrap_or(false),
            uniform_capacity: buffers.uniform_light_capacity,
        };
        let mut decision = PassDecision::new(true, reason, variant).publishing(&LIGHTING, variant);
        decision.features = vec![
            directional,
            point,
            spot,
            visibility,
            shadow_lookups,
            environment,
            irradiance_volume,
            reflection_probes,
            ambient_occlusion,
            energy_compensation,
        ];
        decision
    }

    crate::pass_systems!(prepare_lighting, lighting_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        [LightingVariant::everything(), LightingVariant::nothing()]
            .map(|variant| {
                ShaderBuild::new("lighting.wgsl", variant.shader_defs(), &GROUPS_BY_INDEX)
            })
            .to_vec()
    }
}

/// Whether the irradiance volume lights the frame's `instances`, and why.
fn volume_decision(world: &World, instances: usize) -> Decision {
    let volume = world.resource::<IrradianceVolumeGpu>();
    Decision::new(
        "irradiance volume",
        volume.grid.is_some() && instances > 0,
        match volume.grid {
            None => volume.skip_reason.clone(),
            Some(g) => format!(
                "{}×{}×{} probes, {} of {} capture passes done",
                g.counts.x, g.counts.y, g.counts.z, volume.completed_passes, g.bounces
            ),
        },
    )
}

/// Whether reflection probes light the frame's `instances`, and why; and the probe slots
/// the shader is compiled for.
fn probes_decision(world: &World, instances: usize) -> (Decision, u32) {
    let reflections = world.resource::<ReflectionProbesGpu>();
    let captured = reflections.captured.iter().flatten().count();
    // Captures do not see the probes' reflections: a probe captured again would
    // otherwise reflect its own previous capture.
    let capture = world.contains_resource::<crate::render::frame::CaptureView>();
    let decision = Decision::new(
        "reflection probes",
        captured > 0 && instances > 0 && !capture,
        if capture {
            "probe capture: the environment only".into()
        } else if reflections.placed.is_empty() {
            reflections.skip_reason.clone()
        } else {
            format!(
                "{} placed, {captured} captured (parallax-corrected boxes)",
                reflections.placed.len()
            )
        },
    );
    (decision, reflections.slots())
}

/// The lighting pass's variant this frame: the layer and transparent passes shade with
/// the same lights, shadows and indirect light.
pub const LIGHTING: Fact<LightingVariant> = Fact::new("lighting variant");

/// The lighting pass's pipelines (one per variant) and bindings.
#[derive(Resource)]
pub struct LightingPass {
    /// Group 0 (the others are the [`LightGroups`]) and the pipelines.
    step: FullscreenStep<LightingVariant>,
    /// Whether the adapter can depth-test against the depth buffer the shader reads
    /// (`READ_ONLY_DEPTH_STENCIL`; GL cannot): background pixels are then rejected
    /// before shading.
    depth_test: bool,
    /// What the pass gathers the shadow mask and the half-resolution volume with: clamped
    /// to the edge, so a pixel on the last row or column reads the last texel twice.
    sampler: wgpu::Sampler,
}

/// Group 0: the view and the G-buffer.
pub const VIEW_AND_GBUFFER: BindGroupSpec =
    BindGroupSpec::fragment("lighting: view and G-buffer", declared::LIGHTING_0);

/// Group 1: the lights, their tile lists and their shadows (defined beside the shadow
/// lookups, and shared with the shadow-mask pass).
pub use crate::render::shadow::lookups::{LIGHTS_AND_SHADOWS, lights_and_shadows};
use crate::render::shadow::lookups::{lookup_defs, views_fit_uniform};

/// Group 2: indirect light (defined beside the environment it binds, and shared with the
/// reflection pass).
pub use crate::render::indirect::environment_maps::ENVIRONMENT;

/// Group 3: the irradiance volume (defined beside it).
pub use crate::render::indirect::probe_volume::PROBES;

/// The lighting pass's bind groups, as (group index, list).
pub const GROUPS_BY_INDEX: [(u32, BindGroupSpec); 4] = [
    (0, VIEW_AND_GBUFFER),
    (1, LIGHTS_AND_SHADOWS),
    (2, ENVIRONMENT),
    (3, PROBES),
];

impl LightingPass {
    /// Creates group 0's layout over the light groups' ([`LightGroups::layouts`]);
    /// pipelines are compiled per variant on first use.
    pub fn new(gpu: &Gpu, groups: &LightGroups) -> Self {
        let depth_test = gpu
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::READ_ONLY_DEPTH_STENCIL);
        let mut step = Fullscreen::new("lighting", "lighting.wgsl");
        if depth_test {
            step = step.depth(wgpu::DepthStencilState {
                format: targets::DEPTH_FORMAT,
                depth_write_enabled: Some(false),
                // The triangle lies at depth 0: it passes where geometry was drawn
                // (reversed Z, background 0), so background pixels are never shaded.
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            });
        }
        let [l1, l2, l3] = &groups.layouts;
        LightingPass {
            step: FullscreenStep::with_groups(gpu, step, &VIEW_AND_GBUFFER, &[l1, l2, l3]),
            depth_test,
            sampler: gpu.sampler("lighting upsample", wgpu::FilterMode::Nearest),
        }
    }
}

/// Everything the lighting pass binds besides its own.
#[derive(SystemParam)]
pub struct LightingInputs<'w> {
    buffers: Res<'w, SceneBuffers>,
    targets: Res<'w, RenderTargets>,
    atlas: Res<'w, ShadowAtlas>,
    ibl: Res<'w, Ibl>,
    volume: Res<'w, IrradianceVolumeGpu>,
    reflections: Res<'w, ReflectionProbesGpu>,
}

/// Compiles this frame's variant if needed, and makes (or keeps) group 0 and the
/// [`LightGroups`].
pub fn prepare_lighting(
    mut p: Prepare<LightingPass>,
    inputs: LightingInputs,
    mut groups: ResMut<LightGroups>,
) -> Result<()> {
    let LightingInputs {
        buffers,
        targets,
        atlas,
        ibl,
        volume,
        reflections,
    } = inputs;
    let (Some(t), Some(&variant)) = (targets.current.as_ref(), p.plan.variant::<LightingPass>())
    else {
        return Ok(());
    };
    let Some([base_color, normal, emissive, depth, mask, volume_half]) = t.views([
        GBUFFER_BASE_COLOR,
        GBUFFER_NORMAL,
        GBUFFER_EMISSIVE,
        DEPTH,
        SHADOW_MASK,
        VOLUME_IRRADIANCE,
    ]) else {
        return Ok(());
    };
    p.pass.step.ensure(&p.gpu, variant, &[t.hdr_format])?;
    use wgpu::BindingResource::{Sampler, TextureView};
    let LightingPass { step, sampler, .. } = &mut *p.pass;
    let group0 = vec![
        buffers.view.as_entire_binding(),
        TextureView(base_color),
        TextureView(normal),
        TextureView(emissive),
        TextureView(depth),
        TextureView(mask),
        Sampler(sampler),
        TextureView(volume_half),
    ];
    step.bind(&p.gpu, group0).and_then(|()| {
        groups
            .prepare(&p.gpu, t, &buffers, &atlas, &ibl, &volume, &reflections)
            .map(|_| ())
    })
}

/// Records the lighting pass: the HDR target is cleared to the pre-exposed background
/// (coverage 0), then a depth-tested full-screen triangle shades only the pixels that
/// hold geometry.
pub fn lighting_pass(
    mut r: Record<LightingPass>,
    groups: Res<LightGroups>,
    frame: Res<ExtractedFrame>,
) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(t), Some(g0), Some([g1, g2, g3])) = (
        r.targets.current.as_ref(),
        r.pass.step.group(),
        groups.groups(),
    ) else {
        return;
    };
    let (Some(encoder), Some([hdr, depth]), Some(pipeline)) = (
        encoder.as_mut(),
        t.views([HDR, DEPTH]),
        r.plan
            .variant::<LightingPass>()
            .and_then(|v| r.pass.step.pipeline(*v, &[t.hdr_format])),
    ) else {
        return;
    };
    let [red, green, blue, _] = frame.view.background;
    let scope = timer.begin_pass(PassId::Lighting);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("lighting"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: f64::from(red),
                        g: f64::from(green),
                        b: f64::from(blue),
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: r.pass.depth_test.then_some(
                wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: None,
                    stencil_ops: None,
                },
            ),
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(pipeline);
        for (i, group) in [g0, g1, g2, g3].into_iter().enumerate() {
            rp.set_bind_group(i as u32, group, &[]);
        }
        rp.draw(0..3, 0..1);
    }
    timer.end_pass(scope);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shadowed_counts_are_constants_up_to_the_unrolled_limit() {
        for count in 0..=UNROLLED_SHADOWED_LIGHTS {
            assert_eq!(shadowed_count_constant(true, count), count);
        }
        assert_eq!(
            shadowed_count_constant(true, UNROLLED_SHADOWED_LIGHTS + 1),
            SHADOWED_AT_RUN_TIME
        );
        // A kind whose lookups are not compiled keeps the view's count, which the slots
        // of the kinds after it are offset by.
        assert_eq!(shadowed_count_constant(false, 2), SHADOWED_AT_RUN_TIME);
        // The shader's sentinel is the same number.
        let source = crate::render::shaders::builtin("surface_light.wgsl").expect("source");
        assert!(source.contains("const SHADOWED_AT_RUN_TIME: u32 = 0xffffffffu;"));
        assert_eq!(SHADOWED_AT_RUN_TIME, 0xffff_ffff);
    }
}

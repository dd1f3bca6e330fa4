//! Deferred lighting pass: reads the G-buffer and depth, evaluates Cook-Torrance for each
//! light, writes pre-exposed HDR luminance (`shaders/lighting.wgsl`).
//!
//! The shader is compiled per [`LightingVariant`]: a light kind the scene doesn't have is
//! not compiled in.

use crate::brdf::VisibilityModel;
use crate::choice::Choice;
use crate::error::Result;
use crate::quality::{Quality, ShadowFilter};
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::{
    DEPTH, GBUFFER_BASE_COLOR, GBUFFER_EMISSIVE, GBUFFER_NORMAL, HDR,
};
use crate::render::graph::{
    Decision, Fact, FactId, FramePass, FramePlan, PassDecision, PassId, Slot,
};
use crate::render::ibl::Ibl;
use crate::render::indirect::ambient_occlusion::{AMBIENT_OCCLUSION, SCREEN_AO};
use crate::render::indirect::irradiance_volume::IrradianceVolumeGpu;
use crate::render::indirect::light_groups::LightGroups;
use crate::render::indirect::reflection_probes::ReflectionProbesGpu;
use crate::render::indirect::volume_irradiance::{HALF_VOLUME, VOLUME_IRRADIANCE};
use crate::render::light_culling::{LIGHT_TILES, LIGHTS_CULLED};
use crate::render::pipelines::{create_module, fullscreen_pipeline};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::{Composed, ShaderDef};
use crate::render::shadow::atlas::ShadowAtlas;
use crate::render::shadow::mask::{MASK, SHADOW_MASK};
use crate::render::shadow::pass::SHADOW_ATLAS;
use crate::render::targets::{self, RenderTargets};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::{ScheduleSystem, SystemParam};
use std::collections::HashMap;

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
        world.insert_resource(LightGroups::new(gpu));
        Ok(LightingPass::new(gpu))
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
        let volume = world.resource::<IrradianceVolumeGpu>();
        let irradiance_volume = Decision::new(
            "irradiance volume",
            volume.grid.is_some() && instances > 0,
            match volume.grid {
                None => volume.skip_reason.clone(),
                Some(g) => format!(
                    "{}×{}×{} probes, {} of {} capture passes done",
                    g.counts.x, g.counts.y, g.counts.z, volume.completed_passes, g.bounces
                ),
            },
        );
        let reflections = world.resource::<ReflectionProbesGpu>();
        let captured = reflections.captured.iter().flatten().count();
        // Captures do not see the probes' reflections: a probe captured again would
        // otherwise reflect its own previous capture.
        let capture = world.contains_resource::<crate::render::frame::CaptureView>();
        let reflection_probes = Decision::new(
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
                reflections.slots()
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

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_lighting.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        lighting_pass.into_configs()
    }
}

/// The lighting pass's variant this frame: the layer and transparent passes shade with
/// the same lights, shadows and indirect light.
pub const LIGHTING: Fact<LightingVariant> = Fact::new("lighting variant");

/// The lighting pass's pipelines (one per variant) and bindings.
#[derive(Resource)]
pub struct LightingPass {
    layouts: [wgpu::BindGroupLayout; 4],
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<(LightingVariant, wgpu::TextureFormat), wgpu::RenderPipeline>,
    /// Whether the adapter can depth-test against the depth buffer the shader reads
    /// (`READ_ONLY_DEPTH_STENCIL`; GL cannot): background pixels are then rejected
    /// before shading.
    depth_test: bool,
    /// Group 0 (the others are the [`LightGroups`]).
    bind_group: CachedGroup,
    /// What the pass gathers the shadow mask and the half-resolution volume with: clamped
    /// to the edge, so a pixel on the last row or column reads the last texel twice.
    sampler: wgpu::Sampler,
}

/// Group 0: the view and the G-buffer.
pub const VIEW_AND_GBUFFER: BindGroupSpec = BindGroupSpec {
    label: "lighting: view and G-buffer",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("view", Binding::Uniform),
        ("gbuffer0", Binding::TextureLoad),
        ("gbuffer1", Binding::TextureLoad),
        ("gbuffer2", Binding::TextureLoad),
        ("depth_buffer", Binding::TextureLoad),
        (
            "shadow_mask",
            Binding::Sampled(wgpu::TextureViewDimension::D2),
        ),
        ("shadow_mask_sampler", Binding::Sampler),
        (
            "volume_half",
            Binding::Sampled(wgpu::TextureViewDimension::D2),
        ),
    ],
};

/// Group 1: the lights, their tile lists and their shadows (defined beside the shadow
/// lookups, and shared with the shadow-mask pass).
pub use crate::render::shadow::lookups::{LIGHTS_AND_SHADOWS, lights_and_shadows};
use crate::render::shadow::lookups::{lookup_defs, views_fit_uniform};

/// Group 2: indirect light (defined beside the environment it binds, and shared with the
/// reflection pass).
pub use crate::render::ibl::ENVIRONMENT;

/// Group 3: the irradiance volume (defined beside it).
pub use crate::render::indirect::irradiance_volume::PROBES;

/// The lighting pass's bind groups, in group order.
pub const GROUPS: [BindGroupSpec; 4] = [VIEW_AND_GBUFFER, LIGHTS_AND_SHADOWS, ENVIRONMENT, PROBES];

impl LightingPass {
    /// Creates the bind group layouts; pipelines are compiled per variant on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layouts = GROUPS.map(|spec| spec.layout(gpu));
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("lighting"),
                bind_group_layouts: &[
                    Some(&layouts[0]),
                    Some(&layouts[1]),
                    Some(&layouts[2]),
                    Some(&layouts[3]),
                ],
                immediate_size: 0,
            });
        LightingPass {
            layouts,
            pipeline_layout,
            pipelines: HashMap::new(),
            depth_test: gpu
                .adapter
                .get_downlevel_capabilities()
                .flags
                .contains(wgpu::DownlevelFlags::READ_ONLY_DEPTH_STENCIL),
            bind_group: CachedGroup::default(),
            sampler: gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("lighting upsample"),
                ..Default::default()
            }),
        }
    }

    /// The shader defs of one variant, for a uniform light copy of `uniform_capacity`
    /// lights.
    pub fn defs(variant: LightingVariant, uniform_capacity: u32) -> Vec<ShaderDef> {
        let mut defs = vec![
            ShaderDef::Bool("HAS_DIRECTIONAL", variant.directional),
            ShaderDef::Bool("HAS_POINT", variant.point),
            ShaderDef::Bool("HAS_SPOT", variant.spot),
            ShaderDef::U32("VISIBILITY_MODEL", variant.visibility as u32),
            ShaderDef::Bool("DIRECTIONAL_SHADOWS", variant.shadows[0]),
            ShaderDef::Bool("POINT_SHADOWS", variant.shadows[1]),
            ShaderDef::Bool("SPOT_SHADOWS", variant.shadows[2]),
            ShaderDef::U32("DIRECTIONAL_SHADOWED", variant.shadowed_counts[0]),
            ShaderDef::U32("POINT_SHADOWED", variant.shadowed_counts[1]),
            ShaderDef::U32("SPOT_SHADOWED", variant.shadowed_counts[2]),
            ShaderDef::Bool("HAS_ENVIRONMENT", variant.environment),
            ShaderDef::Bool("ENV_MAP", variant.env_map),
            ShaderDef::Bool("ENERGY_COMPENSATION", variant.energy_compensation),
            ShaderDef::Bool("SCREEN_AO", variant.screen_ao),
            ShaderDef::Bool("AO_MULTI_BOUNCE", variant.ao_multi_bounce),
            ShaderDef::Bool("IRRADIANCE_VOLUME", variant.irradiance_volume),
            ShaderDef::U32("REFLECTION_PROBE_SLOTS", variant.reflection_probes),
            ShaderDef::Bool("LIGHT_CULLING", variant.light_culling),
            ShaderDef::Bool("SHEEN_LOBE", false),
            ShaderDef::Bool("RELIT_BASE", false),
            ShaderDef::U32("SHADOW_MASK_SCALE", variant.shadow_mask),
            ShaderDef::U32("SHADOW_MASK_LIGHTS", variant.shadow_mask_lights),
            ShaderDef::Bool("HALF_VOLUME", variant.half_volume),
        ];
        defs.extend(lookup_defs(
            variant.shadow_filter,
            variant.uniform_lights,
            variant.uniform_shadow_views,
            uniform_capacity,
        ));
        defs
    }

    /// The WGSL of one variant, for a uniform light copy of `uniform_capacity` lights.
    pub fn source(gpu: &Gpu, variant: LightingVariant, uniform_capacity: u32) -> Result<Composed> {
        gpu.shaders
            .compose("lighting.wgsl", &Self::defs(variant, uniform_capacity))
    }

    fn pipeline(
        &mut self,
        gpu: &Gpu,
        variant: LightingVariant,
        uniform_capacity: u32,
        format: wgpu::TextureFormat,
    ) -> Result<()> {
        if self.pipelines.contains_key(&(variant, format)) {
            return Ok(());
        }
        let module = create_module(
            gpu,
            "lighting",
            &LightingPass::source(gpu, variant, uniform_capacity)?,
        )?;
        let pipeline = fullscreen_pipeline(
            gpu,
            "lighting",
            Some(&self.pipeline_layout),
            &module,
            ("vs_fullscreen", "fs_main"),
            &[format],
            self.depth_test.then_some(wgpu::DepthStencilState {
                format: targets::DEPTH_FORMAT,
                depth_write_enabled: Some(false),
                // The triangle lies at depth 0: it passes where geometry was drawn
                // (reversed Z, background 0), so background pixels are never shaded.
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
        )?;
        self.pipelines.insert((variant, format), pipeline);
        Ok(())
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
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    inputs: LightingInputs,
    mut groups: ResMut<LightGroups>,
    mut pass: ResMut<LightingPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let LightingInputs {
        buffers,
        targets,
        atlas,
        ibl,
        volume,
        reflections,
    } = inputs;
    let (Some(t), Some(&variant)) = (targets.current.as_ref(), plan.variant::<LightingPass>())
    else {
        return;
    };
    let Some([base_color, normal, emissive, depth, mask, volume_half]) = t.views([
        GBUFFER_BASE_COLOR,
        GBUFFER_NORMAL,
        GBUFFER_EMISSIVE,
        DEPTH,
        SHADOW_MASK,
        VOLUME_IRRADIANCE,
    ]) else {
        return;
    };
    if let Err(e) = pass.pipeline(&gpu, variant, buffers.uniform_light_capacity, t.hdr_format) {
        errors.0.push(e);
        return;
    }
    use wgpu::BindingResource::{Sampler, TextureView};
    let LightingPass {
        layouts,
        bind_group,
        sampler,
        ..
    } = &mut *pass;
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
    let made = bind_group
        .get(&gpu, &VIEW_AND_GBUFFER, &layouts[0], group0)
        .map(|_| ())
        .and_then(|()| {
            groups
                .prepare(&gpu, t, &buffers, &atlas, &ibl, &volume, &reflections)
                .map(|_| ())
        });
    if let Err(e) = made {
        errors.0.push(e);
    }
}

/// Records the lighting pass: the HDR target is cleared to the pre-exposed background
/// (coverage 0), then a depth-tested full-screen triangle shades only the pixels that
/// hold geometry.
pub fn lighting_pass(
    plan: Res<FramePlan>,
    pass: Res<LightingPass>,
    groups: Res<LightGroups>,
    frame: Res<ExtractedFrame>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(t), Some(g0), Some([g1, g2, g3])) = (
        targets.current.as_ref(),
        pass.bind_group.group(),
        groups.groups(),
    ) else {
        return;
    };
    let (Some(encoder), Some([hdr, depth]), Some(pipeline)) = (
        encoder.as_mut(),
        t.views([HDR, DEPTH]),
        plan.variant::<LightingPass>()
            .and_then(|v| pass.pipelines.get(&(*v, t.hdr_format))),
    ) else {
        return;
    };
    let [r, g, b, _] = frame.view.background;
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
                        r: f64::from(r),
                        g: f64::from(g),
                        b: f64::from(b),
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: pass.depth_test.then_some(
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

//! Screen-space reflections (`shaders/ssr.wgsl`): what smooth surfaces see of the lit
//! frame, traced over the [depth pyramid](super::depth_pyramid) with rays importance-
//! sampled from the GGX visible normals (Heitz 2018), and written into the HDR target:
//! the lit frame, read from a copy, with the traced reflection in place of the
//! environment's where the rays hit (one bounce: the frame as lighting left it). A ray
//! that misses, points below the surface or leaves the screen keeps the environment's
//! reflection.
//!
//! It runs only when the frame has a surface smoother than the cutoff
//! ([`crate::quality::SsrSettings::max_roughness`]); the reasons are
//! [`crate::render::extract::reflecting::reflections_skip_reason`].

use crate::error::Result;
use crate::quality::Quality;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::extract::reflecting::skip_after_gbuffer;
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::AMBIENT_OCCLUSION;
use crate::render::graph::slots::{
    DEPTH, GBUFFER_BASE_COLOR, GBUFFER_NORMAL, GBUFFER_SPECULAR_LEVEL, HDR,
};
use crate::render::graph::{
    Decision, Extent, FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing,
    Slot, TargetFormat, TextureDesc,
};
use crate::render::indirect::depth_pyramid::{DEPTH_PYRAMID, DEPTH_PYRAMID_LAYOUT};
use crate::render::indirect::gtao::SCREEN_AO;
use crate::render::indirect::light_groups::LightGroups;
use crate::render::indirect::reflection_probes::ReflectionProbesGpu;
use crate::render::lighting::{ENVIRONMENT, PROBES};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{PipelineCache, ShaderVariant};
use crate::render::pipelines::{
    MaskDepth, color_attachment, create_module, depth_attachment, fullscreen_pipeline,
    mask_depth_state, pipeline_layout,
};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::targets::{DEPTH_FORMAT, RenderTargets};
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Screen-space reflections.
    pub const Reflections: PassId = PassId::new("ssr");
}

/// Group 0 of the reflection pass: the view, its parameters, the G-buffer, the pyramid
/// and the copy of the lit frame. Group 1 is the lighting pass's [`crate::render::indirect::environment_maps::ENVIRONMENT`].
pub const SSR: BindGroupSpec = BindGroupSpec::fragment("ssr", declared::SSR_0);

/// Group 2 of the half-resolution composite: the half-resolution trace's hits.
pub const SSR_HALF: BindGroupSpec = BindGroupSpec::fragment("ssr half", declared::SSR_2);

/// Format of the half-resolution hits: their mean light (rgb) and the fraction of rays
/// that hit (a).
pub const HALF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The reflection shader variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SsrVariant {
    /// Rays per pixel.
    pub rays: u32,
    /// Trace iterations per ray.
    pub steps: u32,
    /// An environment to fall back to, from an image (else a uniform colour).
    pub environment: bool,
    /// The environment is an image.
    pub env_map: bool,
    /// The specular weight includes energy compensation, as lighting's does.
    pub energy_compensation: bool,
    /// The AO pass's occlusion enters the specular occlusion, as in lighting.
    pub screen_ao: bool,
    /// Rays that miss fall back to the reflection probes (then the environment): the
    /// probe slots looked up ([`ReflectionProbesGpu::slots`]), 0 for none.
    pub reflection_probes: u32,
    /// The HDR target's format.
    pub format: wgpu::TextureFormat,
    /// Traced at half resolution, then composited.
    pub half: bool,
}

/// `SsrParams` of `ssr.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    max_roughness: f32,
    thickness_m: f32,
    pad: [f32; 2],
}

impl FramePass for SsrPass {
    const ID: PassId = PassId::Reflections;
    const READS: &'static [Slot] = &[
        DEPTH,
        GBUFFER_BASE_COLOR,
        GBUFFER_NORMAL,
        GBUFFER_SPECULAR_LEVEL,
        DEPTH_PYRAMID,
        DEPTH_PYRAMID_LAYOUT,
        AMBIENT_OCCLUSION,
        HDR,
    ];
    const WRITES: &'static [Slot] = &[HDR, SSR_COLOR, SSR_HALF_HITS, SSR_HALF_MASK, SSR_MASK];
    const CONSULTS: &'static [FactId] = &[SCREEN_AO.id];
    type Variant = SsrVariant;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        if !world.contains_resource::<LightGroups>() {
            world.insert_resource(LightGroups::new(gpu));
        }
        Ok(SsrPass::new(gpu, &world.resource::<LightGroups>().layouts))
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<SsrVariant> {
        let quality = world.resource::<Quality>();
        let frame = world.resource::<ExtractedFrame>();
        let ssr = quality.ssr;
        let env = frame.environment.as_ref();
        let variant = SsrVariant {
            rays: ssr.rays.clamp(1, 16),
            steps: ssr.steps.clamp(8, 256),
            environment: env.is_some(),
            env_map: env.is_some_and(|e| e.image.is_some()),
            energy_compensation: quality.energy_compensation,
            screen_ao: plan.fact(&SCREEN_AO).copied().unwrap_or(false),
            reflection_probes: world.resource::<ReflectionProbesGpu>().slots(),
            format: quality.hdr_precision.format(),
            half: ssr.half_resolution,
        };
        // Runs exactly where the G-buffer wrote the level it reads.
        let skip = skip_after_gbuffer(world, plan);
        let reason = skip.clone().unwrap_or_else(|| {
            format!(
                "{} ray(s) per {}, {} steps, roughness ≤ {:.2}, thickness {:.2} m",
                variant.rays,
                if variant.half { "2×2 pixels" } else { "pixel" },
                variant.steps,
                ssr.max_roughness,
                ssr.thickness_m
            )
        });
        let fallback = Decision::new(
            "reflection fallback",
            skip.is_none(),
            match (variant.reflection_probes > 0, variant.environment) {
                (true, _) => "the reflection probes, then the environment, where a ray misses",
                (false, true) => "the environment where a ray misses",
                (false, false) => "no probe or environment: a ray that misses reflects nothing",
            },
        );
        let half = Sizing::Texture(
            if variant.half {
                Extent::HALF
            } else {
                Extent::Fixed(1, 1)
            },
            None,
        );
        let mut decision = PassDecision::new(skip.is_none(), reason, variant)
            .sized(SSR_HALF_HITS, half)
            .sized(SSR_HALF_MASK, half);
        decision.features = vec![fallback];
        decision
    }

    crate::pass_systems!(prepare_ssr, ssr_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        let everything = SsrVariant {
            rays: 2,
            steps: 16,
            environment: true,
            env_map: true,
            energy_compensation: true,
            screen_ao: true,
            reflection_probes: 2,
            format: wgpu::TextureFormat::Rgba16Float,
            half: true,
        };
        let nothing = SsrVariant::SMALLEST;
        vec![
            ShaderBuild::new(
                "ssr.wgsl",
                everything.shader_defs(),
                &[(0, SSR), (1, ENVIRONMENT), (2, SSR_HALF), (3, PROBES)],
            ),
            ShaderBuild::new(
                "ssr.wgsl",
                nothing.shader_defs(),
                &[(0, SSR), (1, ENVIRONMENT), (3, PROBES)],
            ),
        ]
    }
}

/// The lit frame as the trace reads it: a copy of the HDR target, made before the pass
/// writes the reflections into it.
pub const SSR_COLOR: Slot = Slot::target("ssr lit frame", TargetFormat::Hdr);

/// The half-resolution trace's hits (1×1 at full resolution).
pub const SSR_HALF_HITS: Slot = Slot::texture(
    "ssr half",
    TextureDesc::full(TargetFormat::Fixed(HALF_FORMAT)).at(None),
);

/// The blocks the half-resolution trace shades: depth 1 where the block's pixel traces
/// (1×1 at full resolution).
pub const SSR_HALF_MASK: Slot = Slot::texture(
    "ssr half mask",
    TextureDesc::full(TargetFormat::Fixed(DEPTH_FORMAT)).at(None),
);

/// The pixels the last step shades: depth 1 where a pixel traces (full resolution) or
/// its block has a hit (half), 0 elsewhere.
pub const SSR_MASK: Slot = Slot::target("ssr mask", TargetFormat::Fixed(DEPTH_FORMAT));

/// An empty group: group 2 of the steps that do not read the half-resolution hits.
const NO_GROUP: BindGroupSpec = BindGroupSpec {
    label: "ssr: none",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[],
};

/// The reflection pass's pipelines and bind groups (groups 1 and 3 are the
/// [`LightGroups`]' 2 and 3).
#[derive(Resource)]
pub struct SsrPass {
    /// The layouts of groups 0 (its own), 2 (the half-resolution hits) and the empty one.
    layouts: [wgpu::BindGroupLayout; 3],
    /// Groups 0, 1, nothing and 3 (full resolution, half-resolution trace); 0 to 3
    /// (composite).
    pipeline_layouts: [wgpu::PipelineLayout; 2],
    /// Per variant: the full-resolution mark and trace pipelines, or the half-resolution
    /// trace mark, trace, composite mark and composite pipelines.
    pipelines: PipelineCache<SsrVariant, Vec<wgpu::RenderPipeline>>,
    params: wgpu::Buffer,
    /// Group 0, the hits' group and the empty group.
    bind_groups: [CachedGroup; 3],
}

impl SsrPass {
    /// Creates the layouts; pipelines compile per variant on first use.
    /// `light` are the [`LightGroups`]' layouts (groups 1 to 3 of the lighting pass).
    pub fn new(gpu: &Gpu, light: &[wgpu::BindGroupLayout; 3]) -> Self {
        let layouts = [SSR.layout(gpu), SSR_HALF.layout(gpu), NO_GROUP.layout(gpu)];
        let [own, hits, none] = &layouts;
        let [_, environment, probes] = light;
        let pipeline_layouts = [
            [own, environment, none, probes],
            [own, environment, hits, probes],
        ]
        .map(|groups| pipeline_layout(gpu, "ssr", &groups));
        SsrPass {
            layouts,
            pipeline_layouts,
            pipelines: PipelineCache::default(),
            params: gpu.uniform_buffer("ssr params", std::mem::size_of::<Params>() as u64),
            bind_groups: Default::default(),
        }
    }

    fn pipeline(&mut self, gpu: &Gpu, variant: SsrVariant) -> Result<()> {
        let SsrPass {
            pipeline_layouts,
            pipelines,
            ..
        } = self;
        pipelines.ensure(&variant, |defs| {
            compile(gpu, pipeline_layouts, variant, defs)
        })?;
        Ok(())
    }
}

/// The full-resolution mark and trace pipelines of `variant`, or the half-resolution
/// trace mark, trace, composite mark and composite pipelines, from `ssr.wgsl` under
/// `defs`.
fn compile(
    gpu: &Gpu,
    pipeline_layouts: &[wgpu::PipelineLayout; 2],
    variant: SsrVariant,
    defs: &[ShaderDef],
) -> Result<Vec<wgpu::RenderPipeline>> {
    let module = create_module(gpu, "ssr", &gpu.shaders.compose("ssr.wgsl", defs)?)?;
    let pipeline = |layout: usize, entry: &str, formats: &[wgpu::TextureFormat], depth| {
        fullscreen_pipeline(
            gpu,
            entry,
            Some(&pipeline_layouts[layout]),
            &module,
            ("vs_fullscreen", entry),
            formats,
            depth,
        )
    };
    Ok(if variant.half {
        vec![
            pipeline(
                0,
                "fs_mark_trace_half",
                &[],
                Some(mask_depth_state(MaskDepth::Mark)),
            )?,
            pipeline(
                0,
                "fs_trace_half",
                &[HALF_FORMAT],
                Some(mask_depth_state(MaskDepth::Test)),
            )?,
            pipeline(
                1,
                "fs_mark_half",
                &[],
                Some(mask_depth_state(MaskDepth::Mark)),
            )?,
            pipeline(
                1,
                "fs_composite_half",
                &[variant.format],
                Some(mask_depth_state(MaskDepth::Test)),
            )?,
        ]
    } else {
        vec![
            pipeline(
                0,
                "fs_mark_full",
                &[],
                Some(mask_depth_state(MaskDepth::Mark)),
            )?,
            pipeline(
                0,
                "fs_main",
                &[variant.format],
                Some(mask_depth_state(MaskDepth::Test)),
            )?,
        ]
    })
}

impl SsrVariant {
    /// One ray of one step at full resolution, with no indirect term: the shader's
    /// smallest build.
    pub const SMALLEST: SsrVariant = SsrVariant {
        rays: 1,
        steps: 1,
        environment: false,
        env_map: false,
        energy_compensation: false,
        screen_ao: false,
        reflection_probes: 0,
        format: wgpu::TextureFormat::Rgba16Float,
        half: false,
    };
}

impl ShaderVariant for SsrVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![
            ShaderDef::U32("RAYS", self.rays),
            ShaderDef::U32("STEPS", self.steps),
            ShaderDef::Bool("HAS_ENVIRONMENT", self.environment),
            ShaderDef::Bool("ENV_MAP", self.env_map),
            ShaderDef::Bool("ENERGY_COMPENSATION", self.energy_compensation),
            ShaderDef::Bool("SCREEN_AO", self.screen_ao),
            ShaderDef::U32("REFLECTION_PROBE_SLOTS", self.reflection_probes),
        ]
    }
}

/// Everything the reflection pass binds besides its own resources.
#[derive(SystemParam)]
pub struct SsrInputs<'w> {
    quality: Res<'w, Quality>,
    buffers: Res<'w, SceneBuffers>,
    targets: Res<'w, RenderTargets>,
}

/// Compiles the variant, sizes the copy of the lit frame, writes the parameters and
/// builds the bind groups.
pub fn prepare_ssr(mut p: Prepare<SsrPass>, inputs: SsrInputs) -> Result<()> {
    let SsrInputs {
        quality,
        buffers,
        targets,
    } = inputs;
    let (Some(&variant), Some(t)) = (p.plan.variant::<SsrPass>(), targets.current.as_ref()) else {
        return Ok(());
    };
    p.pass.pipeline(&p.gpu, variant)?;
    let ssr = quality.ssr;
    let params = Params {
        max_roughness: ssr.max_roughness.clamp(0.0, 1.0),
        thickness_m: if ssr.thickness_m.is_finite() {
            ssr.thickness_m.max(0.0)
        } else {
            0.0
        },
        pad: [0.0; 2],
    };
    p.gpu
        .queue
        .write_buffer(&p.pass.params, 0, bytemuck::bytes_of(&params));
    let (Some([depth, g0, g1, level, color, half]), Some(pyramid), Some(layout)) = (
        t.views([
            DEPTH,
            GBUFFER_BASE_COLOR,
            GBUFFER_NORMAL,
            GBUFFER_SPECULAR_LEVEL,
            SSR_COLOR,
            SSR_HALF_HITS,
        ]),
        t.buffer(DEPTH_PYRAMID),
        t.buffer(DEPTH_PYRAMID_LAYOUT),
    ) else {
        return Ok(());
    };
    use wgpu::BindingResource::TextureView;
    let SsrPass {
        layouts,
        params,
        bind_groups: [main, hits, none],
        ..
    } = &mut *p.pass;
    main.get(
        &p.gpu,
        &SSR,
        &layouts[0],
        vec![
            buffers.view.as_entire_binding(),
            params.as_entire_binding(),
            TextureView(depth),
            TextureView(g0),
            TextureView(g1),
            TextureView(level),
            pyramid.as_entire_binding(),
            TextureView(color),
            layout.as_entire_binding(),
        ],
    )
    .map(|_| ())
    .and_then(|()| {
        hits.get(&p.gpu, &SSR_HALF, &layouts[1], vec![TextureView(half)])
            .map(|_| ())
    })
    .and_then(|()| {
        none.get(&p.gpu, &NO_GROUP, &layouts[2], Vec::new())
            .map(|_| ())
    })
}

/// One step of the pass: its pipeline, its colour target and how it is loaded, the mask
/// it writes (cleared) or tests (loaded), and its bind groups.
struct Step<'a> {
    pipeline: &'a wgpu::RenderPipeline,
    color: Option<(&'a wgpu::TextureView, wgpu::LoadOp<wgpu::Color>)>,
    mask: Option<(&'a wgpu::TextureView, wgpu::LoadOp<f32>)>,
    groups: [&'a wgpu::BindGroup; 4],
}

/// Records the copy of the lit frame and the steps that write its reflections into the
/// HDR target (no blending: f32 targets are not blendable). At full resolution, the mark
/// of the pixels that trace, then their trace. At half resolution, the mark of the blocks
/// that trace and their trace into the half-size target, then the mark of the pixels that
/// get hits and their composite. The last step shades only the marked pixels, over the lit
/// frame the HDR target already holds.
pub fn ssr_pass(mut r: Record<SsrPass>, light: Res<LightGroups>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let [main, hits, none] = &r.pass.bind_groups;
    let (
        Some(encoder),
        Some(t),
        Some(main),
        Some(hits),
        Some(none),
        Some([_, environment, probes]),
    ) = (
        encoder.as_mut(),
        r.targets.current.as_ref(),
        main.group(),
        hits.group(),
        none.group(),
        light.groups(),
    )
    else {
        return;
    };
    let (Some([hdr, half, mask, half_mask]), Some(pipelines)) = (
        t.views([HDR, SSR_HALF_HITS, SSR_MASK, SSR_HALF_MASK]),
        r.plan
            .variant::<SsrPass>()
            .and_then(|v| r.pass.pipelines.get(v)),
    ) else {
        return;
    };
    t.copy(encoder, HDR, SSR_COLOR);
    let without_hits = [main, environment, none, probes];
    let with_hits = [main, environment, hits, probes];
    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
    let marked = Some((mask, wgpu::LoadOp::Clear(0.0)));
    let tested = Some((mask, wgpu::LoadOp::Load));
    let steps = match pipelines.as_slice() {
        [mark, full] => vec![
            Step {
                pipeline: mark,
                color: None,
                mask: marked,
                groups: without_hits,
            },
            Step {
                pipeline: full,
                color: Some((hdr, wgpu::LoadOp::Load)),
                mask: tested,
                groups: without_hits,
            },
        ],
        [mark_trace, trace, mark, composite] => vec![
            Step {
                pipeline: mark_trace,
                color: None,
                mask: Some((half_mask, wgpu::LoadOp::Clear(0.0))),
                groups: without_hits,
            },
            Step {
                pipeline: trace,
                color: Some((half, clear)),
                mask: Some((half_mask, wgpu::LoadOp::Load)),
                groups: without_hits,
            },
            Step {
                pipeline: mark,
                color: None,
                mask: marked,
                groups: with_hits,
            },
            Step {
                pipeline: composite,
                color: Some((hdr, wgpu::LoadOp::Load)),
                mask: tested,
                groups: with_hits,
            },
        ],
        _ => return,
    };
    let last = steps.len() - 1;
    let scope = timer.begin_pass(PassId::Reflections);
    for (i, step) in steps.into_iter().enumerate() {
        // The r.pass's GPU time: from the start of its first step to the end of its last.
        let writes = timer
            .render_writes(&scope)
            .filter(|_| i == 0 || i == last)
            .map(|w| wgpu::RenderPassTimestampWrites {
                query_set: w.query_set,
                beginning_of_pass_write_index: w.beginning_of_pass_write_index.filter(|_| i == 0),
                end_of_pass_write_index: w.end_of_pass_write_index.filter(|_| i == last),
            });
        // The mark step has no colour target at all (not one that is unset).
        let colors: Vec<_> = step
            .color
            .map(|(view, load)| Some(color_attachment(view, load)))
            .into_iter()
            .collect();
        let mask = step.mask.map(|(view, load)| depth_attachment(view, load));
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ssr"),
            color_attachments: &colors,
            depth_stencil_attachment: mask,
            timestamp_writes: writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(step.pipeline);
        for (index, group) in step.groups.into_iter().enumerate() {
            rp.set_bind_group(index as u32, group, &[]);
        }
        rp.draw(0..3, 0..1);
    }
    timer.end_pass(scope);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        let variant = SsrVariant::SMALLEST;
        let defs = variant.shader_defs();
        crate::assert_wgsl_twin!(Params, "ssr.wgsl", &defs, "SsrParams", [
            max_roughness, thickness_m, pad => "pad0",
        ]);
    }
}

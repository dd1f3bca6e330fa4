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
//! [`reflections_skip_reason`].

use crate::error::Result;
use crate::quality::Quality;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::{
    DEPTH, GBUFFER_BASE_COLOR, GBUFFER_EMISSIVE, GBUFFER_NORMAL, HDR,
};
use crate::render::graph::{Decision, FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::ibl::{ENVIRONMENT, Ibl};
use crate::render::indirect::ambient_occlusion::AMBIENT_OCCLUSION;
use crate::render::indirect::depth_pyramid::{
    DEPTH_PYRAMID, DepthPyramidPass, reflections_skip_reason,
};
use crate::render::indirect::irradiance_volume::{IrradianceVolumeGpu, PROBES, probe_bindings};
use crate::render::indirect::reflection_probes::ReflectionProbesGpu;
use crate::render::pipelines::{
    MaskDepth, color_attachment, create_module, depth_attachment, fullscreen_pipeline,
    mask_depth_state,
};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::targets::{DEPTH_FORMAT, RenderTargets, Target};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::{ScheduleSystem, SystemParam};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Screen-space reflections.
    pub const Reflections: PassId = PassId::new("ssr");
}

/// Group 0 of the reflection pass: the view, its parameters, the G-buffer, the pyramid
/// and the copy of the lit frame. Group 1 is the lighting pass's [`ENVIRONMENT`].
pub const SSR: BindGroupSpec = BindGroupSpec {
    label: "ssr",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("view", Binding::Uniform),
        ("params", Binding::Uniform),
        ("depth_buffer", Binding::TextureLoad),
        ("gbuffer0", Binding::TextureLoad),
        ("gbuffer1", Binding::TextureLoad),
        ("gbuffer2", Binding::TextureLoad),
        ("pyramid", Binding::Storage),
        ("scene_color", Binding::TextureLoad),
        ("pyramid_layout", Binding::Uniform),
    ],
};

/// Group 2 of the half-resolution composite: the half-resolution trace's hits.
pub const SSR_HALF: BindGroupSpec = BindGroupSpec {
    label: "ssr half",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("half_added", Binding::TextureLoad)],
};

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
        GBUFFER_EMISSIVE,
        DEPTH_PYRAMID,
        AMBIENT_OCCLUSION,
        HDR,
    ];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = SsrVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(SsrPass::new(gpu))
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
            screen_ao: plan.runs(PassId::AmbientOcclusion),
            reflection_probes: world.resource::<ReflectionProbesGpu>().slots(),
            format: quality.hdr_precision.format(),
            half: ssr.half_resolution,
        };
        let skip = reflections_skip_reason(world);
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
        PassDecision {
            runs: skip.is_none(),
            reason,
            features: vec![fallback],
            variant,
            writes: Vec::new(),
        }
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_ssr.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        ssr_pass.into_configs()
    }
}

/// The generations of what the bind groups were built from.
type Generations = [u64; 6];

/// An empty group: group 2 of the steps that do not read the half-resolution hits.
const NO_GROUP: BindGroupSpec = BindGroupSpec {
    label: "ssr: none",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[],
};

/// The reflection pass's pipelines, the copy of the lit frame it reads and its bindings.
#[derive(Resource)]
pub struct SsrPass {
    layouts: [wgpu::BindGroupLayout; 5],
    /// Groups 0, 1, nothing and 3 (full resolution, half-resolution trace); 0 to 3
    /// (composite).
    pipeline_layouts: [wgpu::PipelineLayout; 2],
    /// Per variant: the full-resolution mark and trace pipelines, or the half-resolution
    /// trace mark, trace, composite mark and composite pipelines.
    pipelines: HashMap<SsrVariant, Vec<wgpu::RenderPipeline>>,
    params: wgpu::Buffer,
    color: Option<Target>,
    /// The half-resolution trace's hits, at half size.
    half: Option<Target>,
    /// The pixels the last step shades: depth 1 where a pixel traces (full resolution) or
    /// its block has a hit (half), 0 elsewhere; at full size.
    mask: Option<Target>,
    /// The blocks the half-resolution trace shades: depth 1 where the block's pixel
    /// traces; at half size.
    half_mask: Option<Target>,
    bind_groups: Option<(Generations, [wgpu::BindGroup; 5])>,
}

impl SsrPass {
    /// Creates the layouts; pipelines compile per variant on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layouts = [
            SSR.layout(gpu),
            ENVIRONMENT.layout(gpu),
            SSR_HALF.layout(gpu),
            PROBES.layout(gpu),
            NO_GROUP.layout(gpu),
        ];
        let pipeline_layouts = [[0, 1, 4, 3], [0, 1, 2, 3]].map(|groups| {
            let bind_group_layouts: Vec<Option<&wgpu::BindGroupLayout>> =
                groups.iter().map(|&g| Some(&layouts[g])).collect();
            gpu.device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("ssr"),
                    bind_group_layouts: &bind_group_layouts,
                    immediate_size: 0,
                })
        });
        SsrPass {
            layouts,
            pipeline_layouts,
            pipelines: HashMap::new(),
            params: gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("ssr params"),
                    contents: &[0; std::mem::size_of::<Params>()],
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                }),
            color: None,
            half: None,
            mask: None,
            half_mask: None,
            bind_groups: None,
        }
    }

    /// The shader defs of `variant`.
    pub fn defs(variant: SsrVariant) -> Vec<ShaderDef> {
        vec![
            ShaderDef::U32("RAYS", variant.rays),
            ShaderDef::U32("STEPS", variant.steps),
            ShaderDef::Bool("HAS_ENVIRONMENT", variant.environment),
            ShaderDef::Bool("ENV_MAP", variant.env_map),
            ShaderDef::Bool("ENERGY_COMPENSATION", variant.energy_compensation),
            ShaderDef::Bool("SCREEN_AO", variant.screen_ao),
            ShaderDef::U32("REFLECTION_PROBE_SLOTS", variant.reflection_probes),
        ]
    }

    fn pipeline(&mut self, gpu: &Gpu, variant: SsrVariant) -> Result<()> {
        if self.pipelines.contains_key(&variant) {
            return Ok(());
        }
        let module = create_module(
            gpu,
            "ssr",
            &gpu.shaders.compose("ssr.wgsl", &SsrPass::defs(variant))?,
        )?;
        let pipeline = |layout: usize, entry: &str, formats: &[wgpu::TextureFormat], depth| {
            fullscreen_pipeline(
                gpu,
                entry,
                Some(&self.pipeline_layouts[layout]),
                &module,
                ("vs_fullscreen", entry),
                formats,
                depth,
            )
        };
        let pipelines = if variant.half {
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
        };
        self.pipelines.insert(variant, pipelines);
        Ok(())
    }
}

/// Everything the reflection pass binds besides its own resources.
#[derive(SystemParam)]
pub struct SsrInputs<'w> {
    quality: Res<'w, Quality>,
    buffers: Res<'w, SceneBuffers>,
    targets: Res<'w, RenderTargets>,
    ibl: Res<'w, Ibl>,
    pyramid: Res<'w, DepthPyramidPass>,
    volume: Res<'w, IrradianceVolumeGpu>,
    reflections: Res<'w, ReflectionProbesGpu>,
}

/// Compiles the variant, sizes the copy of the lit frame, writes the parameters and
/// builds the bind groups.
pub fn prepare_ssr(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    inputs: SsrInputs,
    mut pass: ResMut<SsrPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let SsrInputs {
        quality,
        buffers,
        targets,
        ibl,
        pyramid,
        volume,
        reflections,
    } = inputs;
    let (Some(&variant), Some(t), Some(p)) = (
        plan.variant::<SsrPass>(),
        targets.current.as_ref(),
        pyramid.pyramid.as_ref(),
    ) else {
        return;
    };
    if let Err(e) = pass.pipeline(&gpu, variant) {
        errors.0.push(e);
        return;
    }
    let size = wgpu::Extent3d {
        width: t.size.0,
        height: t.size.1,
        depth_or_array_layers: 1,
    };
    if pass
        .color
        .as_ref()
        .is_none_or(|c| c.texture.size() != size || c.texture.format() != t.hdr_format)
    {
        pass.color = Some(Target::new(&gpu, "ssr lit frame", t.size, t.hdr_format));
        let half = (t.size.0.div_ceil(2), t.size.1.div_ceil(2));
        pass.half = Some(Target::new(&gpu, "ssr half", half, HALF_FORMAT));
        pass.half_mask = Some(Target::new(&gpu, "ssr half mask", half, DEPTH_FORMAT));
        pass.mask = Some(Target::new(&gpu, "ssr mask", t.size, DEPTH_FORMAT));
        pass.bind_groups = None;
    }
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
    gpu.queue
        .write_buffer(&pass.params, 0, bytemuck::bytes_of(&params));
    let (probe_generations, probe_resources) = probe_bindings(&volume, &reflections);
    let key = [
        t.generation,
        buffers.generation,
        pyramid.generation,
        ibl.generation,
        probe_generations[0],
        probe_generations[1],
    ];
    if pass.bind_groups.as_ref().is_some_and(|(k, _)| *k == key) {
        return;
    }
    let (Some([depth, g0, g1, g2, ao]), Some(color), Some(half)) = (
        t.views([
            DEPTH,
            GBUFFER_BASE_COLOR,
            GBUFFER_NORMAL,
            GBUFFER_EMISSIVE,
            AMBIENT_OCCLUSION,
        ]),
        pass.color.as_ref(),
        pass.half.as_ref(),
    ) else {
        return;
    };
    use wgpu::BindingResource::{Sampler, TextureView};
    let main = SSR.group(
        &gpu,
        &pass.layouts[0],
        vec![
            buffers.view.as_entire_binding(),
            pass.params.as_entire_binding(),
            TextureView(depth),
            TextureView(g0),
            TextureView(g1),
            TextureView(g2),
            p.buffer.as_entire_binding(),
            TextureView(&color.view),
            p.layout.as_entire_binding(),
        ],
    );
    let environment = ENVIRONMENT.group(
        &gpu,
        &pass.layouts[1],
        vec![
            ibl.uniform.as_entire_binding(),
            TextureView(ibl.cube_view()),
            Sampler(&ibl.sampler),
            TextureView(ibl.lut_view()),
            TextureView(ao),
        ],
    );
    let half = SSR_HALF.group(&gpu, &pass.layouts[2], vec![TextureView(&half.view)]);
    let probes = PROBES.group(&gpu, &pass.layouts[3], probe_resources);
    let none = NO_GROUP.group(&gpu, &pass.layouts[4], Vec::new());
    match main.and_then(|m| Ok([m, environment?, half?, probes?, none?])) {
        Ok(groups) => pass.bind_groups = Some((key, groups)),
        Err(e) => errors.0.push(e),
    }
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
pub fn ssr_pass(
    plan: Res<FramePlan>,
    pass: Res<SsrPass>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (
        Some(encoder),
        Some(t),
        Some(color),
        Some(half),
        Some(mask),
        Some(half_mask),
        Some((_, groups)),
    ) = (
        encoder.as_mut(),
        targets.current.as_ref(),
        pass.color.as_ref(),
        pass.half.as_ref(),
        pass.mask.as_ref(),
        pass.half_mask.as_ref(),
        pass.bind_groups.as_ref(),
    )
    else {
        return;
    };
    let (Some(hdr), Some(pipelines)) = (
        t.get(HDR),
        plan.variant::<SsrPass>()
            .and_then(|v| pass.pipelines.get(v)),
    ) else {
        return;
    };
    encoder.copy_texture_to_texture(
        hdr.texture.as_image_copy(),
        color.texture.as_image_copy(),
        hdr.texture.size(),
    );
    let [main, environment, hits, probes, none] = groups;
    let without_hits = [main, environment, none, probes];
    let with_hits = [main, environment, hits, probes];
    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
    let marked = Some((&mask.view, wgpu::LoadOp::Clear(0.0)));
    let tested = Some((&mask.view, wgpu::LoadOp::Load));
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
                color: Some((&hdr.view, wgpu::LoadOp::Load)),
                mask: tested,
                groups: without_hits,
            },
        ],
        [mark_trace, trace, mark, composite] => vec![
            Step {
                pipeline: mark_trace,
                color: None,
                mask: Some((&half_mask.view, wgpu::LoadOp::Clear(0.0))),
                groups: without_hits,
            },
            Step {
                pipeline: trace,
                color: Some((&half.view, clear)),
                mask: Some((&half_mask.view, wgpu::LoadOp::Load)),
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
                color: Some((&hdr.view, wgpu::LoadOp::Load)),
                mask: tested,
                groups: with_hits,
            },
        ],
        _ => return,
    };
    let last = steps.len() - 1;
    let scope = timer.begin_pass(PassId::Reflections);
    for (i, step) in steps.into_iter().enumerate() {
        // The pass's GPU time: from the start of its first step to the end of its last.
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

//! Screen-space ambient occlusion (`shaders/gtao.wgsl`): ground-truth ambient occlusion
//! (GTAO, Jimenez et al. 2016; the formulas in [`crate::shading::ambient_occlusion`]) from the
//! depth buffer and the G-buffer's normals, at half or full resolution, then a
//! depth-aware resolve to the full-resolution [`AMBIENT_OCCLUSION`] target that the
//! lighting pass applies to indirect light only.
//!
//! It runs only when the frame has indirect light to occlude (an environment), something
//! is drawn and [`crate::quality::AoSettings::resolution`] is not `off`.

use crate::choice::Choice;
use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::AO;
use crate::quality::{AoResolution, AoSettings, Quality};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::{AMBIENT_OCCLUSION, AO_FORMAT};
use crate::render::graph::slots::{DEPTH, GBUFFER_NORMAL};
use crate::render::graph::{
    Extent, Fact, FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing, Slot,
    TargetFormat, TextureDesc,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, ShaderVariant};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Screen-space ambient occlusion.
    pub const AmbientOcclusion: PassId = PassId::new("ao");
}

/// Format of the traced AO: visibility and the texel's position relative to the camera
/// (m), which the resolve's plane test reads instead of reconstructing it (16-bit floats:
/// 0.05 % of the distance, well inside the test's 1 % tolerance).
pub const RAW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Whether the AO pass runs this frame: the passes that shade indirect light then apply
/// [`AMBIENT_OCCLUSION`].
pub const SCREEN_AO: Fact<bool> = Fact::new("screen-space AO");

/// The traced AO at the AO resolution (half or full, the decision's), which the resolve
/// reads.
pub const AO_RAW: Slot = Slot::texture(
    "ao raw",
    TextureDesc::full(TargetFormat::Fixed(RAW_FORMAT)).at(None),
);

/// Largest screen radius a slice marches, as a fraction of the target's height: a
/// surface close to the camera would otherwise march across the whole frame.
const MAX_RADIUS_FRACTION: f32 = 1.0;

/// The trace step's bindings: the resolve step's but its input, `raw_ao`, which it writes.
pub const TRACE: BindGroupSpec =
    BindGroupSpec::fragment("ao trace", declared::GTAO_0.split_at(4).0);

/// The resolve step's bindings: the trace step's and its output.
pub const RESOLVE: BindGroupSpec = BindGroupSpec::fragment("ao resolve", declared::GTAO_0);

/// The AO shader variant: the loop counts and the filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AoVariant {
    /// Slices per pixel.
    pub slices: u32,
    /// Depth samples per side of a slice.
    pub steps: u32,
    /// The 4×4 depth-aware filter.
    pub denoise: bool,
}

/// `AoParams` of `gtao.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    radius_m: f32,
    pixels_per_m: f32,
    max_radius_px: f32,
    scale: f32,
}

/// Why the AO pass does not run this frame, if it does not.
pub fn skip_reason(quality: &AoSettings, frame: &ExtractedFrame) -> Option<String> {
    if quality.resolution == AoResolution::Off {
        Some(format!(
            "ambient occlusion is off ({})",
            AO.setting(Value::Name("off"))
        ))
    } else if frame.instances.is_empty() {
        Some("nothing is drawn".into())
    } else if frame.environment.is_none() {
        Some("no indirect light to occlude (no environment)".into())
    } else {
        None
    }
}

impl FramePass for AoPass {
    const ID: PassId = PassId::AmbientOcclusion;
    const READS: &'static [Slot] = &[DEPTH, GBUFFER_NORMAL];
    const WRITES: &'static [Slot] = &[AMBIENT_OCCLUSION, AO_RAW];
    const PUBLISHES: &'static [FactId] = &[SCREEN_AO.id];
    type Variant = AoVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(AoPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<AoVariant> {
        let ao = world.resource::<Quality>().ao;
        let frame = world.resource::<ExtractedFrame>();
        let variant = AoVariant {
            slices: ao.slices.clamp(1, 8),
            steps: ao.steps.clamp(1, 32),
            denoise: ao.denoise,
        };
        let skip = skip_reason(&ao, frame);
        let runs = skip.is_none();
        let reason = skip.unwrap_or_else(|| {
            format!(
                "GTAO at {} resolution, {} slices × {} steps, radius {:.2} m, {}",
                ao.resolution.name(),
                variant.slices,
                variant.steps,
                ao.radius_m,
                if ao.denoise { "denoised" } else { "raw" }
            )
        });
        let scale = ao.resolution.scale().max(1);
        PassDecision::new(runs, reason, variant)
            .sized(AO_RAW, Sizing::Texture(Extent::Divided(scale), None))
            .publishing(&SCREEN_AO, runs)
    }

    crate::pass_systems!(prepare_ao, ao_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        [(2, 3, true), (1, 1, false)]
            .map(|(slices, steps, denoise)| {
                let variant = AoVariant {
                    slices,
                    steps,
                    denoise,
                };
                ShaderBuild::new("gtao.wgsl", variant.shader_defs(), &[(0, RESOLVE)])
            })
            .to_vec()
    }
}

impl ShaderVariant for AoVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![
            ShaderDef::U32("SLICES", self.slices),
            ShaderDef::U32("STEPS", self.steps),
            ShaderDef::Bool("DENOISE", self.denoise),
        ]
    }
}

/// The AO pass's steps and parameters.
#[derive(Resource)]
pub struct AoPass {
    /// Traces the slices at AO resolution.
    trace: FullscreenStep<AoVariant>,
    /// Filters and upsamples into [`AMBIENT_OCCLUSION`].
    resolve: FullscreenStep<AoVariant>,
    params: wgpu::Buffer,
}

impl AoPass {
    /// Creates the layouts; pipelines compile per variant on first use.
    pub fn new(gpu: &Gpu) -> Self {
        AoPass {
            trace: FullscreenStep::new(
                gpu,
                Fullscreen::new("ao trace", "gtao.wgsl").entry("fs_trace"),
                &TRACE,
            ),
            resolve: FullscreenStep::new(
                gpu,
                Fullscreen::new("ao resolve", "gtao.wgsl").entry("fs_resolve"),
                &RESOLVE,
            ),
            params: gpu.uniform_buffer("ao params", std::mem::size_of::<Params>() as u64),
        }
    }
}

/// Compiles the variant, sizes the AO-resolution target, writes the parameters and builds
/// the bind groups.
#[allow(clippy::too_many_arguments)]
pub fn prepare_ao(
    mut p: Prepare<AoPass>,
    quality: Res<Quality>,
    frame: Res<ExtractedFrame>,
    buffers: Res<SceneBuffers>,
) -> Result<()> {
    let (Some(&variant), Some(t), Some(camera)) = (
        p.plan.variant::<AoPass>(),
        p.targets.current.as_ref(),
        frame.camera.as_ref(),
    ) else {
        return Ok(());
    };
    (p.pass.trace.ensure(&p.gpu, variant, &[RAW_FORMAT]))
        .and_then(|()| p.pass.resolve.ensure(&p.gpu, variant, &[AO_FORMAT]))?;
    let scale = quality.ao.resolution.scale().max(1);
    let height = t.size.1 as f32;
    let params = Params {
        radius_m: if quality.ao.radius_m.is_finite() {
            quality.ao.radius_m.max(0.0)
        } else {
            0.0
        },
        pixels_per_m: 0.5 * height * camera.clip_from_view.y_axis.y.abs(),
        max_radius_px: (MAX_RADIUS_FRACTION * height).max(1.0),
        scale: scale as f32,
    };
    p.gpu
        .queue
        .write_buffer(&p.pass.params, 0, bytemuck::bytes_of(&params));
    let Some([depth, normal, raw]) = t.views([DEPTH, GBUFFER_NORMAL, AO_RAW]) else {
        return Ok(());
    };
    use wgpu::BindingResource::TextureView;
    let AoPass {
        trace,
        resolve,
        params,
    } = &mut *p.pass;
    let common = || {
        vec![
            buffers.view.as_entire_binding(),
            params.as_entire_binding(),
            TextureView(depth),
            TextureView(normal),
        ]
    };
    let mut with_raw = common();
    with_raw.push(TextureView(raw));
    (trace.bind(&p.gpu, common())).and_then(|()| resolve.bind(&p.gpu, with_raw))
}

/// Records the trace at AO resolution and the resolve into [`AMBIENT_OCCLUSION`].
pub fn ao_pass(mut r: Record<AoPass>) {
    let (Some(t), Some(&variant)) = (r.targets.current.as_ref(), r.plan.variant::<AoPass>()) else {
        return;
    };
    let Some([out, raw]) = t.views([AMBIENT_OCCLUSION, AO_RAW]) else {
        return;
    };
    let encoder = &mut *r.encoder;
    r.pass
        .trace
        .draw(encoder, "ao trace", (variant, &[RAW_FORMAT]), &[raw]);
    r.pass
        .resolve
        .draw(encoder, "ao resolve", (variant, &[AO_FORMAT]), &[out]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        let variant = AoVariant {
            slices: 1,
            steps: 1,
            denoise: false,
        };
        crate::assert_wgsl_twin!(
            Params,
            "gtao.wgsl",
            &variant.shader_defs(),
            "AoParams",
            [radius_m, pixels_per_m, max_radius_px, scale]
        );
    }
}

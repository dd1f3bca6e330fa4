//! Temporal anti-aliasing (`--aa taa`; Karis 2014, "High Quality Temporal Supersampling";
//! Salvi 2016, "An Excursion in Temporal Supersampling"): every frame is jittered inside
//! the pixel (Halton 2, 3 over [`TAA_JITTER_PERIOD`] frames), and `taa.wgsl` blends this frame
//! with the history of the earlier ones, reprojected by the motion vectors
//! ([`crate::render::graph::slots::MOTION`]), rejected where the surface was not visible then, and clipped to the
//! colour range of this frame's neighbourhood. The history is two colour targets and two
//! depth-and-count targets the pass owns (ping-pong); [`TaaResolve`] writes the result
//! into the HDR target, sharpened if asked.
//!
//! The history is reset (the next frame is a frame without history, at the first jitter
//! position) on a camera cut ([`crate::App::camera_cut`]), a new output size, a change of
//! quality settings, and a change of the scene's make-up (meshes, materials, lights or
//! environment added, removed or edited; moving transforms are what motion vectors are
//! for). [`TaaState`] says why.

use crate::error::Result;
use crate::quality::Quality;
use crate::quality::knob::Value;
use crate::quality::knobs::AA;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::{DEPTH, HDR, MOTION};
use crate::render::graph::{
    Extent, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing, Slot, TargetFormat,
    TextureDesc,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::Fullscreen;
use crate::render::pipelines::draw_fullscreen;
use crate::render::post::antialias::accumulate::mean_format;
use crate::render::post::antialias::resolve::TaaResolve;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Temporal anti-aliasing.
    pub const Taa: PassId = PassId::new("taa");
}

/// The history of earlier frames, ping-ponged: the colour (in the [`mean_format`]) …
pub const TAA_HISTORY: [Slot; 2] = [
    Slot::texture(
        "taa history a",
        TextureDesc::full(TargetFormat::Decided).history(),
    ),
    Slot::texture(
        "taa history b",
        TextureDesc::full(TargetFormat::Decided).history(),
    ),
];

/// … and each pixel's view depth and frame count.
pub const TAA_HISTORY_DEPTH: [Slot; 2] = [
    Slot::texture(
        "taa history depth a",
        TextureDesc::full(TargetFormat::Fixed(DEPTH_FRAMES_FORMAT)).history(),
    ),
    Slot::texture(
        "taa history depth b",
        TextureDesc::full(TargetFormat::Fixed(DEPTH_FRAMES_FORMAT)).history(),
    ),
];

/// Frames the history of a moving pixel averages at most: its weight on each new frame
/// is at least 1/16, so a change shows within a few frames.
pub const TAA_FRAMES: u32 = 16;

/// The length of the jitter sequence (Halton 2, 3), and the frames a still `lumen render`
/// converges: the box average of these jittered frames is `--accumulate 64`'s image.
pub const TAA_JITTER_PERIOD: u32 = 64;

/// Frames the history of a still pixel (moved less than [`TAA_STILL_PX`]) averages at most,
/// with an f32 history: one jitter sequence. A still camera's image after
/// [`TAA_JITTER_PERIOD`] frames is the plain mean of the whole sequence, the box average
/// `--accumulate 64` makes, instead of weighting the latest 16 most; a longer memory would
/// let a shading change under a still camera (a moving object's shadow) trail, held back
/// only by clipping. Once the pixel moves, the count drops to [`TAA_FRAMES`]. An f16
/// history (GL) rounds away updates (x − m)/n below 2⁻¹¹ m, a 3 % change at n = 64, yet
/// it still measured closer to 64 renders with this count than with 16 (FLIP 0.0213
/// against 0.0266 on `aliasing`).
pub const TAA_STILL_FRAMES: u32 = TAA_JITTER_PERIOD;

/// A pixel whose motion is shorter than this (in pixels per frame) is still.
pub const TAA_STILL_PX: f32 = 0.01;

/// γ of the clipping box while a pixel moves (twice this once it is still).
pub const TAA_CLIP_GAMMA: f32 = 1.25;

/// View depth and frame count: f16 holds depths to 65 km at 0.05 % (the disocclusion test
/// allows 5 %) and counts to 2048 exactly (the most is 64), and every adapter renders to it.
const DEPTH_FRAMES_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

/// Where the history stands: frames since its last reset and why it was reset. The app
/// keeps it before each frame ([`crate::App`]); the pass reads it.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct TaaState {
    /// Frames rendered since the last reset (0: this frame has no history); picks the
    /// jitter position.
    pub frame: u32,
    /// Why the history was reset before this frame, if it was.
    pub reset: Option<String>,
    /// The output size of the last frame.
    pub size: Option<(u32, u32)>,
    /// The exposure multiplier of the last frame (the history is pre-exposed with it).
    pub exposure: Option<f32>,
}

impl FramePass for TaaPass {
    const ID: PassId = PassId::Taa;
    const READS: &'static [Slot] = &[HDR, DEPTH, MOTION];
    const WRITES: &'static [Slot] = &[
        HDR,
        TAA_HISTORY[0],
        TAA_HISTORY[1],
        TAA_HISTORY_DEPTH[0],
        TAA_HISTORY_DEPTH[1],
    ];
    type Variant = wgpu::TextureFormat;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        TaaPass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<wgpu::TextureFormat> {
        let quality = world.resource::<Quality>();
        let accumulating = quality.aa.accumulate > 1;
        let taa = quality.aa.temporal();
        let state = world
            .get_resource::<TaaState>()
            .cloned()
            .unwrap_or_default();
        let reason = match (&state.reset, taa) {
            (_, false) if accumulating => {
                "the accumulation of jittered renders already filters every pixel".to_string()
            }
            (_, false) => format!("off (not {})", AA.setting(Value::Name("taa"))),
            (Some(why), true) => format!("history reset ({why}): this frame alone"),
            (None, true) => format!(
                "frame {} since the history's reset, at most {TAA_FRAMES} averaged \
                 ({TAA_STILL_FRAMES} where still)",
                state.frame + 1
            ),
        };
        let color_format = world
            .get_resource::<TaaPass>()
            .map_or(wgpu::TextureFormat::Rgba32Float, |p| p.color_format);
        let f16 = color_format == wgpu::TextureFormat::Rgba16Float;
        let mut reason = reason;
        if taa && f16 {
            reason += "; an f16 history: this adapter cannot render to f32";
        }
        if taa && quality.aa.taa_sharpen > 0.0 {
            reason += &format!("; sharpened {}", quality.aa.taa_sharpen);
        }
        let sizing = Sizing::Texture(Extent::Full, Some(color_format));
        PassDecision::new(taa, reason, quality.hdr_precision.format())
            .sized(TAA_HISTORY[0], sizing)
            .sized(TAA_HISTORY[1], sizing)
    }

    crate::pass_systems!(prepare_taa, taa_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![
            ShaderBuild::new("taa.wgsl", Vec::new(), &[(0, BINDINGS)]),
            ShaderBuild::new(
                "taa_resolve.wgsl",
                Vec::new(),
                &[(0, crate::render::post::antialias::resolve::BINDINGS)],
            ),
        ]
    }
}

/// The TAA step's inputs.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("taa", declared::TAA_0);

/// `TaaParams` of `taa.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct TaaParams {
    previous_clip_from_world: [f32; 16],
    clip_from_world: [f32; 16],
    world_from_clip: [f32; 16],
    settings: [f32; 4],
    still: [f32; 4],
}

/// TAA's pipelines, history and bindings.
#[derive(Resource)]
pub struct TaaPass {
    step: FullscreenStep,
    resolve: TaaResolve,
    /// The colour history's format: f32 where the adapter renders it (a mean over up to
    /// [`TAA_STILL_FRAMES`] frames: f16 would drop updates smaller than its rounding),
    /// f16 otherwise ([`mean_format`]).
    color_format: wgpu::TextureFormat,
    params: wgpu::Buffer,
    /// Per parity (the history this frame writes): the TAA group and the resolve's.
    groups: [[CachedGroup; 2]; 2],
    parity: usize,
}

impl TaaPass {
    /// Compiles the TAA step; the resolve compiles per HDR format.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let color_format = mean_format(gpu);
        let mut step = FullscreenStep::new(gpu, Fullscreen::new("taa", "taa.wgsl"), &BINDINGS);
        step.ensure(gpu, (), &[color_format, DEPTH_FRAMES_FORMAT])?;
        Ok(TaaPass {
            step,
            resolve: TaaResolve::new(gpu),
            color_format,
            params: gpu.uniform_buffer("taa params", std::mem::size_of::<TaaParams>() as u64),
            groups: Default::default(),
            parity: 0,
        })
    }
}

/// (Re)creates the history at the frame's size (a new history is a reset), writes the
/// matrices and settings, and flips which history this frame writes.
#[allow(clippy::too_many_arguments)]
pub fn prepare_taa(
    mut p: Prepare<TaaPass>,
    frame: Res<ExtractedFrame>,
    state: Option<Res<TaaState>>,
    quality: Res<Quality>,
) -> Result<()> {
    let Some(&format) = p.plan.variant::<TaaPass>() else {
        return Ok(());
    };
    let pass = &mut *p.pass;
    pass.resolve.step.ensure(&p.gpu, (), &[format])?;
    let Some(t) = p.targets.current.as_ref() else {
        return Ok(());
    };
    let (Some([hdr, depth, motion]), Some(color), Some(depth_frames)) = (
        t.views([HDR, DEPTH, MOTION]),
        t.views(TAA_HISTORY),
        t.views(TAA_HISTORY_DEPTH),
    ) else {
        return Ok(());
    };
    // A history the graph made anew holds nothing: this frame starts over.
    let fresh = TAA_HISTORY
        .iter()
        .chain(&TAA_HISTORY_DEPTH)
        .any(|s| t.fresh(*s));
    for (write, [taa, resolve]) in pass.groups.iter_mut().enumerate() {
        let read = 1 - write;
        let made = pass
            .step
            .bind_in(
                taa,
                &p.gpu,
                vec![
                    wgpu::BindingResource::TextureView(hdr),
                    wgpu::BindingResource::TextureView(depth),
                    wgpu::BindingResource::TextureView(motion),
                    wgpu::BindingResource::TextureView(color[read]),
                    wgpu::BindingResource::TextureView(depth_frames[read]),
                    pass.params.as_entire_binding(),
                ],
            )
            .map(|_| ())
            .and_then(|()| {
                pass.resolve
                    .group(resolve, &p.gpu, color[write])
                    .map(|_| ())
            });
        made?;
    }
    let state = state.map(|s| s.clone()).unwrap_or_default();
    let valid = !fresh && state.reset.is_none() && state.frame > 0;
    let exposure = frame.camera.as_ref().map_or(1.0, |c| c.exposure);
    let ratio = match state.exposure {
        Some(before) if before > 0.0 && (exposure / before).is_finite() => exposure / before,
        _ => 1.0,
    };
    let temporal = &frame.temporal;
    let params = TaaParams {
        previous_clip_from_world: temporal.previous_clip_from_world.to_cols_array(),
        clip_from_world: temporal.clip_from_world.to_cols_array(),
        world_from_clip: glam::Mat4::from_cols_array_2d(&frame.view.world_from_clip)
            .to_cols_array(),
        settings: [
            if valid { 1.0 } else { 0.0 },
            ratio,
            TAA_FRAMES as f32,
            TAA_CLIP_GAMMA,
        ],
        still: [TAA_STILL_FRAMES as f32, TAA_STILL_PX, 0.0, 0.0],
    };
    p.gpu
        .queue
        .write_buffer(&pass.params, 0, bytemuck::bytes_of(&params));
    pass.resolve.set_sharpen(&p.gpu, quality.aa.taa_sharpen);
    pass.parity = 1 - pass.parity;
    Ok(())
}

/// Records the TAA step into the new history, then the resolve into the HDR target.
pub fn taa_pass(mut r: Record<TaaPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let t = r.targets.current.as_ref();
    let [taa_group, resolve_group] = &r.pass.groups[r.pass.parity];
    let (Some(encoder), Some(hdr), Some(resolve), Some(taa_group), Some(resolve_group)) = (
        encoder.as_mut(),
        t.and_then(|t| t.view(HDR)),
        r.plan
            .variant::<TaaPass>()
            .and_then(|f| r.pass.resolve.step.pipeline((), &[*f])),
        taa_group.group(),
        resolve_group.group(),
    ) else {
        return;
    };
    let (Some(color), Some(depth_frames), Some(taa)) = (
        t.and_then(|t| t.view(TAA_HISTORY[r.pass.parity])),
        t.and_then(|t| t.view(TAA_HISTORY_DEPTH[r.pass.parity])),
        r.pass
            .step
            .pipeline((), &[r.pass.color_format, DEPTH_FRAMES_FORMAT]),
    ) else {
        return;
    };
    draw_fullscreen(
        encoder,
        timer,
        PassId::Taa.name(),
        &[color, depth_frames],
        taa,
        taa_group,
    );
    draw_fullscreen(
        encoder,
        timer,
        "taa resolve",
        &[hdr],
        resolve,
        resolve_group,
    );
}

/// What in the scene changed its make-up since this system last ran (meshes, materials,
/// lights, the environment or the camera's own settings added, removed or edited;
/// transforms are left to motion vectors), or the quality settings: the TAA history
/// cannot be reprojected across such a change.
#[allow(clippy::type_complexity)]
pub fn history_change(
    quality: Res<Quality>,
    made: Query<
        (),
        Or<(
            Changed<crate::scene::Mesh3d>,
            Changed<crate::scene::Material>,
            Changed<crate::scene::MaterialMaps>,
            Changed<crate::scene::DirectionalLight>,
            Changed<crate::scene::PointLight>,
            Changed<crate::scene::SpotLight>,
            Changed<crate::scene::Environment>,
        )>,
    >,
    cameras: Query<(), Changed<crate::scene::Camera>>,
    mut removed: RemovedComponents<crate::scene::Mesh3d>,
) -> Option<&'static str> {
    let removed = removed.read().count() > 0;
    if quality.is_changed() {
        Some("quality settings changed")
    } else if !cameras.is_empty() {
        Some("camera cut (the camera's settings changed)")
    } else if !made.is_empty() || removed {
        Some("the scene changed")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        #[rustfmt::skip]
        crate::assert_wgsl_twin!(TaaParams, "taa.wgsl", &[], "TaaParams", [
            previous_clip_from_world, clip_from_world, world_from_clip, settings, still,
        ]);
    }
}

//! The irradiance volume at half resolution (`shaders/volume_irradiance.wgsl`): the
//! volume's irradiance (DDGI's blend of eight probes, sixteen bilinear samples) looked up
//! once per 2 × 2 pixels, at the top-left pixel of each block, in its own pass. The
//! lighting pass then gathers the four texels around each pixel and weights them as it
//! weights the half-resolution shadow mask (bilinear × a tent in view depth,
//! [`crate::shading::shadow_kernel::shadow_mask_weight`]) times a normal term
//! ([`crate::shading::irradiance_volume::upsample_normal_weight`], so that light does not cross a
//! crease), instead of looking the volume up per pixel; where every weight is 0 it takes
//! the texel nearest in depth among those facing the pixel's way.
//!
//! It runs when [`crate::quality::GiSettings::half_resolution`] is on, the frame has an
//! irradiance volume, and something is drawn. Probe captures, the transparent pass and the
//! layer passes keep their per-pixel lookups.

use crate::error::Result;
use crate::quality::Quality;
use crate::quality::knob::Value;
use crate::quality::knobs::GI_RESOLUTION;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::{DEPTH, GBUFFER_NORMAL};
use crate::render::graph::{
    Fact, FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot,
};
use crate::render::indirect::probe_volume::{IrradianceVolumeGpu, PROBES, probe_bindings};
use crate::render::indirect::reflection_probes::ReflectionProbesGpu;
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipelines::{
    MaskDepth, create_module, fullscreen_pipeline, mask_depth_state, pipeline_layout,
};
use crate::render::scaled_output;
use crate::render::scene_buffers::SceneBuffers;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The irradiance volume's lookups, once per 2 × 2 pixels.
    pub const VolumeIrradiance: PassId = PassId::new("volume irradiance");
}

/// Pixels per texel along each axis.
pub const VOLUME_IRRADIANCE_SCALE: u32 = 2;

/// Format of the pass's output: pre-exposed irradiance (rgb) and the view depth (m) of the
/// pixel each texel was looked up at (16-bit floats, as the HDR target and the shadow
/// mask's depth).
pub const VOLUME_IRRADIANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The irradiance at half resolution (⌈width/2⌉ × ⌈height/2⌉; 1×1 while the pass does
/// not run).
pub const VOLUME_IRRADIANCE: Slot = Slot::texture(
    "volume irradiance",
    scaled_output::scaled(VOLUME_IRRADIANCE_FORMAT),
);

/// The depth of each texel's pixel, which the lookups are depth-tested against.
pub const VOLUME_IRRADIANCE_DEPTH: Slot =
    Slot::texture("volume irradiance depth", scaled_output::DEPTH_COPY);

/// Whether the volume is looked up at half resolution this frame (the lighting pass then
/// upsamples [`VOLUME_IRRADIANCE`]).
pub const HALF_VOLUME: Fact<bool> = Fact::new("half-resolution volume");

/// Group 0: the view, depth and the G-buffer's normals; group 3 is the lighting pass's
/// [`PROBES`], groups 1 and 2 are empty.
pub const VIEW_AND_GBUFFER: BindGroupSpec = BindGroupSpec::fragment(
    "volume irradiance: view and G-buffer",
    declared::VOLUME_IRRADIANCE_0,
);

/// The groups between 0 and the probes' group 3, which the shader does not read.
/// The part of [`PROBES`] the shader declares: the volume's four bindings (its layout
/// binds the whole group, which it shares with the lighting pass).
const PROBES_READ: BindGroupSpec = BindGroupSpec {
    bindings: PROBES.bindings.split_at(4).0,
    ..PROBES
};

const UNUSED: BindGroupSpec = BindGroupSpec {
    label: "volume irradiance: unused",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[],
};

/// Why the pass does not run this frame, if it does not.
pub fn skip_reason(quality: &Quality, frame: &ExtractedFrame, volume: bool) -> Option<String> {
    if !quality.gi.half_resolution {
        Some(format!(
            "full resolution ({}): the lighting pass looks the volume up per pixel",
            GI_RESOLUTION.setting(Value::Bool(false))
        ))
    } else if frame.instances.is_empty() {
        Some("nothing is drawn".into())
    } else if !volume {
        Some("no irradiance volume".into())
    } else {
        None
    }
}

impl FramePass for VolumeIrradiancePass {
    const ID: PassId = PassId::VolumeIrradiance;
    const READS: &'static [Slot] = &[DEPTH, GBUFFER_NORMAL];
    const WRITES: &'static [Slot] = &[VOLUME_IRRADIANCE, VOLUME_IRRADIANCE_DEPTH];
    const PUBLISHES: &'static [FactId] = &[HALF_VOLUME.id];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(VolumeIrradiancePass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        let volume = world.resource::<IrradianceVolumeGpu>().grid.is_some();
        let skip = skip_reason(
            world.resource::<Quality>(),
            world.resource::<ExtractedFrame>(),
            volume,
        );
        let reason = skip
            .clone()
            .unwrap_or_else(|| "one lookup per 2×2 pixels, upsampled by depth and normal".into());
        let runs = skip.is_none();
        let sizing = scaled_output::sizing(runs, VOLUME_IRRADIANCE_SCALE);
        PassDecision::new(runs, reason, ())
            .sized(VOLUME_IRRADIANCE, sizing)
            .sized(VOLUME_IRRADIANCE_DEPTH, sizing)
            .publishing(&HALF_VOLUME, runs)
    }

    crate::pass_systems!(prepare_volume_irradiance, volume_irradiance_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![ShaderBuild::new(
            "volume_irradiance.wgsl",
            Vec::new(),
            &[
                (0, VIEW_AND_GBUFFER),
                (1, UNUSED),
                (2, UNUSED),
                (3, PROBES_READ),
            ],
        )]
    }
}

/// The pass's pipelines, its half-resolution depth and output, and its bind groups.
#[derive(Resource)]
pub struct VolumeIrradiancePass {
    /// The layouts of group 0, of the empty groups 1 and 2, and of group 3.
    layouts: [wgpu::BindGroupLayout; 3],
    pipeline_layout: wgpu::PipelineLayout,
    /// The depth copy at half resolution, then the lookups, depth-tested against it,
    /// compiled the first time the pass runs.
    pipelines: Option<[wgpu::RenderPipeline; 2]>,
    /// Groups 0, 1 (also bound as 2) and 3.
    bind_groups: [CachedGroup; 3],
}

impl VolumeIrradiancePass {
    /// Creates the layouts; the pipelines compile the first time the pass runs.
    pub fn new(gpu: &Gpu) -> Self {
        let layouts = [
            VIEW_AND_GBUFFER.layout(gpu),
            UNUSED.layout(gpu),
            PROBES.layout(gpu),
        ];
        let [own, unused, probes] = &layouts;
        let pipeline_layout =
            pipeline_layout(gpu, "volume irradiance", &[own, unused, unused, probes]);
        VolumeIrradiancePass {
            layouts,
            pipeline_layout,
            pipelines: None,
            bind_groups: Default::default(),
        }
    }

    /// Compiles both pipelines (the pass has one variant), once.
    fn compile(&mut self, gpu: &Gpu) -> Result<()> {
        if self.pipelines.is_some() {
            return Ok(());
        }
        let module = create_module(
            gpu,
            "volume irradiance",
            &gpu.shaders.compose("volume_irradiance.wgsl", &[])?,
        )?;
        let depth = fullscreen_pipeline(
            gpu,
            "volume irradiance depth",
            Some(&self.pipeline_layout),
            &module,
            ("vs_fullscreen", "fs_depth"),
            &[],
            Some(mask_depth_state(MaskDepth::Mark)),
        )?;
        let lookups = fullscreen_pipeline(
            gpu,
            "volume irradiance",
            Some(&self.pipeline_layout),
            &module,
            ("vs_fullscreen", "fs_main"),
            &[VOLUME_IRRADIANCE_FORMAT],
            Some(mask_depth_state(MaskDepth::Test)),
        )?;
        self.pipelines = Some([depth, lookups]);
        Ok(())
    }
}

/// Compiles the pass and builds its bind groups.
pub fn prepare_volume_irradiance(
    mut p: Prepare<VolumeIrradiancePass>,
    buffers: Res<SceneBuffers>,
    volume: Res<IrradianceVolumeGpu>,
    reflections: Res<ReflectionProbesGpu>,
) -> Result<()> {
    let Some(t) = p.targets.current.as_ref() else {
        return Ok(());
    };
    p.pass.compile(&p.gpu)?;
    let Some([depth, normal]) = t.views([DEPTH, GBUFFER_NORMAL]) else {
        return Ok(());
    };
    use wgpu::BindingResource::TextureView;
    let VolumeIrradiancePass {
        layouts,
        bind_groups: [g0, unused, g3],
        ..
    } = &mut *p.pass;
    g0.get(
        &p.gpu,
        &VIEW_AND_GBUFFER,
        &layouts[0],
        vec![
            buffers.view.as_entire_binding(),
            TextureView(depth),
            TextureView(normal),
        ],
    )
    .map(|_| ())
    .and_then(|()| {
        unused
            .get(&p.gpu, &UNUSED, &layouts[1], Vec::new())
            .map(|_| ())
    })
    .and_then(|()| {
        g3.get(
            &p.gpu,
            &PROBES,
            &layouts[2],
            probe_bindings(&volume, &reflections),
        )
        .map(|_| ())
    })
}

/// Records the pass: the depth of each texel's pixel, then the lookups, depth-tested
/// against it.
pub fn volume_irradiance_pass(mut r: Record<VolumeIrradiancePass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let [g0, unused, g3] = &r.pass.bind_groups;
    let (Some(encoder), Some(g0), Some(unused), Some(g3), Some([depth, lookups])) = (
        encoder.as_mut(),
        g0.group(),
        unused.group(),
        g3.group(),
        r.pass.pipelines.as_ref(),
    ) else {
        return;
    };
    let Some([output, depth_copy]) = r
        .targets
        .current
        .as_ref()
        .and_then(|t| t.views([VOLUME_IRRADIANCE, VOLUME_IRRADIANCE_DEPTH]))
    else {
        return;
    };
    // The background keeps (0, 0, 0, −1): no irradiance, no depth.
    let background = wgpu::Color {
        r: 0.0,
        g: 0.0,
        b: 0.0,
        a: -1.0,
    };
    scaled_output::record(
        encoder,
        timer,
        ["volume irradiance depth", "volume irradiance"],
        output,
        depth_copy,
        [depth, lookups],
        &[g0, unused, unused, g3],
        background,
    );
}

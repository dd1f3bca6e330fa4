//! The opaque frame as transmissive surfaces see it (`shaders/frame_mips.wgsl`): after
//! the opaque surfaces are lit and the sky is drawn, the HDR target is copied into an
//! f16 texture of the frame's size and each mip level above is averaged from the one
//! below (2 × 2 texels, bilinear taps at their shared corner). The transparent pass
//! samples it along each transmissive fragment's refracted ray, at a level that grows
//! with the surface's roughness ([`crate::shading::transmission::transmission_lod`]): a rough
//! pane blurs what is behind it, as in Filament's and the Khronos sample renderer's
//! screen-space refraction.
//!
//! It runs only when a transmissive surface is in view; otherwise the transparent pass
//! binds a 1 × 1 black texture in its place. The chain is a graph resource
//! ([`TRANSMISSION_SOURCE`]): the graph may give its memory to another full-size f16
//! texture used at another time of the frame.

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::slots::HDR;
use crate::render::graph::{
    FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot, TargetFormat, TextureDesc,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::Fullscreen;
use crate::render::post::antialias::copy::CopyToHdr;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The opaque frame's mip chain, for refraction.
    pub const TransmissionSource: PassId = PassId::new("transmission source");
}

/// The opaque frame and its mip chain, at the output's size.
pub const TRANSMISSION_SOURCE: Slot = Slot::texture(
    "transmission source",
    TextureDesc::full(TargetFormat::Fixed(FORMAT)).with_mips(),
);

/// The chain's format: f16 renders and filters on every backend, and the frame is
/// pre-exposed, so its range suffices.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// A level's input: the level below and a bilinear sampler.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("frame mips", declared::FRAME_MIPS_0);

/// What the chain is made and read with: trilinear, clamped to the frame's edges.
pub fn sampler(gpu: &Gpu) -> wgpu::Sampler {
    gpu.mipmapped_sampler("frame mips")
}

/// The pass: the copy, the downsampling pipeline, its sampler, and the groups that read
/// each level (level 0's copies the HDR target).
#[derive(Resource)]
pub struct TransmissionSourcePass {
    downsample: FullscreenStep,
    copy: CopyToHdr,
    sampler: wgpu::Sampler,
    copy_group: CachedGroup,
    /// Level `i`'s group reads level `i` (to make level `i + 1`).
    level_groups: Vec<CachedGroup>,
}

impl TransmissionSourcePass {
    /// Compiles the downsampling and the copy into [`FORMAT`].
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let mut downsample = FullscreenStep::new(
            gpu,
            Fullscreen::new("frame mips", "frame_mips.wgsl"),
            &BINDINGS,
        );
        downsample.ensure(gpu, (), &[FORMAT])?;
        let mut copy = CopyToHdr::new(gpu);
        copy.0.ensure(gpu, (), &[FORMAT])?;
        Ok(TransmissionSourcePass {
            downsample,
            copy,
            sampler: sampler(gpu),
            copy_group: CachedGroup::default(),
            level_groups: Vec::new(),
        })
    }
}

impl FramePass for TransmissionSourcePass {
    const ID: PassId = PassId::TransmissionSource;
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[TRANSMISSION_SOURCE];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        TransmissionSourcePass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        let frame = world.resource::<ExtractedFrame>();
        let count = frame
            .transparent_batches()
            .filter(|b| b.transmissive)
            .count();
        if count == 0 {
            PassDecision::new(false, "no transmissive surface in view", ())
        } else {
            PassDecision::new(
                true,
                format!("{count} transmissive surface(s) see the opaque frame, mipmapped"),
                (),
            )
        }
    }

    crate::pass_systems!(prepare_transmission_source, transmission_source_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![
            ShaderBuild::new("frame_mips.wgsl", Vec::new(), &[(0, BINDINGS)]),
            crate::render::post::antialias::copy::build(),
        ]
    }
}

/// Makes (or keeps) the copy's group and each level's.
pub fn prepare_transmission_source(mut p: Prepare<TransmissionSourcePass>) -> Result<()> {
    let (Some(()), Some(t)) = (
        p.plan.variant::<TransmissionSourcePass>(),
        p.targets.current.as_ref(),
    ) else {
        return Ok(());
    };
    let Some(hdr) = t.view(HDR) else {
        return Ok(());
    };
    let levels = t.level_count(TRANSMISSION_SOURCE) as usize;
    let pass = &mut *p.pass;
    pass.level_groups
        .resize_with(levels.saturating_sub(1), CachedGroup::default);
    let mut made = pass
        .copy
        .group(&mut pass.copy_group, &p.gpu, hdr)
        .map(|_| ());
    for (level, group) in pass.level_groups.iter_mut().enumerate() {
        let Some(below) = t.level(TRANSMISSION_SOURCE, level as u32) else {
            continue;
        };
        made = made.and_then(|()| {
            pass.downsample
                .bind_in(
                    group,
                    &p.gpu,
                    vec![
                        wgpu::BindingResource::TextureView(below),
                        wgpu::BindingResource::Sampler(&pass.sampler),
                    ],
                )
                .map(|_| ())
        });
    }
    made
}

/// Copies the HDR target into level 0 and averages each level into the next.
pub fn transmission_source_pass(mut r: Record<TransmissionSourcePass>) {
    let (Some(()), Some(t)) = (
        r.plan.variant::<TransmissionSourcePass>(),
        r.targets.current.as_ref(),
    ) else {
        return;
    };
    let Some(level0) = t.level(TRANSMISSION_SOURCE, 0) else {
        return;
    };
    let name = "transmission source";
    let copy = r.pass.copy.0.pipeline((), &[FORMAT]);
    r.encoder
        .fullscreen(name, &[level0], copy, r.pass.copy_group.group());
    let downsample = r.pass.downsample.pipeline((), &[FORMAT]);
    for (level, group) in r.pass.level_groups.iter().enumerate() {
        if let Some(target) = t.level(TRANSMISSION_SOURCE, level as u32 + 1) {
            r.encoder
                .fullscreen(name, &[target], downsample, group.group());
        }
    }
}

//! The opaque frame as transmissive surfaces see it (`shaders/frame_mips.wgsl`): after
//! the opaque surfaces are lit and the sky is drawn, the HDR target is copied into an
//! f16 texture of the frame's size and each mip level above is averaged from the one
//! below (2 × 2 texels, bilinear taps at their shared corner). The transparent pass
//! samples it along each transmissive fragment's refracted ray, at a level that grows
//! with the surface's roughness ([`crate::transmission::transmission_lod`]): a rough
//! pane blurs what is behind it, as in Filament's and the Khronos sample renderer's
//! screen-space refraction.
//!
//! It runs only when a transmissive surface is in view; otherwise the transparent pass
//! binds a 1 × 1 black texture in its place.

use crate::error::Result;
use crate::render::antialiasing::copy::CopyToHdr;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::HDR;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::{draw_fullscreen, fullscreen_variant, one_group_layout};
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The opaque frame's mip chain, for refraction.
    pub const TransmissionSource: PassId = PassId::new("transmission source");
}

/// The opaque frame and its mip chain, which the pass owns.
pub const TRANSMISSION_SOURCE: Slot = Slot::owned("transmission source");

/// The chain's format: f16 renders and filters on every backend, and the frame is
/// pre-exposed, so its range suffices.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// A level's input: the level below and a bilinear sampler.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "frame mips",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("below", Binding::Sampled(wgpu::TextureViewDimension::D2)),
        ("bilinear", Binding::Sampler),
    ],
};

/// The number of levels of a chain over a frame of `size`: down to 1 × 1.
pub fn level_count(size: (u32, u32)) -> u32 {
    32 - size.0.max(size.1).max(1).leading_zeros()
}

/// The chain at one frame size: the texture, a view of all its levels (what the
/// transparent pass samples), one view per level (the targets) and the groups that read
/// them (level 0's copies the HDR target).
pub struct Chain {
    /// The targets' generation it was made for.
    pub key: u64,
    /// Every level, for sampling.
    pub view: wgpu::TextureView,
    /// Width of level 0 in texels.
    pub width: u32,
    levels: Vec<wgpu::TextureView>,
    copy_group: wgpu::BindGroup,
    groups: Vec<wgpu::BindGroup>,
}

/// The pass: the copy, the downsampling pipeline, its sampler, and the chain.
#[derive(Resource)]
pub struct TransmissionSourcePass {
    layout: wgpu::BindGroupLayout,
    downsample: wgpu::RenderPipeline,
    copy: CopyToHdr,
    sampler: wgpu::Sampler,
    /// The chain, once a frame with a transmissive surface has needed it.
    pub chain: Option<Chain>,
}

impl TransmissionSourcePass {
    /// Compiles the downsampling and the copy into [`FORMAT`].
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let layout = BINDINGS.layout(gpu);
        let downsample = fullscreen_variant(
            gpu,
            "frame mips",
            &one_group_layout(gpu, "frame mips", &layout),
            "frame_mips.wgsl",
            &[],
            FORMAT,
        )?;
        let mut copy = CopyToHdr::new(gpu);
        copy.ensure(gpu, FORMAT)?;
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("frame mips"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Ok(TransmissionSourcePass {
            layout,
            downsample,
            copy,
            sampler,
            chain: None,
        })
    }

    /// The sampler the transparent pass reads the chain with: trilinear, clamped to the
    /// frame's edges.
    pub fn sampler(&self) -> &wgpu::Sampler {
        &self.sampler
    }

    fn make_chain(
        &self,
        gpu: &Gpu,
        key: u64,
        size: (u32, u32),
        hdr: &wgpu::TextureView,
    ) -> Result<Chain> {
        let count = level_count(size);
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("transmission source"),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: count,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let levels: Vec<wgpu::TextureView> = (0..count)
            .map(|level| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("transmission source level"),
                    base_mip_level: level,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let groups = levels[..levels.len() - 1]
            .iter()
            .map(|below| {
                BINDINGS.group(
                    gpu,
                    &self.layout,
                    vec![
                        wgpu::BindingResource::TextureView(below),
                        wgpu::BindingResource::Sampler(&self.sampler),
                    ],
                )
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Chain {
            key,
            view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            width: size.0.max(1),
            copy_group: self.copy.group(gpu, hdr)?,
            levels,
            groups,
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

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_transmission_source.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        transmission_source_pass.into_configs()
    }
}

/// (Re)makes the chain at the frame's size.
pub fn prepare_transmission_source(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<TransmissionSourcePass>,
    mut errors: ResMut<FrameErrors>,
) {
    if plan.variant::<TransmissionSourcePass>().is_none() {
        return;
    }
    let Some((t, hdr)) = targets
        .current
        .as_ref()
        .and_then(|t| Some((t, t.view(HDR)?)))
    else {
        return;
    };
    if pass.chain.as_ref().is_some_and(|c| c.key == t.generation) {
        return;
    }
    match pass.make_chain(&gpu, t.generation, t.size, hdr) {
        Ok(chain) => pass.chain = Some(chain),
        Err(e) => errors.0.push(e),
    }
}

/// Copies the HDR target into level 0 and averages each level into the next.
pub fn transmission_source_pass(
    pass: Res<TransmissionSourcePass>,
    plan: Res<FramePlan>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(()), Some(chain), Some(copy)) = (
        encoder.as_mut(),
        plan.variant::<TransmissionSourcePass>(),
        pass.chain.as_ref(),
        pass.copy.pipeline(FORMAT),
    ) else {
        return;
    };
    draw_fullscreen(
        encoder,
        timer,
        "transmission source",
        &[&chain.levels[0]],
        copy,
        &chain.copy_group,
    );
    for (target, group) in chain.levels[1..].iter().zip(&chain.groups) {
        draw_fullscreen(
            encoder,
            timer,
            "transmission source",
            &[target],
            &pass.downsample,
            group,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_end_at_one_texel() {
        assert_eq!(level_count((1, 1)), 1);
        assert_eq!(level_count((256, 256)), 9);
        assert_eq!(level_count((1280, 720)), 11);
        assert_eq!(level_count((0, 0)), 1);
    }
}

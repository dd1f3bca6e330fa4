//! The copy of the HDR image that the one-frame filters (FXAA, SMAA) read
//! (`aa_prepare.wgsl`): the linear colour, which they blend, with the perceptual luma they
//! compare in alpha ([`crate::shading::antialiasing::perceptual_luma`] of the
//! [`crate::shading::antialiasing::compress_hdr`]ed colour), in a target of its own so that the
//! filters can write their result into the HDR target they do not read.

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::{Slot, TargetFormat, TextureDesc};
use crate::render::pipeline_cache::Fullscreen;
use crate::render::pipelines::draw_fullscreen;
use crate::render::timing::GpuTimer;

/// The prepared image's format: f16, 11 significant bits (a relative error of 2⁻¹²
/// at most) up to 65504, far above a pre-exposed frame's highlights.
pub const PREPARED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The prepared image: the linear colour (rgb) and its perceptual luma (a), at the
/// output's size. FXAA and SMAA write it (one of them runs in a frame).
pub const AA_PREPARED: Slot = Slot::target("aa prepared", TargetFormat::Fixed(PREPARED_FORMAT));

/// A depth mask at the output's size, 1 where a filter's first step found an edge.
pub const MASK: TextureDesc =
    TextureDesc::full(TargetFormat::Fixed(crate::render::targets::DEPTH_FORMAT));

/// The preparation step's input.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("aa prepare", declared::AA_PREPARE_0);

/// The preparation step's pipeline and the bind group that reads the HDR target.
pub struct Preparation(FullscreenStep);

impl Preparation {
    /// Compiles the preparation step.
    pub fn new(gpu: &Gpu) -> Result<Preparation> {
        let mut step = FullscreenStep::new(
            gpu,
            Fullscreen::new("aa prepare", "aa_prepare.wgsl"),
            &BINDINGS,
        );
        step.ensure(gpu, (), &[PREPARED_FORMAT])?;
        Ok(Preparation(step))
    }

    /// Makes (or keeps) the group that prepares from `hdr`.
    pub fn prepare(&mut self, gpu: &Gpu, hdr: &wgpu::TextureView) -> Result<()> {
        self.0
            .bind(gpu, vec![wgpu::BindingResource::TextureView(hdr)])
    }

    /// Records the preparation into `prepared` ([`AA_PREPARED`]), timed as `name`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        name: &'static str,
        prepared: &wgpu::TextureView,
    ) {
        if let (Some(group), Some(pipeline)) =
            (self.0.group(), self.0.pipeline((), &[PREPARED_FORMAT]))
        {
            draw_fullscreen(encoder, timer, name, &[prepared], pipeline, group);
        }
    }
}

/// The step's shader build ([`crate::render::graph::FramePass::shader_builds`] of the
/// passes that use it).
pub fn build() -> crate::render::graph::ShaderBuild {
    crate::render::graph::ShaderBuild::new("aa_prepare.wgsl", Vec::new(), &[(0, BINDINGS)])
}

//! The copy of the HDR image that the one-frame filters (FXAA, SMAA) read
//! (`aa_prepare.wgsl`): the linear colour, which they blend, with the perceptual luma they
//! compare in alpha ([`crate::antialiasing::perceptual_luma`] of the
//! [`crate::antialiasing::compress_hdr`]ed colour), in a target of its own so that the
//! filters can write their result into the HDR target they do not read.

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::pipelines::{draw_fullscreen, fullscreen_variant, one_group_layout};
use crate::render::targets::Target;
use crate::render::timing::GpuTimer;

/// The prepared image's format: f16, 11 significant bits (a relative error of 2⁻¹²
/// at most) up to 65504, far above a pre-exposed frame's highlights.
pub const PREPARED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The preparation step's input.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "aa prepare",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("hdr", Binding::TextureLoad)],
};

/// The preparation step's pipeline.
pub struct Preparation {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

/// A prepared image and the bind group that fills it from one HDR target.
pub struct PreparedImage {
    /// The linear colour (rgb) and its perceptual luma (a).
    pub target: Target,
    group: wgpu::BindGroup,
}

impl Preparation {
    /// Compiles the preparation step.
    pub fn new(gpu: &Gpu) -> Result<Preparation> {
        let layout = BINDINGS.layout(gpu);
        let pipeline = fullscreen_variant(
            gpu,
            "aa prepare",
            &one_group_layout(gpu, "aa prepare", &layout),
            "aa_prepare.wgsl",
            &[],
            PREPARED_FORMAT,
        )?;
        Ok(Preparation { layout, pipeline })
    }

    /// A prepared image of `size` pixels, filled from `hdr`.
    pub fn image(
        &self,
        gpu: &Gpu,
        size: (u32, u32),
        hdr: &wgpu::TextureView,
    ) -> Result<PreparedImage> {
        let target = Target::new(gpu, "aa prepared", size, PREPARED_FORMAT);
        let group = BINDINGS.group(
            gpu,
            &self.layout,
            vec![wgpu::BindingResource::TextureView(hdr)],
        )?;
        Ok(PreparedImage { target, group })
    }

    /// Records the preparation of `image` from its HDR target, timed as `name`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        name: &'static str,
        image: &PreparedImage,
    ) {
        draw_fullscreen(
            encoder,
            timer,
            name,
            &[&image.target.view],
            &self.pipeline,
            &image.group,
        );
    }
}

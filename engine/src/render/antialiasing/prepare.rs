//! The copy of the HDR image that the one-frame filters (FXAA, SMAA) read
//! (`aa_prepare.wgsl`): the linear colour, which they blend, with the perceptual luma they
//! compare in alpha ([`crate::antialiasing::perceptual_luma`] of the
//! [`crate::antialiasing::compress_hdr`]ed colour), in a target of its own so that the
//! filters can write their result into the HDR target they do not read.

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::graph::{Slot, TargetFormat, TextureDesc};
use crate::render::pipelines::{draw_fullscreen, fullscreen_variant, one_group_layout};
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
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "aa prepare",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("hdr", Binding::TextureLoad)],
};

/// The preparation step's pipeline and the bind group that reads the HDR target.
pub struct Preparation {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    group: CachedGroup,
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
        Ok(Preparation {
            layout,
            pipeline,
            group: CachedGroup::default(),
        })
    }

    /// Makes (or keeps) the group that prepares from `hdr`.
    pub fn prepare(&mut self, gpu: &Gpu, hdr: &wgpu::TextureView) -> Result<()> {
        self.group.get(
            gpu,
            &BINDINGS,
            &self.layout,
            vec![wgpu::BindingResource::TextureView(hdr)],
        )?;
        Ok(())
    }

    /// Records the preparation into `prepared` ([`AA_PREPARED`]), timed as `name`.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        name: &'static str,
        prepared: &wgpu::TextureView,
    ) {
        if let Some(group) = self.group.group() {
            draw_fullscreen(encoder, timer, name, &[prepared], &self.pipeline, group);
        }
    }
}

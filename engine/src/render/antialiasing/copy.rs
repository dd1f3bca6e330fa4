//! A full-screen copy of a texture into the frame's HDR target (`copy.wgsl`), compiled per
//! HDR format: the last step of the passes that build their result in a target of their
//! own because they read the HDR target while making it (accumulation; TAA has its own
//! resolve, [`super::resolve`]).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::pipelines::PerFormat;

/// The copy's input.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "copy",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[("source", Binding::TextureLoad)],
};

/// The copy's layout and its pipelines, one per HDR format.
pub struct CopyToHdr {
    layout: wgpu::BindGroupLayout,
    pipelines: PerFormat,
}

impl CopyToHdr {
    /// The layouts; pipelines compile on first use.
    pub fn new(gpu: &Gpu) -> CopyToHdr {
        let layout = BINDINGS.layout(gpu);
        CopyToHdr {
            pipelines: PerFormat::new(gpu, "copy", "copy.wgsl", &layout),
            layout,
        }
    }

    /// Compiles the copy into `format` unless it exists.
    pub fn ensure(&mut self, gpu: &Gpu, format: wgpu::TextureFormat) -> Result<()> {
        self.pipelines.ensure(gpu, format)
    }

    /// The copy into `format`, once [`CopyToHdr::ensure`]d.
    pub fn pipeline(&self, format: wgpu::TextureFormat) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.get(format)
    }

    /// The bind group that copies from `source`, made (or kept) in `cache`.
    pub fn group<'c>(
        &self,
        cache: &'c mut CachedGroup,
        gpu: &Gpu,
        source: &wgpu::TextureView,
    ) -> Result<&'c wgpu::BindGroup> {
        cache.get(
            gpu,
            &BINDINGS,
            &self.layout,
            vec![wgpu::BindingResource::TextureView(source)],
        )
    }
}

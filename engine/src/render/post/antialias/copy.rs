//! A full-screen copy of a texture into the frame's HDR target (`copy.wgsl`), compiled per
//! HDR format: the last step of the passes that build their result in a target of their
//! own because they read the HDR target while making it (accumulation, the transmission
//! source; TAA has its own resolve, [`super::resolve`]).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::pipeline_cache::Fullscreen;

/// The copy's input.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("copy", declared::COPY_0);

/// The copy: one pipeline per HDR format.
pub struct CopyToHdr(pub FullscreenStep);

impl CopyToHdr {
    /// The layouts; pipelines compile on first use.
    pub fn new(gpu: &Gpu) -> CopyToHdr {
        CopyToHdr(FullscreenStep::new(
            gpu,
            Fullscreen::new("copy", "copy.wgsl"),
            &BINDINGS,
        ))
    }

    /// The bind group that copies from `source`, made (or kept) in `cache`.
    pub fn group<'c>(
        &self,
        cache: &'c mut CachedGroup,
        gpu: &Gpu,
        source: &wgpu::TextureView,
    ) -> Result<&'c wgpu::BindGroup> {
        self.0
            .bind_in(cache, gpu, vec![wgpu::BindingResource::TextureView(source)])
    }
}

/// The step's shader build ([`crate::render::graph::FramePass::shader_builds`] of the
/// passes that use it).
pub fn build() -> crate::render::graph::ShaderBuild {
    crate::render::graph::ShaderBuild::new("copy.wgsl", Vec::new(), &[(0, BINDINGS)])
}

//! A full-screen step of a pass: one bind group (its [`BindGroupSpec`]), the step's
//! pipelines per variant and target format ([`FullscreenPipelines`]), and the group it
//! binds, kept while it binds the same resources ([`CachedGroup`]).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup};
use crate::render::device::Gpu;
use crate::render::frame::FrameEncoder;
use crate::render::pipeline_cache::{Fullscreen, FullscreenPipelines, ShaderVariant};

/// One full-screen step: its layout, pipelines and bind group.
pub struct FullscreenStep<V: ShaderVariant = ()> {
    spec: &'static BindGroupSpec,
    layout: wgpu::BindGroupLayout,
    pipelines: FullscreenPipelines<V>,
    group: CachedGroup,
}

impl<V: ShaderVariant> FullscreenStep<V> {
    /// `step` over the bind group `spec`; pipelines compile on first use.
    pub fn new(gpu: &Gpu, step: Fullscreen, spec: &'static BindGroupSpec) -> Self {
        Self::with_groups(gpu, step, spec, &[])
    }

    /// `step` over the bind group `spec` (group 0) and groups 1, 2, … of layouts `more`,
    /// which the caller binds.
    pub fn with_groups(
        gpu: &Gpu,
        step: Fullscreen,
        spec: &'static BindGroupSpec,
        more: &[&wgpu::BindGroupLayout],
    ) -> Self {
        let layout = spec.layout(gpu);
        let mut groups = vec![&layout];
        groups.extend_from_slice(more);
        FullscreenStep {
            pipelines: FullscreenPipelines::new(gpu, step, &groups),
            spec,
            layout,
            group: CachedGroup::default(),
        }
    }

    /// Compiles the step's `variant` into colour targets of `formats` unless it was
    /// before.
    pub fn ensure(&mut self, gpu: &Gpu, variant: V, formats: &[wgpu::TextureFormat]) -> Result<()> {
        self.pipelines.ensure(gpu, variant, formats).map(|_| ())
    }

    /// The pipeline of `variant` into `formats`, once [`FullscreenStep::ensure`]d.
    pub fn pipeline(
        &self,
        variant: V,
        formats: &[wgpu::TextureFormat],
    ) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.get(variant, formats)
    }

    /// Makes (or keeps) the step's bind group of `resources`, one per binding of its spec.
    pub fn bind(&mut self, gpu: &Gpu, resources: Vec<wgpu::BindingResource<'_>>) -> Result<()> {
        self.group
            .get(gpu, self.spec, &self.layout, resources)
            .map(|_| ())
    }

    /// The group of `resources` made (or kept) in `cache`, for a step that alternates
    /// between groups (ping-pong targets).
    pub fn bind_in<'c>(
        &self,
        cache: &'c mut CachedGroup,
        gpu: &Gpu,
        resources: Vec<wgpu::BindingResource<'_>>,
    ) -> Result<&'c wgpu::BindGroup> {
        cache.get(gpu, self.spec, &self.layout, resources)
    }

    /// Records the step's `variant` into `targets` (of `formats`) with the bind group
    /// [`FullscreenStep::bind`] made last, labelled `name`; nothing where either is
    /// missing ([`FrameEncoder::fullscreen`]).
    pub fn draw(
        &self,
        encoder: &mut FrameEncoder,
        name: &'static str,
        (variant, formats): (V, &[wgpu::TextureFormat]),
        targets: &[&wgpu::TextureView],
    ) {
        encoder.fullscreen(name, targets, self.pipeline(variant, formats), self.group());
    }

    /// The bind group [`FullscreenStep::bind`] made last.
    pub fn group(&self) -> Option<&wgpu::BindGroup> {
        self.group.group()
    }

    /// The bind group layout.
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }
}

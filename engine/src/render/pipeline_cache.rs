//! The one cache of specialised pipelines every pass keeps.
//!
//! A pass compiles its shaders per *variant*: the features this frame's scene needs (which
//! lights, which shadows, how many AO slices), fixed at compile time as shader defs so that
//! a feature the scene does not use costs nothing. A variant is a small `Copy` struct the
//! pass's `decide` returns ([`crate::render::graph::PassDecision`]), and it turns into
//! shader defs in exactly one place: its [`ShaderVariant`] impl. [`PipelineCache`] keys the
//! compiled pipelines by the variant, so a pass compiles each variant once and a frame
//! that needs the same one again finds it.
//!
//! [`FullscreenPipelines`] is the cache for the most common kind of step: one full-screen
//! triangle (`vs_fullscreen`) and one fragment entry point, into any number of colour
//! targets. The targets' formats are part of its key, not of the variant's defs: a format
//! is pipeline state, and a variant that changes the shader by format (sRGB encoding) says
//! so in its own defs.
//!
//! Why a trait and not a derive: a variant's defs are not always its fields one by one
//! (lighting adds the shadow lookups' defs; the layer pass renames one def per layer), and
//! a trait impl beside the variant states that in plain Rust, where a derive would need
//! attributes for each exception.

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use crate::render::pipelines::{
    compute_pipeline, create_module, fullscreen_target_pipeline, pipeline_layout,
};
use crate::render::shaders::ShaderDef;
use std::collections::HashMap;
use std::fmt::Debug;
use std::hash::Hash;

/// A pass's shader variant: what it compiles its shaders with.
pub trait ShaderVariant: Clone + Eq + Hash + Debug + Send + Sync + 'static {
    /// The shader defs of this variant, in the order the header declares them.
    fn shader_defs(&self) -> Vec<ShaderDef>;
}

/// A pass with one shader build: no defs.
impl ShaderVariant for () {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        Vec::new()
    }
}

/// The most colour targets a render pipeline writes (WebGPU's `maxColorAttachments`).
pub const MAX_COLOR_TARGETS: usize = 8;

/// The colour target formats of a pipeline as a key, in order, `None` past the last: a
/// lookup builds it on the stack.
pub type TargetFormats = [Option<wgpu::TextureFormat>; MAX_COLOR_TARGETS];

/// `formats` as a key; `None` when there are more than [`MAX_COLOR_TARGETS`].
pub fn target_formats(formats: &[wgpu::TextureFormat]) -> Option<TargetFormats> {
    let mut key = [None; MAX_COLOR_TARGETS];
    if formats.len() > MAX_COLOR_TARGETS {
        return None;
    }
    for (k, f) in key.iter_mut().zip(formats) {
        *k = Some(*f);
    }
    Some(key)
}

/// A variant of `V` per set of colour target formats: the defs are `V`'s.
impl<V: ShaderVariant> ShaderVariant for (V, TargetFormats) {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        self.0.shader_defs()
    }
}

/// Pipelines (or sets of pipelines, `P`) compiled once per variant `V`.
pub struct PipelineCache<V, P = wgpu::RenderPipeline> {
    compiled: HashMap<V, P>,
}

impl<V, P> Default for PipelineCache<V, P> {
    fn default() -> Self {
        PipelineCache {
            compiled: HashMap::new(),
        }
    }
}

impl<V: ShaderVariant, P> PipelineCache<V, P> {
    /// The pipeline of `variant`, compiled by `compile` from the variant's defs unless it
    /// was before. A failed compile is returned and not kept, so the next frame tries
    /// again (after a shader reload, say).
    pub fn ensure(
        &mut self,
        variant: &V,
        compile: impl FnOnce(&[ShaderDef]) -> Result<P>,
    ) -> Result<&P> {
        self.ensure_with(variant, || compile(&variant.shader_defs()))
    }
}

impl<K: Clone + Eq + Hash, P> PipelineCache<K, P> {
    /// The entry of `key`, made by `compile` unless it was before: for what a variant's
    /// pipelines are built from besides its defs (a module per variant, then a pipeline
    /// per variant and target).
    pub fn ensure_with(&mut self, key: &K, compile: impl FnOnce() -> Result<P>) -> Result<&P> {
        if !self.compiled.contains_key(key) {
            let pipeline = compile()?;
            self.compiled.insert(key.clone(), pipeline);
        }
        Ok(&self.compiled[key])
    }

    /// The entry of `key`, once made.
    pub fn get(&self, key: &K) -> Option<&P> {
        self.compiled.get(key)
    }

    /// How many variants are compiled.
    pub fn len(&self) -> usize {
        self.compiled.len()
    }

    /// Whether no variant is compiled yet.
    pub fn is_empty(&self) -> bool {
        self.compiled.is_empty()
    }
}

/// How a full-screen step's pipelines are built: `fragment` of the module composed from
/// `shader`, after `vs_fullscreen`.
#[derive(Clone, Debug)]
pub struct Fullscreen {
    /// The label of the pipelines and their modules.
    pub label: &'static str,
    /// The entry module, a file of `shaders/`.
    pub shader: &'static str,
    /// The fragment entry point.
    pub fragment: &'static str,
    /// How the colour target is blended (`None`: replaced).
    pub blend: Option<wgpu::BlendState>,
    /// The depth state, if the step has a depth attachment.
    pub depth: Option<wgpu::DepthStencilState>,
}

impl Fullscreen {
    /// `fs_main` of `shader`, replacing the target, no depth.
    pub const fn new(label: &'static str, shader: &'static str) -> Fullscreen {
        Fullscreen {
            label,
            shader,
            fragment: "fs_main",
            blend: None,
            depth: None,
        }
    }

    /// The same step with another fragment entry point.
    pub const fn entry(self, fragment: &'static str) -> Fullscreen {
        Fullscreen { fragment, ..self }
    }

    /// The same step blending into its target with `blend`.
    pub const fn blending(self, blend: wgpu::BlendState) -> Fullscreen {
        Fullscreen {
            blend: Some(blend),
            ..self
        }
    }

    /// The same step with a depth attachment in state `depth`.
    pub fn depth(self, depth: wgpu::DepthStencilState) -> Fullscreen {
        Fullscreen {
            depth: Some(depth),
            ..self
        }
    }
}

/// The pipelines of one full-screen step, per variant and colour target format.
pub struct FullscreenPipelines<V: ShaderVariant = ()> {
    step: Fullscreen,
    layout: wgpu::PipelineLayout,
    cache: PipelineCache<(V, TargetFormats)>,
}

impl<V: ShaderVariant> FullscreenPipelines<V> {
    /// The step's pipeline layout over `groups` (bind groups 0, 1, …); nothing compiles
    /// yet.
    pub fn new(gpu: &Gpu, step: Fullscreen, groups: &[&wgpu::BindGroupLayout]) -> Self {
        FullscreenPipelines {
            layout: pipeline_layout(gpu, step.label, groups),
            step,
            cache: PipelineCache::default(),
        }
    }

    /// The pipeline of `variant` into colour targets of `formats` (none: a step that
    /// writes depth only), compiled unless it was before.
    pub fn ensure(
        &mut self,
        gpu: &Gpu,
        variant: V,
        formats: &[wgpu::TextureFormat],
    ) -> Result<&wgpu::RenderPipeline> {
        let key = target_formats(formats).ok_or_else(|| {
            Error::Gpu(format!(
                "{}: {} colour targets, more than {MAX_COLOR_TARGETS}",
                self.step.label,
                formats.len()
            ))
        })?;
        let FullscreenPipelines {
            step,
            layout,
            cache,
        } = self;
        cache.ensure(&(variant, key), |defs| {
            let module = create_module(gpu, step.label, &gpu.shaders.compose(step.shader, defs)?)?;
            let targets: Vec<Option<wgpu::ColorTargetState>> = formats
                .iter()
                .map(|&format| {
                    Some(wgpu::ColorTargetState {
                        format,
                        blend: step.blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })
                })
                .collect();
            fullscreen_target_pipeline(
                gpu,
                step.label,
                Some(layout),
                &module,
                ("vs_fullscreen", step.fragment),
                &targets,
                step.depth.clone(),
            )
        })
    }

    /// The pipeline of `variant` into `formats`, once [`FullscreenPipelines::ensure`]d.
    pub fn get(
        &self,
        variant: V,
        formats: &[wgpu::TextureFormat],
    ) -> Option<&wgpu::RenderPipeline> {
        self.cache.get(&(variant, target_formats(formats)?))
    }
}

/// The pipelines of one compute step: entry point `entry` of the module composed from
/// `shader`, per variant.
pub struct ComputePipelines<V: ShaderVariant = ()> {
    label: &'static str,
    shader: &'static str,
    entry: &'static str,
    layout: wgpu::PipelineLayout,
    cache: PipelineCache<V, wgpu::ComputePipeline>,
}

impl<V: ShaderVariant> ComputePipelines<V> {
    /// The step's pipeline layout over `groups` (bind groups 0, 1, …); nothing compiles
    /// yet.
    pub fn new(
        gpu: &Gpu,
        (label, shader, entry): (&'static str, &'static str, &'static str),
        groups: &[&wgpu::BindGroupLayout],
    ) -> Self {
        ComputePipelines {
            label,
            shader,
            entry,
            layout: pipeline_layout(gpu, label, groups),
            cache: PipelineCache::default(),
        }
    }

    /// The pipeline of `variant`, compiled unless it was before.
    pub fn ensure(&mut self, gpu: &Gpu, variant: &V) -> Result<&wgpu::ComputePipeline> {
        let ComputePipelines {
            label,
            shader,
            entry,
            layout,
            cache,
        } = self;
        cache.ensure(variant, |defs| {
            let module = create_module(gpu, label, &gpu.shaders.compose(shader, defs)?)?;
            compute_pipeline(gpu, label, Some(layout), &module, entry)
        })
    }

    /// The pipeline of `variant`, once [`ComputePipelines::ensure`]d.
    pub fn get(&self, variant: &V) -> Option<&wgpu::ComputePipeline> {
        self.cache.get(variant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_formats_key_keeps_the_order_and_refuses_too_many() {
        use wgpu::TextureFormat::{R8Unorm, Rgba16Float};
        let key = target_formats(&[Rgba16Float, R8Unorm]).expect("two targets");
        assert_eq!(key[..3], [Some(Rgba16Float), Some(R8Unorm), None]);
        assert_ne!(key, target_formats(&[R8Unorm, Rgba16Float]).expect("two"));
        assert_eq!(target_formats(&[]), Some([None; MAX_COLOR_TARGETS]));
        assert_eq!(target_formats(&[R8Unorm; MAX_COLOR_TARGETS + 1]), None);
    }
}

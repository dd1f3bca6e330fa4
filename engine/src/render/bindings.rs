//! Bind groups with one source of truth, the WGSL: the build script reads every
//! `@group(G) @binding(B) var…` declaration of `shaders/` into [`declared`] (one list per
//! shader with an entry point and group, its imports included), and a [`BindGroupSpec`]
//! takes such a list (their WGSL names and kinds, the binding index being the position in
//! the list), which builds both the layout and the group. `tests/bindings.rs` composes
//! each pass's shader in every variant and checks, with naga, that every listed name is
//! declared at that group and binding with that kind, and that nothing else is bound
//! there.

use crate::error::{Error, Result};
use crate::render::device::Gpu;

/// The bindings each shader declares, written by the build script from `shaders/`:
/// `STEM_GROUP` (e.g. `GTAO_0`, `LIGHTING_1`, `GBUFFER_MAPS_GROUP`) lists group `GROUP`
/// of `STEM.wgsl` with the modules it imports, in binding order, for every group whose
/// bindings run from 0 without a gap. A float texture that some `textureSample*` or
/// `textureGather*` call of those modules takes is [`Binding::Sampled`], one that is only
/// loaded [`Binding::TextureLoad`]. A dynamic offset is not in the WGSL: such groups are
/// listed by hand.
pub mod declared {
    use super::Binding;
    include!(concat!(env!("OUT_DIR"), "/declared_bindings.rs"));
}

/// What one binding holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binding {
    /// A uniform buffer.
    Uniform,
    /// A read-only storage buffer.
    Storage,
    /// A storage buffer the shader writes.
    StorageReadWrite,
    /// A uniform buffer bound at a dynamic offset, of at least this many bytes.
    DynamicUniform(u64),
    /// A 2D float texture read with `textureLoad` (any float format, depth included,
    /// binds as unfilterable float).
    TextureLoad,
    /// A filterable float texture sampled with a sampler, of this dimension.
    Sampled(wgpu::TextureViewDimension),
    /// A depth texture compared with a comparison sampler.
    Depth,
    /// A filtering sampler.
    Sampler,
    /// A comparison sampler.
    ComparisonSampler,
    /// A 2D storage texture of this format that the shader writes.
    StorageTexture(wgpu::TextureFormat),
}

impl Binding {
    fn ty(self) -> wgpu::BindingType {
        let texture = |sample_type, view_dimension| wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        };
        let buffer = |ty| wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        match self {
            Binding::Uniform => buffer(wgpu::BufferBindingType::Uniform),
            Binding::Storage => buffer(wgpu::BufferBindingType::Storage { read_only: true }),
            Binding::StorageReadWrite => {
                buffer(wgpu::BufferBindingType::Storage { read_only: false })
            }
            Binding::DynamicUniform(size) => wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size),
            },
            Binding::TextureLoad => texture(
                wgpu::TextureSampleType::Float { filterable: false },
                wgpu::TextureViewDimension::D2,
            ),
            Binding::Sampled(dimension) => texture(
                wgpu::TextureSampleType::Float { filterable: true },
                dimension,
            ),
            Binding::Depth => texture(
                wgpu::TextureSampleType::Depth,
                wgpu::TextureViewDimension::D2,
            ),
            Binding::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            Binding::ComparisonSampler => {
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison)
            }
            Binding::StorageTexture(format) => wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
        }
    }
}

/// One bind group: its label, the stages that see it, and its bindings in order (binding
/// `i` is `bindings[i]`, named as in the WGSL).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BindGroupSpec {
    /// Label of the layout and the groups.
    pub label: &'static str,
    /// The shader stages that read it.
    pub visibility: wgpu::ShaderStages,
    /// (WGSL variable name, kind), binding index = position.
    pub bindings: &'static [(&'static str, Binding)],
}

impl BindGroupSpec {
    /// The group `label`, seen by `visibility`, binding `bindings` (usually a [`declared`]
    /// list, or a leading part of one).
    pub const fn new(
        label: &'static str,
        visibility: wgpu::ShaderStages,
        bindings: &'static [(&'static str, Binding)],
    ) -> Self {
        BindGroupSpec {
            label,
            visibility,
            bindings,
        }
    }

    /// [`BindGroupSpec::new`] seen by the fragment stage.
    pub const fn fragment(
        label: &'static str,
        bindings: &'static [(&'static str, Binding)],
    ) -> Self {
        BindGroupSpec::new(label, wgpu::ShaderStages::FRAGMENT, bindings)
    }

    /// [`BindGroupSpec::new`] seen by the compute stage.
    pub const fn compute(
        label: &'static str,
        bindings: &'static [(&'static str, Binding)],
    ) -> Self {
        BindGroupSpec::new(label, wgpu::ShaderStages::COMPUTE, bindings)
    }

    /// How many textures (sampled, depth or loaded) and samplers it binds: what counts
    /// against `max_sampled_textures_per_shader_stage` and `max_samplers_per_shader_stage`.
    pub fn textures_and_samplers(&self) -> (u32, u32) {
        self.bindings
            .iter()
            .fold((0, 0), |(t, s), (_, kind)| match kind {
                Binding::TextureLoad | Binding::Sampled(_) | Binding::Depth => (t + 1, s),
                Binding::Sampler | Binding::ComparisonSampler => (t, s + 1),
                _ => (t, s),
            })
    }

    /// The layout.
    pub fn layout(&self, gpu: &Gpu) -> wgpu::BindGroupLayout {
        let entries: Vec<wgpu::BindGroupLayoutEntry> = self
            .bindings
            .iter()
            .zip(0u32..)
            .map(|(&(_, kind), binding)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: self.visibility,
                ty: kind.ty(),
                count: None,
            })
            .collect();
        gpu.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(self.label),
                entries: &entries,
            })
    }

    /// `resources` as the group's entries, binding `i` being `resources[i]`; a count that is
    /// not the bindings' is an error naming the group.
    fn entries<'a>(
        &self,
        resources: Vec<wgpu::BindingResource<'a>>,
    ) -> Result<Vec<wgpu::BindGroupEntry<'a>>> {
        if resources.len() != self.bindings.len() {
            return Err(Error::Gpu(format!(
                "bind group '{}': {} resources for {} bindings",
                self.label,
                resources.len(),
                self.bindings.len()
            )));
        }
        Ok(resources
            .into_iter()
            .zip(0u32..)
            .map(|(resource, binding)| wgpu::BindGroupEntry { binding, resource })
            .collect())
    }

    /// A group of `layout` (made by [`BindGroupSpec::layout`]) binding `resources`, one per
    /// binding in order.
    pub fn group(
        &self,
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        resources: Vec<wgpu::BindingResource<'_>>,
    ) -> Result<wgpu::BindGroup> {
        let entries = self.entries(resources)?;
        Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout,
            entries: &entries,
        }))
    }
}

/// The identity of one bound resource: a clone of its handle (which keeps it alive, so its
/// identity is not reused while a group that binds it is kept), compared by identity.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Bound {
    Buffer(wgpu::Buffer, u64, Option<wgpu::BufferSize>),
    View(wgpu::TextureView),
    Sampler(wgpu::Sampler),
}

impl Bound {
    fn of(resource: &wgpu::BindingResource<'_>) -> Option<Bound> {
        match resource {
            wgpu::BindingResource::Buffer(b) => {
                Some(Bound::Buffer(b.buffer.clone(), b.offset, b.size))
            }
            wgpu::BindingResource::TextureView(v) => Some(Bound::View((*v).clone())),
            wgpu::BindingResource::Sampler(s) => Some(Bound::Sampler((*s).clone())),
            _ => None,
        }
    }
}

/// A bind group kept while it binds the same layout and the same resources: its key is
/// the identity of the layout and of every bound buffer (with its range), texture view and
/// sampler, so a resized, re-created or re-assigned resource can never leave it stale,
/// and nothing has to count generations.
#[derive(Debug, Default)]
pub struct CachedGroup {
    key: Option<(wgpu::BindGroupLayout, Vec<Bound>)>,
    group: Option<wgpu::BindGroup>,
}

impl CachedGroup {
    /// The group of `spec` with `layout` binding `resources` (one per binding, in order):
    /// the kept one when it binds the same, else a new one, kept in its place.
    pub fn get(
        &mut self,
        gpu: &Gpu,
        spec: &BindGroupSpec,
        layout: &wgpu::BindGroupLayout,
        resources: Vec<wgpu::BindingResource<'_>>,
    ) -> Result<&wgpu::BindGroup> {
        let entries = spec.entries(resources)?;
        Ok(self.entries(gpu, spec.label, layout, entries))
    }

    /// The group of `layout` with `entries`: the kept one when it binds the same, else a
    /// new one, kept in its place.
    pub fn entries(
        &mut self,
        gpu: &Gpu,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        entries: Vec<wgpu::BindGroupEntry<'_>>,
    ) -> &wgpu::BindGroup {
        let bound: Option<Vec<Bound>> = entries.iter().map(|e| Bound::of(&e.resource)).collect();
        let key = bound.map(|b| (layout.clone(), b));
        if key.is_none() || self.key != key {
            self.key = key;
            self.group = None;
        }
        self.group.get_or_insert_with(|| {
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries: &entries,
            })
        })
    }

    /// The group made last, if any.
    pub fn group(&self) -> Option<&wgpu::BindGroup> {
        self.group.as_ref()
    }
}

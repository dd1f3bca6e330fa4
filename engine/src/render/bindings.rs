//! Bind groups with one source of truth: a [`BindGroupSpec`] lists a group's bindings
//! (their WGSL names and kinds, the binding index being the position in the list), and
//! the same list builds both the layout and the group. `tests/bindings.rs` composes each
//! pass's shader and checks that every listed name is declared in the WGSL at that group
//! and binding, and that nothing else is bound there.

use crate::error::{Error, Result};
use crate::render::device::Gpu;

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

    /// A group of `layout` (made by [`BindGroupSpec::layout`]) binding `resources`, one per
    /// binding in order.
    pub fn group(
        &self,
        gpu: &Gpu,
        layout: &wgpu::BindGroupLayout,
        resources: Vec<wgpu::BindingResource<'_>>,
    ) -> Result<wgpu::BindGroup> {
        if resources.len() != self.bindings.len() {
            return Err(Error::Gpu(format!(
                "bind group '{}': {} resources for {} bindings",
                self.label,
                resources.len(),
                self.bindings.len()
            )));
        }
        let entries: Vec<wgpu::BindGroupEntry> = resources
            .into_iter()
            .zip(0u32..)
            .map(|(resource, binding)| wgpu::BindGroupEntry { binding, resource })
            .collect();
        Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout,
            entries: &entries,
        }))
    }
}

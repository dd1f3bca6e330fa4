//! The bind group of shadow lookups and the lights they belong to: group 1 of the
//! lighting pass (`shaders/lights.wgsl` and `shaders/shadows.wgsl` declare it), which the
//! transparent and layer passes bind as it is and the shadow-mask pass
//! ([`crate::render::shadow::mask`]) builds for itself.

use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::light_culling::LightCullingPass;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shadow::pass::ShadowPass;

/// Group 1: the lights, their tile lists and their shadows.
pub const LIGHTS_AND_SHADOWS: BindGroupSpec = BindGroupSpec {
    label: "lighting: lights and shadows",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("lights", Binding::Storage),
        ("uniform_lights", Binding::Uniform),
        ("shadowed_lights", Binding::Uniform),
        ("light_tiles", Binding::Storage),
        ("shadow_views", Binding::Storage),
        ("shadow_atlas", Binding::Depth),
        ("shadow_sampler", Binding::ComparisonSampler),
        ("shadow_atlas_depth", Binding::TextureLoad),
        ("uniform_shadow_views", Binding::Uniform),
    ],
};

/// The resources of [`LIGHTS_AND_SHADOWS`], in its order: the lighting pass and the
/// shadow-mask pass bind the same.
pub fn lights_and_shadows<'a>(
    buffers: &'a SceneBuffers,
    shadows: &'a ShadowPass,
    culling: &'a LightCullingPass,
) -> Vec<wgpu::BindingResource<'a>> {
    use wgpu::BindingResource::{Sampler, TextureView};
    vec![
        buffers.lights.buffer.as_entire_binding(),
        buffers.lights_uniform.as_entire_binding(),
        buffers.shadowed_lights_uniform.as_entire_binding(),
        culling.tiles.as_entire_binding(),
        shadows.gpu_views.buffer.as_entire_binding(),
        TextureView(&shadows.atlas.view),
        Sampler(&shadows.sampler),
        TextureView(&shadows.atlas.view),
        shadows.views_uniform.as_entire_binding(),
    ]
}

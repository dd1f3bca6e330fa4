//! The bind group of shadow lookups and the lights they belong to: group 1 of the
//! lighting pass (`shaders/lights.wgsl` and `shaders/shadows.wgsl` declare it), which the
//! transparent and layer passes bind as it is and the shadow-mask pass
//! ([`crate::render::shadow::mask`]) builds for itself.

use crate::quality::ShadowFilter;
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::extract::ExtractedFrame;
use crate::render::scene_buffers::{SHADOWED_LIGHT_CAPACITY, SceneBuffers};
use crate::render::shaders::ShaderDef;
use crate::render::shadow::atlas::{ShadowAtlas, UNIFORM_SHADOW_VIEWS};

/// Group 1: the lights, their tile lists and their shadows.
pub const LIGHTS_AND_SHADOWS: BindGroupSpec =
    BindGroupSpec::fragment("lighting: lights and shadows", declared::LIGHTING_1);

/// The resources of [`LIGHTS_AND_SHADOWS`], in its order, with the frame's light `tiles`
/// ([`crate::render::graph::slots::LIGHT_TILES`]): the lighting pass and the shadow-mask
/// pass bind the same.
pub fn lights_and_shadows<'a>(
    buffers: &'a SceneBuffers,
    shadows: &'a ShadowAtlas,
    tiles: &'a wgpu::Buffer,
) -> Vec<wgpu::BindingResource<'a>> {
    use wgpu::BindingResource::{Sampler, TextureView};
    vec![
        buffers.lights.buffer.as_entire_binding(),
        buffers.lights_uniform.as_entire_binding(),
        buffers.shadowed_lights_uniform.as_entire_binding(),
        tiles.as_entire_binding(),
        shadows.gpu_views.buffer.as_entire_binding(),
        TextureView(&shadows.atlas.view),
        Sampler(&shadows.sampler),
        TextureView(&shadows.atlas.view),
        shadows.views_uniform.as_entire_binding(),
    ]
}

/// Whether every shadow view of `frame` fits the uniform copy of the view array (read
/// from it, not from the storage buffer: cheaper on lavapipe).
pub fn views_fit_uniform(frame: &ExtractedFrame) -> bool {
    frame.shadow_views.len() <= UNIFORM_SHADOW_VIEWS as usize
}

/// The header constants `lights.wgsl` and `shadows.wgsl` read: the shadow filter, whether
/// the lights and the shadow views are read from their uniform copies, and those copies'
/// capacities (`uniform_capacity` lights), for every pass that binds
/// [`LIGHTS_AND_SHADOWS`].
pub fn lookup_defs(
    filter: ShadowFilter,
    uniform_lights: bool,
    uniform_shadow_views: bool,
    uniform_capacity: u32,
) -> Vec<ShaderDef> {
    vec![
        ShaderDef::U32("SHADOW_FILTER", filter as u32),
        ShaderDef::Bool("UNIFORM_LIGHTS", uniform_lights),
        ShaderDef::Bool("UNIFORM_SHADOW_VIEWS", uniform_shadow_views),
        ShaderDef::U32("UNIFORM_SHADOW_VIEW_CAPACITY", UNIFORM_SHADOW_VIEWS),
        ShaderDef::U32("UNIFORM_LIGHT_CAPACITY", uniform_capacity.max(1)),
        ShaderDef::U32("SHADOWED_LIGHT_CAPACITY", SHADOWED_LIGHT_CAPACITY),
    ]
}

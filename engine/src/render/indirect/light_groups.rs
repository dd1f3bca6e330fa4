//! The bind groups of the lights and of indirect light that every pass shading surfaces
//! binds as they are: group 1, the lights, their tile lists and their shadows
//! ([`LIGHTS_AND_SHADOWS`]); group 2, the environment and the screen's ambient occlusion
//! ([`ENVIRONMENT`]); group 3, the irradiance volume and the reflection probes
//! ([`PROBES`]). The lighting pass prepares them each frame, after the shadow pass has
//! sized the atlas; the layer, transparent and reflection passes bind the same groups.
//! Each is kept while it binds the same resources ([`CachedGroup`]).

use crate::error::Result;
use crate::render::bindings::CachedGroup;
use crate::render::device::Gpu;
use crate::render::graph::slots::AMBIENT_OCCLUSION;
use crate::render::graph::slots::LIGHT_TILES;
use crate::render::indirect::environment_maps::{ENVIRONMENT, Ibl};
use crate::render::indirect::probe_volume::{IrradianceVolumeGpu, PROBES, probe_bindings};
use crate::render::indirect::reflection_probes::ReflectionProbesGpu;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shadow::atlas::ShadowAtlas;
use crate::render::shadow::lookups::{LIGHTS_AND_SHADOWS, lights_and_shadows};
use crate::render::targets::FrameTargets;
use bevy_ecs::prelude::*;

/// Groups 1 to 3 of the passes that shade surfaces, and their layouts.
#[derive(Resource)]
pub struct LightGroups {
    /// The layouts of groups 1, 2 and 3.
    pub layouts: [wgpu::BindGroupLayout; 3],
    groups: [CachedGroup; 3],
}

impl LightGroups {
    /// The layouts; the groups are made by [`LightGroups::prepare`].
    pub fn new(gpu: &Gpu) -> LightGroups {
        LightGroups {
            layouts: [LIGHTS_AND_SHADOWS, ENVIRONMENT, PROBES].map(|spec| spec.layout(gpu)),
            groups: Default::default(),
        }
    }

    /// Makes (or keeps) this frame's groups from the frame's targets `t` and the shared
    /// resources; `false` when the frame lacks a resource they bind.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        t: &FrameTargets,
        buffers: &SceneBuffers,
        atlas: &ShadowAtlas,
        ibl: &Ibl,
        volume: &IrradianceVolumeGpu,
        reflections: &ReflectionProbesGpu,
    ) -> Result<bool> {
        let (Some(tiles), Some(ao)) = (t.buffer(LIGHT_TILES), t.view(AMBIENT_OCCLUSION)) else {
            return Ok(false);
        };
        use wgpu::BindingResource::{Sampler, TextureView};
        let LightGroups { layouts, groups } = self;
        let [lights, environment, probes] = groups;
        lights.get(
            gpu,
            &LIGHTS_AND_SHADOWS,
            &layouts[0],
            lights_and_shadows(buffers, atlas, tiles),
        )?;
        environment.get(
            gpu,
            &ENVIRONMENT,
            &layouts[1],
            vec![
                ibl.uniform.as_entire_binding(),
                TextureView(ibl.cube_view()),
                Sampler(&ibl.sampler),
                TextureView(ibl.lut_view()),
                TextureView(ao),
            ],
        )?;
        probes.get(
            gpu,
            &PROBES,
            &layouts[2],
            probe_bindings(volume, reflections),
        )?;
        Ok(true)
    }

    /// This frame's groups 1, 2 and 3, once prepared.
    pub fn groups(&self) -> Option<[&wgpu::BindGroup; 3]> {
        let [a, b, c] = &self.groups;
        Some([a.group()?, b.group()?, c.group()?])
    }
}

//! Light probes: where the renderer captures the scene's own light for indirect lighting.

use bevy_ecs::prelude::Component;
use glam::Vec3;

/// A box of irradiance probes for diffuse global illumination
/// ([`crate::shading::irradiance_volume`]): probes on a regular grid from `min` to `max` (world
/// space, metres), each capturing the lit scene around it. Points inside the box take
/// their diffuse indirect light from the eight probes around them instead of from the
/// environment's irradiance.
///
/// Without one, a scene gets a volume around all its meshes when
/// [`crate::quality::GiSettings::enabled`] is on (the automatic rule in
/// `docs/src/indirect.md`); spawning one replaces that rule. Only the first volume counts.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct IrradianceVolume {
    /// The corner of the box with the smallest coordinates (m).
    pub min: Vec3,
    /// The opposite corner (m). A box of zero size holds one probe.
    pub max: Vec3,
    /// Distance between neighbouring probes (m); `None` takes
    /// [`crate::quality::GiSettings::density`]. At most
    /// [`crate::shading::irradiance_volume::MAX_PROBES_PER_AXIS`] probes per axis: a box that would
    /// need more spreads them wider.
    pub spacing_m: Option<f32>,
}

impl IrradianceVolume {
    /// A volume over the box `min`..`max` at the quality's spacing.
    pub fn new(min: Vec3, max: Vec3) -> IrradianceVolume {
        IrradianceVolume {
            min,
            max,
            spacing_m: None,
        }
    }
}

/// A reflection probe ([`crate::render::indirect::reflection_probes`]): the lit scene seen
/// from the entity's position (its `Transform`), captured into a cube map and prefiltered
/// like an environment. Smooth and glossy surfaces inside its box reflect it instead of
/// the environment, with the reflected ray corrected for the box's parallax (the box
/// stands in for the room's walls).
///
/// Without one, when [`crate::quality::ReflectionProbeSettings::enabled`] is on, Lumen
/// places one at the centre of all meshes' bounds (the automatic rule in
/// `docs/src/indirect.md`); spawning one replaces that rule. At most two probes are used:
/// the two whose boxes hold the camera or lie nearest to it. Where two boxes overlap, their
/// reflections blend by their weights.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ReflectionProbe {
    /// Half the size of the box of influence along each world axis (m), centred on the
    /// probe. Surfaces outside it do not see the probe; over the outer `blend_m` metres
    /// inside its faces, the probe's weight falls to 0.
    pub half_extents: glam::Vec3,
    /// Width (m) of the band inside the box's faces over which the probe fades out.
    pub blend_m: f32,
}

impl ReflectionProbe {
    /// A probe whose box reaches `half_extents` metres from it along each axis, fading over
    /// the outer tenth of its smallest half-extent.
    pub fn new(half_extents: glam::Vec3) -> ReflectionProbe {
        ReflectionProbe {
            half_extents,
            blend_m: 0.1 * half_extents.min_element().max(0.0),
        }
    }
}

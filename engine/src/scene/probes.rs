//! Light probes: where the renderer captures the scene's own light for indirect lighting.

use bevy_ecs::prelude::Component;
use glam::Vec3;

/// A box of irradiance probes for diffuse global illumination
/// ([`crate::irradiance_volume`]): probes on a regular grid from `min` to `max` (world
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
    /// [`crate::quality::GiSettings::spacing_m`]. At most
    /// [`crate::irradiance_volume::MAX_PROBES_PER_AXIS`] probes per axis: a box that would
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

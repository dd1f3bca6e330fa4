//! Speed/accuracy knobs. Each is a field with a documented cost; presets arrive with the
//! benchmark issue.

use crate::brdf::VisibilityModel;
use bevy_ecs::prelude::Resource;

/// The renderer's quality settings.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Quality {
    /// Visibility (geometric) term of the specular lobe. `schlick-ggx` (the seeds',
    /// default) and `smith-correlated-fast` cost the same; `smith-correlated` adds two
    /// square roots per light and pixel.
    pub visibility: VisibilityModel,
}

//! Shadow maps: every shadow view of the frame (cascades of directional lights, spot
//! views, cube faces of point lights) in one depth atlas, drawn in one pass. The views themselves are computed during extraction
//! ([`crate::render::extract::shadow_views`]).

pub mod atlas;
pub mod lookups;
pub mod mask;
pub mod pass;

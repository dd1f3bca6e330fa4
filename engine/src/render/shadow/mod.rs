//! Shadow maps: every shadow view of the frame (cascades of directional lights, spot
//! views, cube faces of point lights) in one depth atlas, drawn in one pass.

pub mod atlas;
pub mod cascades;
pub mod pass;
pub mod views;

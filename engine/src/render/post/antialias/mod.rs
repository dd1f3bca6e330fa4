//! Anti-aliasing: the accumulation of jittered frames ([`crate::render::jitter`]),
//! temporal anti-aliasing (its motion vectors come from the G-buffer pass), and the post-process filters on one
//! frame (FXAA, SMAA) (docs/src/antialiasing.md).
//!
//! Geometric specular anti-aliasing is not a pass: the G-buffer pass widens the stored
//! roughness ([`crate::shading::brdf::specular_aa_roughness`]).

pub mod accumulate;
pub mod copy;
pub mod fxaa;
pub mod prepare;
pub mod renders;
pub mod resolve;
pub mod smaa;
pub mod taa;

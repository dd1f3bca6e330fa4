//! The passes of indirect light: what the frame adds to direct lighting so that light
//! arriving from other surfaces and from the environment is occluded and reflected.
//! Screen-space ambient occlusion ([`ambient_occlusion`]) and screen-space reflections
//! ([`reflections`]) over the [`depth_pyramid`].

pub mod ambient_occlusion;
pub mod depth_pyramid;
pub mod reflections;

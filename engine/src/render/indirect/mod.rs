//! The passes of indirect light: what the frame adds to direct lighting so that light
//! arriving from other surfaces and from the environment is occluded and reflected.
//! Today: screen-space ambient occlusion ([`ambient_occlusion`]).

pub mod ambient_occlusion;

//! Getting content into the scene: procedural meshes and image files.

pub mod image_io;
pub mod procedural;

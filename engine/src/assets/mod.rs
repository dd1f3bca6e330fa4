//! Getting content into the scene: procedural meshes, glTF import, image files.

pub mod draco;
pub mod gltf;
mod gltf_buffers;
mod gltf_material;
pub mod image_io;
pub mod procedural;
pub mod tangents;
pub mod texture_io;

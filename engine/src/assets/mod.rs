//! Getting content into the scene and images out: procedural meshes, glTF import, image
//! files, and the checked reads and atomic writes every file goes through.

pub mod draco;
pub mod gltf;
mod gltf_animation;
mod gltf_buffers;
mod gltf_checks;
mod gltf_material;
mod gltf_quantized;
mod gltf_skin;
pub mod image_io;
pub mod meshopt;
pub mod procedural;
pub mod tangents;
pub mod texture_io;

//! The geometry stage: the passes that draw the scene's meshes. Skinned and morphed
//! meshes are deformed first ([`deform_pass`]); the [`gbuffer`] pass rasterises every
//! opaque surface into the G-buffer and depth, binding each material's textures
//! ([`gpu_material_maps`]) and the vertex layout of [`mesh_vertex`].
pub mod deform_pass;
pub mod gbuffer;
pub mod gpu_material_maps;
pub mod mesh_vertex;

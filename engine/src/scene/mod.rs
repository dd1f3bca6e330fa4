//! The scene as ECS components: what a user spawns into the `bevy_ecs` World.
//!
//! Everything here is plain data with physical units in its field names and docs. The
//! renderer reads these components each frame (see [`crate::render::extract`]) and never
//! keeps its own copy of the scene.

pub mod animation;
pub mod camera;
pub mod deform;
pub mod environment;
pub mod extension_maps;
pub mod light;
pub mod material;
pub mod material_maps;
pub mod mesh;
pub mod mesh_data;
pub mod probes;
pub mod shadow_settings;
pub mod texture;
pub mod transform;

pub use animation::{AnimationClip, AnimationPlayer};
pub use camera::{AutoExposure, Camera, DepthOfField, Exposure, Lens, Projection, Vignette};
pub use deform::{MorphTarget, MorphWeights, SkinnedMesh};
pub use environment::{Background, Environment, EnvironmentSource, EquirectImage};
pub use extension_maps::ExtensionMaps;
pub use light::{DirectionalLight, LightColor, LuminousIntensity, PointLight, SpotLight};
pub use material::{
    Anisotropy, Clearcoat, DiffuseTransmission, Iridescence, Material, Sheen, Transmission,
};
pub use material_maps::MaterialMaps;
pub use mesh::{Aabb, Mesh3d, MeshData, MeshHandle, Meshes, Vertex};
pub use probes::{IrradianceVolume, ReflectionProbe};
pub use shadow_settings::{Cascades, NotShadowCaster, NotShadowReceiver, ShadowSettings};
pub use texture::{
    ColorSpace, Filter, Sampler, TextureData, TextureHandle, TextureSlot, Textures, UvTransform,
    Wrap,
};
pub use transform::{GlobalTransform, Transform, propagate_transforms};

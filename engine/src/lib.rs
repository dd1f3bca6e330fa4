//! # Lumen
//!
//! A physically based deferred renderer: the scene lives in a `bevy_ecs` World, ECS
//! systems turn it into `wgpu` passes (G-buffer, Cook-Torrance lighting, tone mapping),
//! and every pass is timed.
//!
//! ```no_run
//! use lumen::prelude::*;
//!
//! # fn main() -> lumen::Result<()> {
//! let mut app = App::headless()?;
//! let sphere = app.add_mesh(lumen::assets::procedural::uv_sphere(1.0, 32, 16))?;
//! let world = app.world_mut();
//! world.spawn((Mesh3d(sphere), Material::new(Vec3::new(0.9, 0.6, 0.2), 1.0, 0.3)));
//! world.spawn((DirectionalLight::default(), Transform::from_xyz(1.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y)));
//! world.spawn((Camera::default(), Transform::from_xyz(0.0, 0.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y)));
//! app.render_headless((256, 256))?;
//! lumen::assets::image_io::save_png("sphere.png".as_ref(), &app.read_display_image()?)?;
//! # Ok(())
//! # }
//! ```
//!
//! Units: metres, radians (unless a name says degrees), lux for directional lights,
//! lumens or candela for point and spot lights, cd/m² for emissive and backgrounds.
//! Right-handed, +Y up, cameras and lights look along their local −Z.

pub mod app;
pub mod assets;
pub mod choice;
pub mod environment_sun;
pub mod error;
pub mod files;
pub mod input;
pub mod limits;
pub mod pass_id;
pub mod quality;
pub mod rays;
pub mod reference;
pub mod reference_gpu;
pub mod render;
pub mod scene;
pub mod shading;
pub mod time;
pub mod trace_input;
pub mod validate;
pub mod workflow;

pub use app::{App, FrameReport, FrameTarget, PostUpdate, SceneStats, Update};
pub use error::{Error, Result};
/// The wgpu version the renderer is built on, for embedding it in your own window code.
pub use wgpu;

/// What a script usually needs.
pub mod prelude {
    pub use crate::app::{App, FrameReport, Update};
    pub use crate::choice::Choice;
    pub use crate::input::{InputEvent, KeyCode, Keys, Mouse, MouseButton, MouseButtons};
    pub use crate::quality::{Quality, ShadowFilter, ShadowMask};
    pub use crate::render::post::debug_view::DebugView;
    pub use crate::scene::{
        AnimationPlayer, Background, Camera, Cascades, DirectionalLight, Environment,
        EnvironmentSource, EquirectImage, Exposure, GlobalTransform, IrradianceVolume, LightColor,
        LuminousIntensity, Material, Mesh3d, MeshHandle, Meshes, MorphTarget, MorphWeights,
        NotShadowCaster, NotShadowReceiver, PointLight, Projection, ReflectionProbe,
        ShadowSettings, SkinnedMesh, SpotLight, Transform,
    };
    pub use crate::shading::brdf::VisibilityModel;
    pub use crate::shading::color::Tonemapper;
    pub use crate::time::Time;
    pub use bevy_ecs::hierarchy::ChildOf;
    pub use bevy_ecs::prelude::*;
    pub use glam::{Quat, Vec2, Vec3, Vec4};
}

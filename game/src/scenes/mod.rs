//! The built-in demo and test scenes.

pub mod aliasing;
pub mod cornell;
mod dof;
mod extremes;
mod furnace;
mod lights;
pub mod materials;
mod plane;
mod shadows;
pub mod showcase;
pub mod spheres;

use lumen::App;

/// A built-in scene: a name, one line of description, and the function that spawns it.
pub struct SceneInfo {
    /// Name used with `--scene`.
    pub name: &'static str,
    /// One line for `lumen scenes`.
    pub description: &'static str,
    /// Spawns the scene's meshes, materials, lights and camera into the app.
    pub build: fn(&mut App) -> lumen::Result<()>,
}

/// Every built-in scene.
pub const SCENES: &[SceneInfo] = &[
    SceneInfo {
        name: "showcase",
        description: "the main job: the FlightHelmet and a row of material spheres under the sky.exr HDRI, its sun a 100 000 lx shadow-casting light",
        build: showcase::build,
    },
    SceneInfo {
        name: "spheres",
        description: "7x7 spheres, metallic rising bottom to top, roughness left to right; 4 point lights, a sun (the peer benchmark's scene)",
        build: spheres::build,
    },
    SceneInfo {
        name: "plane",
        description: "one flat plate lit by one directional light, seen head-on (GPU vs CPU BRDF check)",
        build: plane::build,
    },
    SceneInfo {
        name: "shadows",
        description: "a ground plane, a floating sphere, a cube and a pillar; a sun, a point and a spot light, each casting a shadow in view",
        build: shadows::build,
    },
    SceneInfo {
        name: "furnace",
        description: "white furnace: metal (F0 = 1) and white dielectric spheres, roughness 0..1, in a uniform environment of radiance 1",
        build: furnace::build,
    },
    SceneInfo {
        name: "dof",
        description: "striped panels at 1.8, 4 and 16 m through an 85 mm f/1.4 lens focused at 4 m: near, focused and far planes",
        build: dof::build,
    },
    SceneInfo {
        name: "lights",
        description: "many small point lights (256, or --lights N) of 3 m range over a field of blocks: light culling",
        build: lights::build,
    },
    SceneInfo {
        name: "cornell",
        description: "the Cornell box (published dimensions): red and green walls, two white blocks, a point light under the ceiling; colour bleeding",
        build: cornell::build,
    },
    SceneInfo {
        name: "aliasing",
        description: "what aliases worst: sub-pixel wires, rails towards the horizon, a fine checker floor, a bump-mapped sphere, sub-pixel highlights",
        build: aliasing::build,
    },
    SceneInfo {
        name: "materials",
        description: "one object per material feature: opaque, clear, absorbing and rough glass spheres, a thin glass pane, a dispersive block and a blended pane before a striped wall",
        build: materials::build,
    },
    SceneInfo {
        name: "extremes",
        description: "numerical torture: roughness 0, grazing view, a light 1 µm from a surface, 1e9 lux, degenerate lights and transforms",
        build: extremes::build,
    },
];

/// The scene called `name`, or an error that lists the available ones.
pub fn find(name: &str) -> Result<&'static SceneInfo, String> {
    SCENES.iter().find(|s| s.name == name).ok_or_else(|| {
        format!(
            "unknown scene '{name}' (built-in scenes: {})",
            SCENES.iter().map(|s| s.name).collect::<Vec<_>>().join(", ")
        )
    })
}

pub use cornell::{
    CORNELL_CAMERA, CORNELL_GREEN, CORNELL_LIGHT, CORNELL_RED, CORNELL_ROOM, CORNELL_WHITE,
};
pub use dof::{
    DOF_APERTURE, DOF_DISTANCES, DOF_FOCAL_LENGTH_MM, DOF_PANEL_FRACTION, DOF_SCREEN_X, DOF_STRIPES,
};
pub use furnace::{FURNACE_COLUMNS, FURNACE_RADIUS, furnace_center};
pub use lights::{LIGHTS_GROUND_M, LIGHTS_RANGE_M, LightsSceneOptions};
pub use plane::{PLANE_ILLUMINANCE_LUX, PLANE_LIGHT_DIRECTION, PLANE_MATERIAL};
pub use shadows::{
    SHADOWS_CAMERA, SHADOWS_CUBE, SHADOWS_FOV_DEG, SHADOWS_PILLAR, SHADOWS_POINT, SHADOWS_SPHERE,
    SHADOWS_SPOT, SHADOWS_SUN_FROM,
};
pub use spheres::{SPHERE_RADIUS, sphere_center, sphere_material};

//! `lights`: many small point lights over a field of blocks — the light-culling scene.
//! `LightsSceneOptions::count` lights (default 256, `--lights N`), each of range
//! `LIGHTS_RANGE_M`, hover in a jittered grid over a 40 × 40 m ground between 10 × 10
//! blocks and spheres, seen from above at an angle.

use lumen::assets::procedural::{cube, plane, uv_sphere};
use lumen::prelude::*;

/// How many point lights `lights` spawns (a resource read when the scene is built).
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct LightsSceneOptions {
    /// Number of point lights (0..=65536).
    pub count: u32,
}

impl Default for LightsSceneOptions {
    fn default() -> Self {
        LightsSceneOptions { count: 256 }
    }
}

/// Range of every light (m): its smooth window reaches 0 there.
pub const LIGHTS_RANGE_M: f32 = 3.0;
/// Side of the square ground (m).
pub const LIGHTS_GROUND_M: f32 = 40.0;

/// A small deterministic generator (xorshift) so the scene is the same on every run.
fn jitter(state: &mut u64) -> f32 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 40) as f32 / (1u64 << 24) as f32
}

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let count = app
        .world()
        .get_resource::<LightsSceneOptions>()
        .copied()
        .unwrap_or_default()
        .count
        .min(65_536);
    let ground = app.add_mesh(plane(LIGHTS_GROUND_M, LIGHTS_GROUND_M))?;
    let block = app.add_mesh(cube(1.0))?;
    let ball = app.add_mesh(uv_sphere(0.5, 24, 12))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.5), 0.0, 0.7),
        Transform::IDENTITY,
    ));
    let half = LIGHTS_GROUND_M * 0.5;
    for i in 0..10 {
        for j in 0..10 {
            let x = -half + 2.0 + i as f32 * 4.0;
            let z = -half + 2.0 + j as f32 * 4.0;
            let metal = ((i + j) % 3) as f32 * 0.5;
            let (mesh, y) = if (i + j) % 2 == 0 {
                (block, 0.5)
            } else {
                (ball, 0.5)
            };
            world.spawn((
                Mesh3d(mesh),
                Material::new(Vec3::new(0.8, 0.75, 0.7), metal, 0.35),
                Transform::from_xyz(x, y, z),
            ));
        }
    }
    // Lights on a jittered grid covering the ground, 0.4..1.4 m up, warm to cool.
    let side = (count as f32).sqrt().ceil().max(1.0) as u32;
    let step = LIGHTS_GROUND_M / side as f32;
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for k in 0..count {
        let (gx, gz) = ((k % side) as f32, (k / side) as f32);
        let x = -half + (gx + 0.2 + 0.6 * jitter(&mut state)) * step;
        let z = -half + (gz + 0.2 + 0.6 * jitter(&mut state)) * step;
        let y = 0.4 + jitter(&mut state);
        world.spawn((
            PointLight {
                intensity: LuminousIntensity::Lumens(800.0),
                color: LightColor::Kelvin(2700.0 + 5000.0 * jitter(&mut state)),
                range_m: LIGHTS_RANGE_M,
                ..PointLight::default()
            },
            Transform::from_xyz(x, y, z),
        ));
    }
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: 50f32.to_radians(),
                near_m: 0.1,
                far_m: 200.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(5.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 22.0, 30.0).looking_at(Vec3::new(0.0, 0.0, 2.0), Vec3::Y),
    ));
    Ok(())
}

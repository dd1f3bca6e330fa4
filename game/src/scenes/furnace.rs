//! `furnace`: the white furnace test (docs/src/formulas.md#numerical-guards). Spheres of roughness 0 to 1 in two
//! rows, metals of base colour 1 (F0 = 1) above and white dielectrics below, lit only by a
//! uniform environment of radiance 1 cd/m², no lights. With energy compensation and exposure
//! 1 every sphere reflects exactly the light it receives: the spheres vanish into the
//! background.

use lumen::assets::procedural::uv_sphere;
use lumen::prelude::*;

/// Number of spheres per row (roughness 0, 0.1, …, 1).
pub const FURNACE_COLUMNS: u32 = 11;

/// Centre of sphere `i` (roughness i/10) in row 0 (metal, top) or 1 (dielectric, bottom).
pub fn furnace_center(i: u32, row: u32) -> Vec3 {
    Vec3::new(i as f32 - 5.0, if row == 0 { 0.6 } else { -0.6 }, 0.0)
}

/// Sphere radius (m).
pub const FURNACE_RADIUS: f32 = 0.45;

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let sphere = app.add_mesh(uv_sphere(FURNACE_RADIUS, 64, 32))?;
    let world = app.world_mut();
    for i in 0..FURNACE_COLUMNS {
        let roughness = i as f32 / (FURNACE_COLUMNS - 1) as f32;
        for (row, metallic) in [(0, 1.0), (1, 0.0)] {
            world.spawn((
                Mesh3d(sphere),
                Material::new(Vec3::ONE, metallic, roughness),
                Transform::from_translation(furnace_center(i, row)),
            ));
        }
    }
    world.spawn(Environment::uniform(Vec3::ONE));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: 20f32.to_radians(),
                near_m: 0.5,
                far_m: 100.0,
                ..Projection::default()
            },
            exposure: Exposure::Linear(1.0),
            tonemapper: Tonemapper::None,
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 18.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    Ok(())
}

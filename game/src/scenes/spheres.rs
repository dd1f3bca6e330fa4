//! `spheres`: the peer benchmark's scene (the Bevy peer `bevy-spheres`, see docs/src/measured.md), object for
//! object, so that the two engines can be compared frame for frame.

use lumen::assets::procedural::{plane, uv_sphere};
use lumen::prelude::*;

/// Sphere radius in metres.
pub const SPHERE_RADIUS: f32 = 0.4;

/// Centre of the sphere in column `i` (roughness) and row `j` (metallic), 0..7.
pub fn sphere_center(i: u32, j: u32) -> Vec3 {
    Vec3::new(i as f32 - 3.0, j as f32 - 3.0, 0.0)
}

/// Material of sphere (i, j): grey 0.5, metallic j/6, roughness max(i/6, 0.05).
pub fn sphere_material(i: u32, j: u32) -> Material {
    Material::new(Vec3::splat(0.5), j as f32 / 6.0, (i as f32 / 6.0).max(0.05))
}

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let sphere = app.add_mesh(uv_sphere(SPHERE_RADIUS, 32, 16))?;
    let ground = app.add_mesh(plane(20.0, 20.0))?;
    let world = app.world_mut();
    for j in 0..7 {
        for i in 0..7 {
            world.spawn((
                Mesh3d(sphere),
                sphere_material(i, j),
                Transform::from_translation(sphere_center(i, j)),
            ));
        }
    }
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.5), 0.0, 0.8),
        Transform::from_xyz(0.0, -4.0, 0.0),
    ));
    // Irradiance probes around the spheres and down to the floor (the automatic volume
    // would cover the whole 20 m floor and spread them metres apart), in two layers
    // 0.6 m in front of and behind the spheres' plane at the default density.
    world.spawn(IrradianceVolume::new(
        Vec3::new(-3.5, -4.0, -1.2),
        Vec3::new(3.5, 3.0, 1.2),
    ));
    // One reflection probe among the spheres, half-way between the middle sphere and the
    // one below it (the automatic probe would sit inside the middle sphere), its box the
    // floor's 20 m × 20 m and up to the top row.
    world.spawn((
        ReflectionProbe::new(Vec3::new(10.0, 3.5, 10.0)),
        Transform::from_xyz(0.0, -0.5, 0.0),
    ));
    for (x, y) in [(-5.0, 5.0), (5.0, 5.0), (-5.0, -5.0), (5.0, -5.0)] {
        world.spawn((
            PointLight {
                intensity: LuminousIntensity::Lumens(1_000_000.0),
                range_m: 40.0,
                ..PointLight::default()
            },
            Transform::from_xyz(x, y, 10.0),
        ));
    }
    // The sun casts shadows like the peer's: one 2048² cascade out to 30 m.
    world.spawn((
        DirectionalLight {
            illuminance_lux: 10_000.0,
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        ShadowSettings {
            resolution: 2048,
            ..ShadowSettings::directional()
        },
        Cascades {
            count: 1,
            max_distance_m: 30.0,
            ..Cascades::default()
        },
        Transform::from_xyz(1.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: 45f32.to_radians(),
                near_m: 0.1,
                far_m: 100.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(9.7),
            tonemapper: Tonemapper::AcesFitted,
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 12.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    Ok(())
}

//! `shadows`: a ground plane, occluders of different sizes and heights, and one light of
//! each kind, each casting a shadow that is in view. The positions are public so that tests
//! can predict where each shadow falls.

use lumen::assets::procedural::{cuboid, plane, uv_sphere};
use lumen::prelude::*;

/// The floating sphere: centre (m) and radius (m). The sun's shadow.
pub const SHADOWS_SPHERE: (Vec3, f32) = (Vec3::new(-2.0, 1.6, 0.0), 0.7);
/// The cube resting on the ground: centre (m) and half size (m). The point light's shadow.
pub const SHADOWS_CUBE: (Vec3, f32) = (Vec3::new(3.0, 0.4, 1.0), 0.4);
/// The pillar: centre (m) and half extents (m). The spot light's shadow.
pub const SHADOWS_PILLAR: (Vec3, Vec3) = (Vec3::new(0.5, 1.25, -2.5), Vec3::new(0.3, 1.25, 0.3));
/// Where the sun shines from (towards the origin).
pub const SHADOWS_SUN_FROM: Vec3 = Vec3::new(1.0, 2.5, 1.0);
/// Point light position (m): behind the cube, so its shadow falls towards the camera.
pub const SHADOWS_POINT: Vec3 = Vec3::new(3.0, 1.5, -1.2);
/// Spot light position (m) and the point it aims at: behind the pillar.
pub const SHADOWS_SPOT: (Vec3, Vec3) = (Vec3::new(0.5, 4.0, -6.5), Vec3::new(0.5, 0.0, -1.0));
/// Camera position and target (m).
pub const SHADOWS_CAMERA: (Vec3, Vec3) = (Vec3::new(0.0, 7.0, 11.0), Vec3::new(0.0, 0.3, -0.5));
/// Camera vertical field of view.
pub const SHADOWS_FOV_DEG: f32 = 50.0;

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let ground = app.add_mesh(plane(30.0, 30.0))?;
    let sphere = app.add_mesh(uv_sphere(SHADOWS_SPHERE.1, 48, 24))?;
    let cube = app.add_mesh(cuboid(Vec3::splat(SHADOWS_CUBE.1 * 2.0)))?;
    let pillar = app.add_mesh(cuboid(SHADOWS_PILLAR.1 * 2.0))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.5), 0.0, 0.9),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::new(0.8, 0.3, 0.2), 0.0, 0.4),
        Transform::from_translation(SHADOWS_SPHERE.0),
    ));
    world.spawn((
        Mesh3d(cube),
        Material::new(Vec3::new(0.2, 0.5, 0.8), 0.0, 0.5),
        Transform::from_translation(SHADOWS_CUBE.0),
    ));
    world.spawn((
        Mesh3d(pillar),
        Material::new(Vec3::new(0.7, 0.7, 0.3), 0.0, 0.6),
        Transform::from_translation(SHADOWS_PILLAR.0),
    ));
    world.spawn((
        DirectionalLight {
            illuminance_lux: 3_000.0,
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        Transform::from_translation(SHADOWS_SUN_FROM).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        PointLight {
            intensity: LuminousIntensity::Lumens(300_000.0),
            range_m: 25.0,
            cast_shadows: true,
            color: LightColor::Kelvin(3000.0),
            ..PointLight::default()
        },
        Transform::from_translation(SHADOWS_POINT),
    ));
    world.spawn((
        SpotLight {
            intensity: LuminousIntensity::Lumens(200_000.0),
            range_m: 25.0,
            inner_angle_rad: 0.3,
            outer_angle_rad: 0.5,
            cast_shadows: true,
            color: LightColor::Kelvin(7500.0),
            ..SpotLight::default()
        },
        Transform::from_translation(SHADOWS_SPOT.0).looking_at(SHADOWS_SPOT.1, Vec3::Y),
    ));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: SHADOWS_FOV_DEG.to_radians(),
                near_m: 0.1,
                far_m: 100.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(10.0),
            ..Camera::default()
        },
        Transform::from_translation(SHADOWS_CAMERA.0).looking_at(SHADOWS_CAMERA.1, Vec3::Y),
    ));
    Ok(())
}

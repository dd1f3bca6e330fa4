//! `plane`: a square plate facing the camera, lit by one directional light — the case the
//! GPU-vs-CPU BRDF test compares pixel for pixel with `lumen::shading::brdf`.

use lumen::assets::procedural::plane;
use lumen::prelude::*;

/// The plate's material.
pub const PLANE_MATERIAL: Material = Material {
    base_color: Vec4::new(0.8, 0.5, 0.3, 1.0),
    metallic: 0.25,
    perceptual_roughness: 0.4,
    specular_level: 0.5,
    emissive: Vec3::ZERO,
    occlusion: 1.0,
    double_sided: false,
    blend: false,
    transmission: None,
    unlit: false,
    clearcoat: None,
    sheen: None,
    anisotropy: None,
    specular_tint: Vec3::ONE,
    iridescence: None,
    diffuse_transmission: None,
};

/// Illuminance of the light in lux.
pub const PLANE_ILLUMINANCE_LUX: f32 = 2000.0;

/// Direction from the plate towards the light (not normalised).
pub const PLANE_LIGHT_DIRECTION: Vec3 = Vec3::new(0.3, 0.4, 1.0);

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let mesh = app.add_mesh(plane(4.0, 4.0))?;
    let world = app.world_mut();
    // The plane faces +Y; turn it to face +Z (the camera).
    world.spawn((
        Mesh3d(mesh),
        PLANE_MATERIAL,
        Transform::IDENTITY.with_rotation(Quat::from_rotation_x(std::f32::consts::FRAC_PI_2)),
    ));
    world.spawn((
        DirectionalLight {
            illuminance_lux: PLANE_ILLUMINANCE_LUX,
            ..DirectionalLight::default()
        },
        Transform::from_translation(PLANE_LIGHT_DIRECTION).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            exposure: Exposure::Linear(1.0 / 1000.0),
            projection: Projection {
                fov_y_rad: 30f32.to_radians(),
                ..Projection::default()
            },
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    Ok(())
}

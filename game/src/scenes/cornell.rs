//! `cornell`: the Cornell box, with the dimensions of the Cornell University Program of
//! Computer Graphics' published measurements (a room about 0.55 m on a side, mm → m). A red
//! wall on the left, a green one on the right, white floor, ceiling and back wall, a short
//! and a tall white block turned about 17°, and one light just under the ceiling's
//! centre. It is where colour bleeding (light bounced off the red and green walls onto
//! the white ones) shows.
//!
//! The original light is a 130 × 105 mm emitter in the ceiling. Lumen's lights are points,
//! spots and suns, so the light is a shadow-casting point light 2 cm below the ceiling,
//! where both the rasterizer and the path tracer see the same light. The reflectances are
//! the usual RGB fits of the measured spectra (as in Mitsuba's and pbrt's scenes).

use lumen::assets::procedural::{cuboid, plane};
use lumen::prelude::*;

/// Width (x), height (y) and depth (z) of the room (m).
pub const CORNELL_ROOM: Vec3 = Vec3::new(0.556, 0.5488, 0.5592);
/// Reflectance of the white surfaces (linear RGB).
pub const CORNELL_WHITE: Vec3 = Vec3::new(0.725, 0.71, 0.68);
/// Reflectance of the red wall, at x = [`CORNELL_ROOM`].x (linear RGB).
pub const CORNELL_RED: Vec3 = Vec3::new(0.63, 0.065, 0.05);
/// Reflectance of the green wall, at x = 0 (linear RGB).
pub const CORNELL_GREEN: Vec3 = Vec3::new(0.14, 0.45, 0.091);
/// The light's position (m) and luminous intensity (cd).
pub const CORNELL_LIGHT: (Vec3, f32) = (Vec3::new(0.278, 0.5288, 0.2796), 5.0);
/// The camera: position (m), target (m) and vertical field of view (degrees: a 35 mm lens
/// on a 25 mm sensor).
pub const CORNELL_CAMERA: (Vec3, Vec3, f32) = (
    Vec3::new(0.278, 0.273, -0.8),
    Vec3::new(0.278, 0.273, 0.2796),
    39.3,
);

fn matte(color: Vec3) -> Material {
    Material {
        double_sided: true,
        ..Material::new(color, 0.0, 1.0)
    }
}

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let room = CORNELL_ROOM;
    let floor = app.add_mesh(plane(room.x, room.z))?;
    let side = app.add_mesh(plane(room.y, room.z))?;
    let back = app.add_mesh(plane(room.x, room.y))?;
    let short_block = app.add_mesh(cuboid(Vec3::new(0.165, 0.165, 0.165)))?;
    let tall_block = app.add_mesh(cuboid(Vec3::new(0.165, 0.33, 0.165)))?;
    let centre = room * 0.5;
    let world = app.world_mut();
    let quarter = std::f32::consts::FRAC_PI_2;
    for (mesh, color, transform) in [
        // Floor (facing +y) and ceiling (facing −y).
        (
            floor,
            CORNELL_WHITE,
            Transform::from_xyz(centre.x, 0.0, centre.z),
        ),
        (
            floor,
            CORNELL_WHITE,
            Transform::from_xyz(centre.x, room.y, centre.z)
                .with_rotation(Quat::from_rotation_x(2.0 * quarter)),
        ),
        // Back wall, facing −z (towards the camera).
        (
            back,
            CORNELL_WHITE,
            Transform::from_xyz(centre.x, centre.y, room.z)
                .with_rotation(Quat::from_rotation_x(-quarter)),
        ),
        // Red wall at x = room.x facing −x; green wall at x = 0 facing +x.
        (
            side,
            CORNELL_RED,
            Transform::from_xyz(room.x, centre.y, centre.z)
                .with_rotation(Quat::from_rotation_z(quarter)),
        ),
        (
            side,
            CORNELL_GREEN,
            Transform::from_xyz(0.0, centre.y, centre.z)
                .with_rotation(Quat::from_rotation_z(-quarter)),
        ),
        // The blocks: centres from the published corner coordinates.
        (
            short_block,
            CORNELL_WHITE,
            Transform::from_xyz(0.1855, 0.0825, 0.169)
                .with_rotation(Quat::from_rotation_y(-17f32.to_radians())),
        ),
        (
            tall_block,
            CORNELL_WHITE,
            Transform::from_xyz(0.3685, 0.165, 0.3513)
                .with_rotation(Quat::from_rotation_y(17f32.to_radians())),
        ),
    ] {
        world.spawn((Mesh3d(mesh), matte(color), transform));
    }
    world.spawn((
        PointLight {
            intensity: LuminousIntensity::Candela(CORNELL_LIGHT.1),
            range_m: 10.0,
            cast_shadows: true,
            ..PointLight::default()
        },
        Transform::from_translation(CORNELL_LIGHT.0),
    ));
    let (eye, target, fov_deg) = CORNELL_CAMERA;
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: fov_deg.to_radians(),
                near_m: 0.01,
                far_m: 10.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(3.5),
            ..Camera::default()
        },
        Transform::from_translation(eye).looking_at(target, Vec3::Y),
    ));
    Ok(())
}

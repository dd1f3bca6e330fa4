//! `dof`: striped panels spread over depth — one in front of the focus plane, one on it,
//! one far behind — seen through an 85 mm f/1.4 lens focused on the middle one, so that
//! near, focused and far planes are all visible. The panels' fine stripes show how much
//! detail each plane keeps.

use lumen::assets::procedural::{cuboid, plane, uv_sphere};
use lumen::prelude::*;
use lumen::scene::{DepthOfField, Lens};

/// Distance of the near, focused and far panels from the camera (m).
pub const DOF_DISTANCES: [f32; 3] = [1.8, 4.0, 16.0];
/// Horizontal position of each panel's centre as a fraction of the half-width of the view
/// at its distance (−1 left edge, 1 right edge).
pub const DOF_SCREEN_X: [f32; 3] = [-0.55, 0.0, 0.55];
/// Each panel's height as a fraction of the view's height at its distance.
pub const DOF_PANEL_FRACTION: f32 = 0.5;
/// Stripes per panel.
pub const DOF_STRIPES: u32 = 24;
/// The camera: 85 mm on a full-frame (24 mm) sensor at f/1.4, focused on the middle panel.
pub const DOF_FOCAL_LENGTH_MM: f32 = 85.0;
/// Aperture f-number.
pub const DOF_APERTURE: f32 = 1.4;

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let lens = Lens {
        aperture_f_stops: DOF_APERTURE,
        focus_distance_m: DOF_DISTANCES[1],
        ..Lens::default()
    };
    let fov = lens.fov_for_focal_length(DOF_FOCAL_LENGTH_MM);
    let ground = app.add_mesh(plane(200.0, 200.0))?;
    let bar = app.add_mesh(cuboid(Vec3::ONE))?;
    let ball = app.add_mesh(uv_sphere(1.0, 32, 16))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.35), 0.0, 0.9),
        Transform::from_xyz(0.0, -1.0, 0.0),
    ));
    let aspect = 16.0 / 9.0;
    for (k, &d) in DOF_DISTANCES.iter().enumerate() {
        let half_h = d * (fov * 0.5).tan();
        let height = 2.0 * half_h * DOF_PANEL_FRACTION;
        let width = height;
        let center = Vec3::new(DOF_SCREEN_X[k] * half_h * aspect, 0.0, -d);
        let stripe = width / DOF_STRIPES as f32;
        for i in 0..DOF_STRIPES {
            let x = center.x - width * 0.5 + (i as f32 + 0.5) * stripe;
            let bright = i % 2 == 0;
            world.spawn((
                Mesh3d(bar),
                Material::new(Vec3::splat(if bright { 0.85 } else { 0.04 }), 0.0, 0.7),
                Transform::from_xyz(x, center.y, center.z).with_scale(Vec3::new(
                    stripe,
                    height,
                    stripe * 0.2,
                )),
            ));
        }
        // A ball beside each panel, on the ground.
        world.spawn((
            Mesh3d(ball),
            Material::new(Vec3::new(0.8, 0.25, 0.1), 0.0, 0.3),
            Transform::from_xyz(center.x + width * 0.8, -1.0 + d * 0.04, center.z)
                .with_scale(Vec3::splat(d * 0.04)),
        ));
    }
    world.spawn((
        DirectionalLight {
            illuminance_lux: 20_000.0,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(-1.0, 3.0, 2.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn(Environment::uniform(Vec3::splat(2000.0)));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: fov,
                near_m: 0.2,
                far_m: 500.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(12.5),
            lens,
            depth_of_field: Some(DepthOfField::default()),
            ..Camera::default()
        },
        Transform::IDENTITY,
    ));
    Ok(())
}

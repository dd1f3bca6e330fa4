//! `aliasing`: what aliases worst, for measuring anti-aliasing. Wires thinner than a
//! pixel against a bright sky, bars on the floor running towards the horizon at grazing
//! angles, a fine checker floor, a sphere with a high-frequency normal map, and small
//! mirror-smooth spheres whose highlights from a small bright light are smaller than a
//! pixel. The path tracer renders the same scene (textures included).

use lumen::assets::procedural::{cuboid, plane, uv_sphere};
use lumen::prelude::*;
use lumen::scene::{
    ColorSpace, Filter, MaterialMaps, Sampler, TextureData, TextureSlot, UvTransform,
};

/// Camera position and target (m).
pub const ALIASING_CAMERA: (Vec3, Vec3) = (Vec3::new(0.0, 1.6, 6.0), Vec3::new(0.0, 0.8, 0.0));
/// Camera vertical field of view.
pub const ALIASING_FOV_DEG: f32 = 50.0;
/// The normal-mapped sphere: centre and radius (m).
pub const ALIASING_BUMPY_SPHERE: (Vec3, f32) = (Vec3::new(1.7, 0.8, 0.0), 0.8);
/// Checker squares along each side of the 40 m floor.
pub const ALIASING_CHECKERS: u32 = 80;
/// Bumps along the normal-mapped sphere's equator.
pub const ALIASING_BUMPS: u32 = 48;

/// A checker texture of `squares` × `squares` squares of `texels` texels each, light and
/// dark grey (sRGB).
pub fn checker(squares: u32, texels: u32) -> TextureData {
    let side = squares * texels;
    let mut rgba8 = Vec::with_capacity((side * side * 4) as usize);
    for y in 0..side {
        for x in 0..side {
            let v = if (x / texels + y / texels).is_multiple_of(2) {
                200
            } else {
                40
            };
            rgba8.extend_from_slice(&[v, v, v, 255]);
        }
    }
    TextureData {
        width: side,
        height: side,
        rgba8,
        color_space: ColorSpace::Srgb,
    }
}

/// A tangent-space normal map of `bumps` × `bumps / 2` egg-crate bumps over the sphere's
/// (u, v): height h = a sin(2π b u) sin(π b v), normal ∝ (−∂h/∂u, −∂h/∂v, 1).
pub fn bump_map(bumps: u32, width: u32) -> TextureData {
    let height = width / 2;
    let (b, a) = (bumps as f32, 0.004f32);
    let mut rgba8 = Vec::with_capacity((width * height * 4) as usize);
    let tau = std::f32::consts::TAU;
    for y in 0..height {
        for x in 0..width {
            let u = (x as f32 + 0.5) / width as f32;
            let v = (y as f32 + 0.5) / height as f32;
            let dh_du = a * tau * b * (tau * b * u).cos() * (0.5 * tau * b * v).sin();
            let dh_dv = a * 0.5 * tau * b * (tau * b * u).sin() * (0.5 * tau * b * v).cos();
            let n = Vec3::new(-dh_du, -dh_dv, 1.0).normalize();
            let code = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
            rgba8.extend_from_slice(&[code(n.x), code(n.y), code(n.z), 255]);
        }
    }
    TextureData {
        width,
        height,
        rgba8,
        color_space: ColorSpace::Linear,
    }
}

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let floor = app.add_mesh(plane(40.0, 40.0))?;
    let wire = app.add_mesh(cuboid(Vec3::new(9.0, 0.012, 0.012)))?;
    let pole = app.add_mesh(cuboid(Vec3::new(0.02, 3.0, 0.02)))?;
    let rail = app.add_mesh(cuboid(Vec3::new(0.03, 0.03, 16.0)))?;
    let bumpy = app.add_mesh(uv_sphere(ALIASING_BUMPY_SPHERE.1, 96, 48))?;
    let bead = app.add_mesh(uv_sphere(0.12, 32, 16))?;
    let checker = app.add_texture(checker(8, 8))?;
    let normal = app.add_texture(bump_map(ALIASING_BUMPS, 512))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::ONE, 0.0, 0.5),
        MaterialMaps {
            base_color: Some(TextureSlot {
                sampler: Sampler {
                    mag: Filter::Nearest,
                    ..Sampler::default()
                },
                transform: UvTransform {
                    scale: Vec2::splat(ALIASING_CHECKERS as f32 / 8.0),
                    ..UvTransform::default()
                },
                ..TextureSlot::new(checker)
            }),
            ..MaterialMaps::default()
        },
        Transform::IDENTITY,
    ));
    // Wires across the view, slightly turned, at three depths.
    for (i, (y, z, yaw, roll)) in [
        (2.2f32, -1.0f32, 6f32, 2f32),
        (1.5, 1.0, -4.0, -3.0),
        (2.8, -4.0, 2.0, 5.0),
    ]
    .into_iter()
    .enumerate()
    {
        world.spawn((
            Mesh3d(wire),
            Material::new(Vec3::splat(0.05), if i == 1 { 1.0 } else { 0.0 }, 0.3),
            Transform::from_translation(Vec3::new(0.0, y, z)).with_rotation(
                Quat::from_rotation_y(yaw.to_radians()) * Quat::from_rotation_z(roll.to_radians()),
            ),
        ));
    }
    // Poles leaning by a few degrees.
    for (x, z, lean) in [
        (-3.2f32, -2.0f32, 7f32),
        (-2.6, -0.5, -4.0),
        (3.4, -3.0, 3.0),
    ] {
        world.spawn((
            Mesh3d(pole),
            Material::new(Vec3::splat(0.08), 0.0, 0.5),
            Transform::from_translation(Vec3::new(x, 1.5, z))
                .with_rotation(Quat::from_rotation_z(lean.to_radians())),
        ));
    }
    // Rails on the floor running towards the horizon.
    for (x, yaw) in [(-1.2f32, 14f32), (-0.6, 9.0), (0.3, -6.0)] {
        world.spawn((
            Mesh3d(rail),
            Material::new(Vec3::new(0.9, 0.85, 0.8), 1.0, 0.2),
            Transform::from_translation(Vec3::new(x, 0.015, -6.0))
                .with_rotation(Quat::from_rotation_y(yaw.to_radians())),
        ));
    }
    world.spawn((
        Mesh3d(bumpy),
        Material::new(Vec3::new(0.95, 0.75, 0.45), 1.0, 0.2),
        MaterialMaps {
            normal: Some(TextureSlot::new(normal)),
            ..MaterialMaps::default()
        },
        Transform::from_translation(ALIASING_BUMPY_SPHERE.0),
    ));
    // Mirror-smooth beads: highlights smaller than a pixel.
    for i in 0..5 {
        world.spawn((
            Mesh3d(bead),
            Material::new(Vec3::new(0.95, 0.95, 0.95), 1.0, 0.05),
            Transform::from_translation(Vec3::new(-1.9 + 0.45 * i as f32, 0.12, 1.8)),
        ));
    }
    world.spawn((
        DirectionalLight {
            illuminance_lux: 10_000.0,
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        Transform::from_translation(Vec3::new(-1.0, 2.0, 1.5)).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        PointLight {
            intensity: LuminousIntensity::Lumens(20_000.0),
            range_m: 20.0,
            radius_m: 0.01,
            cast_shadows: false,
            ..PointLight::default()
        },
        Transform::from_translation(Vec3::new(-0.5, 1.2, 3.5)),
    ));
    world.spawn(Environment::uniform(Vec3::new(1500.0, 1700.0, 2000.0)));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: ALIASING_FOV_DEG.to_radians(),
                near_m: 0.1,
                far_m: 100.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(10.5),
            ..Camera::default()
        },
        Transform::from_translation(ALIASING_CAMERA.0).looking_at(ALIASING_CAMERA.1, Vec3::Y),
    ));
    Ok(())
}

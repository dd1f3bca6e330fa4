//! `extremes`: every case of docs/src/formulas.md#numerical-guards that direct lighting can meet, in one frame.
//! It must render finite (no NaN, no Inf) everywhere.

use lumen::assets::procedural::{cube, plane, uv_sphere};
use lumen::prelude::*;

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let ground = app.add_mesh(plane(40.0, 40.0))?;
    let sphere = app.add_mesh(uv_sphere(0.5, 48, 24))?;
    let block = app.add_mesh(cube(1.0))?;
    let world = app.world_mut();
    // A perfect mirror (roughness 0, metal F0 = 1) seen at a grazing angle.
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::ONE, 1.0, 0.0),
        Transform::IDENTITY,
    ));
    // Roughness exactly 0 and 1, dielectric and metal.
    for (k, (metallic, roughness)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
        .into_iter()
        .enumerate()
    {
        world.spawn((
            Mesh3d(sphere),
            Material::new(Vec3::ONE, metallic, roughness),
            Transform::from_xyz(k as f32 * 1.2 - 1.8, 0.5, 0.0),
        ));
    }
    // Out-of-range and non-finite material values.
    world.spawn((
        Mesh3d(block),
        Material {
            base_color: Vec4::new(f32::NAN, 2.0, -1.0, 1.0),
            metallic: f32::INFINITY,
            perceptual_roughness: f32::NAN,
            specular_level: -3.0,
            emissive: Vec3::new(1e9, f32::INFINITY, -5.0),
            occlusion: f32::NAN,
            double_sided: true,
            blend: false,
            transmission: None,
            unlit: false,
            clearcoat: None,
            sheen: None,
            anisotropy: None,
            specular_tint: Vec3::ONE,
            iridescence: None,
            diffuse_transmission: None,
        },
        Transform::from_xyz(2.5, 0.5, -1.0),
    ));
    // A zero-scale (degenerate) instance.
    world.spawn((
        Mesh3d(block),
        Material::default(),
        Transform::from_xyz(0.0, 1.0, 0.0).with_scale(Vec3::ZERO),
    ));
    // 1e9 lux, nearly along the surface.
    world.spawn((
        DirectionalLight {
            illuminance_lux: 1e9,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(1.0, 0.001, 0.2).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // A point light 1 µm above the mirror, and one inside a sphere's surface.
    world.spawn((
        PointLight {
            intensity: LuminousIntensity::Candela(1e7),
            range_m: 50.0,
            ..PointLight::default()
        },
        Transform::from_xyz(0.3, 1e-6, 1.0),
    ));
    world.spawn((
        PointLight {
            intensity: LuminousIntensity::Lumens(f32::INFINITY),
            range_m: 0.0,
            ..PointLight::default()
        },
        Transform::from_xyz(-1.8, 1.0, 0.0),
    ));
    // A spot with inner = outer cone, pointing straight down, and one with NaN angles.
    world.spawn((
        SpotLight {
            intensity: LuminousIntensity::Lumens(1e8),
            inner_angle_rad: 0.4,
            outer_angle_rad: 0.4,
            range_m: f32::INFINITY,
            ..SpotLight::default()
        },
        Transform::from_xyz(0.0, 3.0, 0.0).looking_at(Vec3::ZERO, Vec3::Z),
    ));
    world.spawn((
        SpotLight {
            intensity: LuminousIntensity::Candela(1e6),
            inner_angle_rad: f32::NAN,
            outer_angle_rad: f32::NAN,
            color: LightColor::Kelvin(f32::NAN),
            ..SpotLight::default()
        },
        Transform::from_xyz(1.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // Grazing view: the eye 2 cm above the mirror, looking along it.
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(15.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.02, 6.0).looking_at(Vec3::new(0.0, 0.0, -10.0), Vec3::Y),
    ));
    Ok(())
}

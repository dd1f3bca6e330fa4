//! `materials`: one object per material feature beyond the metal/roughness base, in a row
//! on a grey floor in front of a striped wall (the stripes show refraction), under a
//! uniform sky and a shadow-casting sun. Left to right:
//!
//! 1. an opaque white dielectric sphere, for comparison;
//! 2. a clear glass sphere (`KHR_materials_transmission` + `_volume`, IOR 1.5, thickness
//!    its diameter): the stripes behind it refracted;
//! 3. a green absorbing glass sphere (its attenuation colour over 0.6 m, Beer–Lambert);
//! 4. a rough glass sphere (roughness 0.35): the stripes blurred;
//! 5. a thin-walled glass pane (thickness 0): the stripes through it unbent;
//! 6. a dispersive glass block turned 45° (`KHR_materials_dispersion` 5, Abbe number 4):
//!    the stripes' edges split into colours;
//! 7. an alpha-blended red pane (`alphaMode: BLEND`, α 0.4);
//! 8. a car-paint sphere: a red base, half metal, roughness 0.5, under a whole,
//!    nearly smooth clearcoat (`KHR_materials_clearcoat`, coat roughness 0.05): a sharp
//!    reflection over a soft highlight;
//! 9. a velvet sphere: a dark blue rough base under a light blue sheen
//!    (`KHR_materials_sheen`, colour (0.5, 0.6, 0.9), roughness 0.4): a bright rim;
//! 10. a brushed-metal sphere: pale gold, roughness 0.3, anisotropy 0.8 along its
//!     tangents (`KHR_materials_anisotropy`), which run around it: its highlights are
//!     drawn out into arcs around the sphere;
//! 11. a dark dielectric sphere with a coloured specular reflection
//!     (`KHR_materials_specular`: specular level 1, colour (1, 0.55, 0.15)): orange
//!     highlights and reflections over a nearly black base;
//! 12. an iridescent sphere: a nearly black dielectric under a whole 400 nm film of
//!     index 1.3 (`KHR_materials_iridescence`): its reflection shifts in colour from the
//!     centre to the rim;
//! 13. a translucent leaf: a thin green pane that transmits 70 % of its diffuse light in
//!     yellow-green (`KHR_materials_diffuse_transmission`, colour (0.7, 0.9, 0.2)),
//!     turned so that the camera sees the side the sun does not reach: it is lit through.
//!
//! In front of the row, two smaller spheres: an unlit orange one (`KHR_materials_unlit`:
//! its base colour as it is, whatever the light) on the left, and a glowing one on the
//! right whose emission (`KHR_materials_emissive_strength`: colour (1, 0.6, 0.25) ×
//! strength 2000, in cd/m²) is brighter than any lit surface.
//!
//! docs/src/materials.md describes each.

use lumen::assets::procedural::{cuboid, plane, uv_sphere};
use lumen::prelude::*;
use lumen::scene::{Anisotropy, Clearcoat, DiffuseTransmission, Iridescence, Sheen, Transmission};

/// The objects' x positions (m), left to right, at the floor's centre line z = 0.
pub const MATERIALS_X: [f32; 13] = [
    -3.96, -3.3, -2.64, -1.98, -1.32, -0.66, 0.0, 0.66, 1.32, 1.98, 2.64, 3.3, 3.96,
];
/// The translucent leaf's normal (unit): towards the camera's side, away from the sun.
pub const LEAF_NORMAL: Vec3 = Vec3::new(-0.9363292, -0.2808988, 0.2106741);
/// Radius of the spheres (m).
pub const MATERIALS_RADIUS: f32 = 0.32;
/// The centres of the unlit (left) and emissive (right) spheres in front of the row (m).
pub const FRONT_ROW: [Vec3; 2] = [
    Vec3::new(-1.65, FRONT_RADIUS, 0.9),
    Vec3::new(1.65, FRONT_RADIUS, 0.9),
];
/// Radius of the two spheres in front of the row (m).
pub const FRONT_RADIUS: f32 = 0.2;
/// The unlit sphere's base colour (linear).
pub const UNLIT_COLOR: Vec3 = Vec3::new(0.9, 0.45, 0.1);
/// The glowing sphere's emitted luminance (cd/m²): glTF's emissive factor (1, 0.6,
/// 0.25) × `KHR_materials_emissive_strength` 2000.
pub const EMISSION: Vec3 = Vec3::new(2000.0, 1200.0, 500.0);

fn glass(tint: Vec3, distance_m: f32, roughness: f32, thickness_m: f32) -> Material {
    Material {
        transmission: Some(Transmission {
            factor: 1.0,
            ior: 1.5,
            thickness_m,
            attenuation_color: tint,
            attenuation_distance_m: distance_m,
            dispersion: 0.0,
        }),
        ..Material::new(Vec3::ONE, 0.0, roughness)
    }
}

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let floor = app.add_mesh(plane(12.0, 8.0))?;
    let stripe = app.add_mesh(cuboid(Vec3::new(0.25, 3.0, 0.05)))?;
    let sphere = app.add_mesh(uv_sphere(MATERIALS_RADIUS, 48, 24))?;
    let pane = app.add_mesh(cuboid(Vec3::new(0.6, 0.8, 0.02)))?;
    let block = app.add_mesh(cuboid(Vec3::new(0.45, 0.8, 0.25)))?;
    let diameter = 2.0 * MATERIALS_RADIUS;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::splat(0.5), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    // Alternating dark and light stripes along the back wall, 1.5 m behind the row.
    for k in 0..24 {
        let light = k % 2 == 0;
        let colour = if light {
            Vec3::new(0.85, 0.8, 0.7)
        } else {
            Vec3::new(0.05, 0.07, 0.12)
        };
        world.spawn((
            Mesh3d(stripe),
            Material::new(colour, 0.0, 0.7),
            Transform::from_xyz(-2.875 + 0.25 * k as f32, 1.5, -1.5),
        ));
    }
    let objects = [
        Material::new(Vec3::splat(0.8), 0.0, 0.3),
        glass(Vec3::ONE, f32::INFINITY, 0.0, diameter),
        glass(Vec3::new(0.2, 0.8, 0.35), 0.6, 0.0, diameter),
        glass(Vec3::ONE, f32::INFINITY, 0.35, diameter),
    ];
    for (x, material) in MATERIALS_X.iter().zip(objects) {
        world.spawn((
            Mesh3d(sphere),
            material,
            Transform::from_xyz(*x, MATERIALS_RADIUS + 0.01, 0.0),
        ));
    }
    world.spawn((
        Mesh3d(pane),
        glass(Vec3::ONE, f32::INFINITY, 0.0, 0.0),
        Transform::from_xyz(MATERIALS_X[4], 0.41, 0.0),
    ));
    let mut dispersive = glass(Vec3::ONE, f32::INFINITY, 0.0, 0.3);
    if let Some(t) = dispersive.transmission.as_mut() {
        t.dispersion = 5.0;
    }
    world.spawn((
        Mesh3d(block),
        dispersive,
        Transform::from_xyz(MATERIALS_X[5], 0.41, 0.0)
            .with_rotation(Quat::from_rotation_y(std::f32::consts::FRAC_PI_4)),
    ));
    let mut red = Material::new(Vec3::new(0.9, 0.1, 0.1), 0.0, 0.3);
    red.base_color.w = 0.4;
    red.blend = true;
    world.spawn((
        Mesh3d(pane),
        red,
        Transform::from_xyz(MATERIALS_X[6], 0.41, 0.0),
    ));
    world.spawn((
        Mesh3d(sphere),
        Material {
            clearcoat: Some(Clearcoat {
                factor: 1.0,
                perceptual_roughness: 0.05,
            }),
            ..Material::new(Vec3::new(0.6, 0.02, 0.03), 0.5, 0.5)
        },
        Transform::from_xyz(MATERIALS_X[7], MATERIALS_RADIUS + 0.01, 0.0),
    ));
    world.spawn((
        Mesh3d(sphere),
        Material {
            sheen: Some(Sheen {
                color: Vec3::new(0.5, 0.6, 0.9),
                perceptual_roughness: 0.4,
            }),
            ..Material::new(Vec3::new(0.02, 0.03, 0.12), 0.0, 0.9)
        },
        Transform::from_xyz(MATERIALS_X[8], MATERIALS_RADIUS + 0.01, 0.0),
    ));
    world.spawn((
        Mesh3d(sphere),
        Material {
            anisotropy: Some(Anisotropy {
                strength: 0.8,
                rotation_rad: 0.0,
            }),
            ..Material::new(Vec3::new(0.95, 0.8, 0.55), 1.0, 0.3)
        },
        Transform::from_xyz(MATERIALS_X[9], MATERIALS_RADIUS + 0.01, 0.0),
    ));
    world.spawn((
        Mesh3d(sphere),
        Material {
            specular_level: 1.0,
            specular_tint: Vec3::new(1.0, 0.55, 0.15),
            ..Material::new(Vec3::new(0.02, 0.02, 0.03), 0.0, 0.25)
        },
        Transform::from_xyz(MATERIALS_X[10], MATERIALS_RADIUS + 0.01, 0.0),
    ));
    world.spawn((
        Mesh3d(sphere),
        Material {
            iridescence: Some(Iridescence::default()),
            ..Material::new(Vec3::splat(0.03), 0.0, 0.2)
        },
        Transform::from_xyz(MATERIALS_X[11], MATERIALS_RADIUS + 0.01, 0.0),
    ));
    let leaf = app.add_mesh(plane(0.55, 0.7))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(leaf),
        Material {
            double_sided: true,
            diffuse_transmission: Some(DiffuseTransmission {
                factor: 0.7,
                color: Vec3::new(0.7, 0.9, 0.2),
            }),
            ..Material::new(Vec3::new(0.08, 0.3, 0.04), 0.0, 0.6)
        },
        Transform::from_xyz(MATERIALS_X[12], 0.4, 0.0)
            .with_rotation(Quat::from_rotation_arc(Vec3::Y, LEAF_NORMAL)),
    ));
    let small = app.add_mesh(uv_sphere(FRONT_RADIUS, 32, 16))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(small),
        Material {
            unlit: true,
            ..Material::new(UNLIT_COLOR, 0.0, 0.5)
        },
        Transform::from_translation(FRONT_ROW[0]),
    ));
    world.spawn((
        Mesh3d(small),
        Material {
            emissive: EMISSION,
            ..Material::new(Vec3::splat(0.05), 0.0, 0.5)
        },
        Transform::from_translation(FRONT_ROW[1]),
    ));
    world.spawn(Environment::uniform(Vec3::new(400.0, 500.0, 700.0)));
    world.spawn((
        DirectionalLight {
            illuminance_lux: 3_000.0,
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(1.0, 3.0, 2.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: 47f32.to_radians(),
                near_m: 0.1,
                far_m: 50.0,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(10.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.9, 6.0).looking_at(Vec3::new(0.0, 0.6, -0.5), Vec3::Y),
    ));
    Ok(())
}

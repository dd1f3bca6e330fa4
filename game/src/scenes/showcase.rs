//! `showcase`: the main job's scene, Lumen at its best. The CC0 FlightHelmet on a floor,
//! a row of material spheres behind it (gold, copper and aluminium at three
//! roughnesses on the left; a glossy red plastic, a rough white one and clear glass on
//! the right), under the `sky.exr` HDRI. The HDRI's sun is taken out of the image and
//! becomes a shadow-casting directional light of 100 000 lx (see
//! [`lumen::environment_sun`]); the sky keeps its own light, and the camera is
//! exposed for a sunny day (EV100 15). The quality is whatever the command line says,
//! `high` by default, with every feature it turns on.

use lumen::assets::gltf::{GltfOptions, load_gltf_with};
use lumen::assets::procedural::{plane, uv_sphere};
use lumen::environment_sun::split_sun;
use lumen::prelude::*;
use lumen::scene::Transmission;
use lumen::shading::color::luminance;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The model at the centre, under `assets/`.
pub const SHOWCASE_MODEL: &str = "models/FlightHelmet/FlightHelmet.gltf";
/// The environment, under `assets/`.
pub const SHOWCASE_HDRI: &str = "hdri/sky.exr";
/// Illuminance of the HDRI's sun once taken out (lx): a clear day's direct sun.
pub const SUN_LUX: f32 = 100_000.0;
/// Azimuth the sun is turned to, atan2(x, z) of its direction (rad): front left, the
/// camera being front right.
pub const SUN_AZIMUTH_RAD: f32 = -0.75;
/// Exposure for the sunlit scene (EV100): the "sunny 16" rule.
pub const SHOWCASE_EV100: f32 = 15.0;

/// `assets/<relative>` under the working directory, else under the source tree this
/// binary was built from; an error names both places when neither has it.
pub fn asset(relative: &str) -> lumen::Result<PathBuf> {
    let here = Path::new("assets").join(relative);
    let built = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../assets")
        .join(relative);
    [here.clone(), built.clone()]
        .into_iter()
        .find(|p| p.is_file())
        .ok_or_else(|| {
            lumen::Error::Scene(format!(
                "the showcase needs {} (looked in {} and {}): run it from a clone of the repository",
                relative,
                here.display(),
                built.display()
            ))
        })
}

/// The metal spheres on the left of the row: F0 (linear Rec. 709) and roughness. The F0
/// of gold, copper and aluminium are those of Adobe's "Metal material references" for the
/// Adobe Standard Material (Substance 3D documentation).
const METALS: [(Vec3, f32); 3] = [
    (Vec3::new(1.0, 0.7099, 0.3148), 0.2),
    (Vec3::new(1.0, 0.6504, 0.5274), 0.4),
    (Vec3::new(0.9157, 0.9226, 0.9236), 0.65),
];

/// Clear thin-walled glass, IOR 1.5.
fn glass() -> Material {
    Material {
        transmission: Some(Transmission::default()),
        ..Material::new(Vec3::ONE, 0.0, 0.02)
    }
}

/// Marks the entities of the model at the centre (its nodes).
#[derive(Component, Clone, Copy, Debug)]
pub struct ShowcaseModel;

pub(super) fn build(app: &mut App) -> lumen::Result<()> {
    let options = GltfOptions {
        staging: false,
        ..GltfOptions::default()
    };
    let world = app.world_mut();
    let before: HashSet<Entity> = world.query::<Entity>().iter(world).collect();
    let helmet = load_gltf_with(app, &asset(SHOWCASE_MODEL)?, &options)?;
    let world = app.world_mut();
    let model: Vec<Entity> = world
        .query::<Entity>()
        .iter(world)
        .filter(|e| !before.contains(e))
        .collect();
    for e in model {
        world.entity_mut(e).insert(ShowcaseModel);
    }
    let bounds = helmet
        .bounds
        .ok_or_else(|| lumen::Error::Scene(format!("{SHOWCASE_MODEL} has no geometry")))?;
    let centre = bounds.center();
    let height = bounds.max.y - bounds.min.y;
    let floor_y = bounds.min.y;
    let radius = 0.11 * height;

    let floor = app.add_mesh(plane(80.0 * height, 80.0 * height))?;
    let ball = app.add_mesh(uv_sphere(radius, 64, 32))?;
    let sky = EquirectImage::load(&asset(SHOWCASE_HDRI)?)?;
    let (sun, sky) = split_sun(&sky)
        .ok_or_else(|| lumen::Error::Scene(format!("{SHOWCASE_HDRI} has no sun to take out")))?;
    let intensity = SUN_LUX / luminance(sun.illuminance).max(f32::MIN_POSITIVE);

    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::splat(0.36), 0.0, 0.65),
        Transform::from_xyz(centre.x, floor_y, centre.z),
    ));
    let mut row: Vec<Material> = METALS
        .iter()
        .map(|(f0, roughness)| Material::new(*f0, 1.0, *roughness))
        .collect();
    row.extend([
        Material::new(Vec3::new(0.7, 0.05, 0.04), 0.0, 0.15),
        Material::new(Vec3::splat(0.8), 0.0, 0.8),
        glass(),
    ]);
    let xs = [-1.05f32, -0.78, -0.51, 0.51, 0.78, 1.05];
    for (x, material) in xs.iter().zip(row) {
        world.spawn((
            Mesh3d(ball),
            material,
            Transform::from_xyz(
                centre.x + x * height,
                floor_y + radius,
                centre.z - 0.35 * height,
            ),
        ));
    }
    // One reflection probe in front of the stand at the helmet's mid height, its box
    // standing on the floor: the automatic one would sit at the centre of every mesh's
    // bounds, inside the helmet's stand. Against 64 paths per pixel at 160×90 (FLIP),
    // `high` 0.0863 → 0.0842 and `ultra` 0.0761 → 0.0740. An irradiance volume over the
    // helmet and the row only (the automatic one spans the whole floor) measured worse
    // on `high` (0.0941), its edge a lighter rectangle on the floor.
    world.spawn((
        ReflectionProbe::new(Vec3::new(1.5, 0.5, 1.2) * height),
        Transform::from_xyz(centre.x, floor_y + 0.5 * height, centre.z + 0.45 * height),
    ));
    // Turn the sky so that the sun shines from the camera's left, in front of the helmet
    // (the rotation adds to the azimuth atan2(x, z)).
    let mut environment = Environment::image(Arc::new(sky), intensity);
    environment.rotation_y_rad = SUN_AZIMUTH_RAD - sun.direction.x.atan2(sun.direction.z);
    let (light, transform) = sun.light(&environment);
    world.spawn(environment);
    world.spawn((light, ShadowSettings::directional(), transform));
    let target = Vec3::new(centre.x, floor_y + 0.48 * height, centre.z);
    let eye = target + Vec3::new(0.28, 0.22, 1.0).normalize() * 2.3 * height;
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: 35f32.to_radians(),
                near_m: 0.02 * height,
                far_m: 40.0 * height,
                ..Projection::default()
            },
            exposure: Exposure::Ev100(SHOWCASE_EV100),
            ..Camera::default()
        },
        Transform::from_translation(eye).looking_at(target, Vec3::Y),
    ));
    Ok(())
}

//! Building an [`App`] from the command line's scene arguments.

use crate::cli::SceneArgs;
use crate::scenes;
use anyhow::{Context, Result};
use lumen::choice::Choice;
use lumen::prelude::*;
use lumen::quality::QualityPreset;
use lumen::scene::AutoExposure;

/// Spawns the requested scene (built-in or glTF file) into `app` and applies the
/// exposure, tone mapping and quality overrides.
pub fn build_scene(app: &mut App, args: &SceneArgs) -> Result<()> {
    // Quality first: the glTF loader reads the texture budget.
    let quality = quality_of(args)?;
    *app.world_mut().resource_mut::<Quality>() = quality;
    match (&args.file, &args.scene) {
        (Some(file), _) => {
            let options = lumen::assets::gltf::GltfOptions {
                light_shadows: args.gltf_light_shadows.unwrap_or(true),
                ..Default::default()
            };
            let summary = lumen::assets::gltf::load_gltf_with(app, file, &options)?;
            log::info!(
                "{}: {} node(s), {} primitive(s), {} triangles, {} light(s)",
                file.display(),
                summary.nodes,
                summary.primitives,
                summary.triangles,
                summary.lights
            );
        }
        (None, name) => {
            let info =
                scenes::find(name.as_deref().unwrap_or("spheres")).map_err(anyhow::Error::msg)?;
            if let Some(count) = args.lights {
                app.world_mut()
                    .insert_resource(scenes::LightsSceneOptions { count });
            }
            (info.build)(app).with_context(|| format!("building scene '{}'", info.name))?;
        }
    }
    apply_environment(app, args)?;
    if let Some(t) = args.time {
        hold_animations(app, t);
    }
    if let Some(view) = args.debug_view {
        app.world_mut().insert_resource(view);
    }
    let world = app.world_mut();
    let mut cameras = world.query::<&mut Camera>();
    for mut camera in cameras.iter_mut(world) {
        apply_camera(&mut camera, args);
    }
    Ok(())
}

/// Poses every animation player at `time_s` seconds of its clip and pauses it there.
pub fn hold_animations(app: &mut App, time_s: f32) {
    let world = app.world_mut();
    let mut players = world.query::<&mut AnimationPlayer>();
    for mut player in players.iter_mut(world) {
        player.seek(time_s);
        player.pause();
    }
}

/// The quality the command line asks for: `--quality` or `--quality-file` (else the
/// defaults), with the knobs' flags applied.
pub fn quality_of(args: &SceneArgs) -> Result<Quality> {
    let mut quality = match (&args.quality_file, args.quality) {
        (Some(file), _) => {
            let knobs = lumen::quality::Knobs::default();
            lumen::quality::preset::load(file, &knobs)?
        }
        (None, Some(preset)) => preset.quality(),
        (None, None) => Quality::default(),
    };
    args.knobs.apply(&mut quality)?;
    Ok(quality)
}

/// The command line's camera settings.
fn apply_camera(camera: &mut Camera, args: &SceneArgs) {
    if let Some(ev) = args.ev100 {
        camera.exposure = Exposure::Ev100(ev);
    }
    if let Some(k) = args.exposure {
        camera.exposure = Exposure::Linear(k);
    }
    if let Some(n) = args.aperture {
        camera.lens.aperture_f_stops = n;
    }
    if let Some(t) = args.shutter {
        camera.lens.shutter_s = t;
    }
    if let Some(s) = args.iso {
        camera.lens.iso = s;
    }
    // Shutter or ISO only make sense as physical exposure; an aperture alone may be for
    // depth of field.
    if args.shutter.is_some() || args.iso.is_some() {
        camera.exposure = Exposure::Physical;
    }
    if args.auto_exposure {
        camera.exposure = Exposure::Auto(AutoExposure::default());
    }
    if let Some(stops) = args.exposure_compensation {
        camera.exposure_compensation = stops;
    }
    if let Some(mm) = args.focal_length {
        camera.projection.fov_y_rad = camera.lens.fov_for_focal_length(mm);
    }
    if let Some(m) = args.focus {
        camera.lens.focus_distance_m = m;
    }
    // Asking for rings asks for depth of field.
    let rings = args
        .knobs
        .get(&lumen::quality::knobs::DOF_RINGS)
        .and_then(lumen::quality::knob::Value::as_i64);
    if args.dof == Some(true) || (args.dof.is_none() && rings.is_some()) {
        let mut dof = camera.depth_of_field.unwrap_or_default();
        if let Some(r) = rings {
            dof.rings = r as u32;
        }
        camera.depth_of_field = Some(dof);
    }
    if args.dof == Some(false) {
        camera.depth_of_field = None;
    }
    if let Some(strength) = args.vignette {
        camera.vignette = Some(lumen::scene::Vignette { strength });
    }
    if let Some(t) = args.tonemap {
        camera.tonemapper = t;
    }
}

/// Luminance (cd/m²) of an environment image value of 1 unless `--env-intensity` says
/// otherwise: the shipped HDRIs average 0.4–1.9, so 1000 gives an interior of a few hundred
/// to two thousand cd/m², on the scale of the built-in scenes' lights.
pub const DEFAULT_ENV_IMAGE_INTENSITY: f32 = 1000.0;

/// Removes every `Environment` and spawns `env`.
pub fn replace_environment(world: &mut World, env: Environment) {
    let old: Vec<Entity> = world
        .query_filtered::<Entity, With<Environment>>()
        .iter(world)
        .collect();
    for e in old {
        world.entity_mut(e).remove::<Environment>();
    }
    world.spawn(env);
}

/// Loads an equirectangular HDR or EXR as the scene's environment, at
/// [`DEFAULT_ENV_IMAGE_INTENSITY`].
pub fn open_environment(app: &mut App, path: &std::path::Path) -> Result<()> {
    let image = EquirectImage::load(path)?;
    let env = Environment::image(std::sync::Arc::new(image), DEFAULT_ENV_IMAGE_INTENSITY);
    replace_environment(app.world_mut(), env);
    Ok(())
}

/// Replaces (or adjusts) the scene's environment as `--env*` and `--background-blur` say.
fn apply_environment(app: &mut App, args: &SceneArgs) -> Result<()> {
    if let Some(path) = &args.env {
        open_environment(app, path)?;
    } else if let Some(env) = args.env_color.map(Environment::uniform) {
        replace_environment(app.world_mut(), env);
    }
    let world = app.world_mut();
    for mut env in world.query::<&mut Environment>().iter_mut(world) {
        if let Some(i) = args.env_intensity {
            env.intensity = i;
        }
        if let Some(deg) = args.env_rotation {
            env.rotation_y_rad = deg.to_radians();
        }
        if let Some(blur) = args.background_blur {
            env.background = lumen::scene::Background::Environment { blur };
        }
        if args.env_hidden {
            env.background = lumen::scene::Background::CameraColor;
        }
    }
    Ok(())
}

/// Checks up front that a scene argument can be used, so that errors come before the GPU
/// is initialised.
pub fn check_scene_args(args: &SceneArgs) -> Result<()> {
    quality_of(args)?;
    if args.lights.is_some() && (args.file.is_some() || args.scene.as_deref() != Some("lights")) {
        anyhow::bail!("--lights applies to the `lights` scene only (use --scene lights)");
    }
    if let Some(file) = &args.file {
        std::fs::metadata(file).with_context(|| format!("cannot read {}", file.display()))?;
    } else if let Some(name) = &args.scene {
        scenes::find(name).map_err(anyhow::Error::msg)?;
    }
    Ok(())
}

/// The preset whose knobs equal `quality`, or `custom`. The shadow cache is left out: it
/// changes no pixel, only whether an unchanged atlas is drawn again.
pub fn preset_name(quality: &Quality) -> String {
    let quality = Quality {
        shadow_cache: true,
        ..quality.clone()
    };
    QualityPreset::ALL
        .iter()
        .find(|p| p.quality() == quality)
        .map_or_else(|| "custom".into(), |p| p.name().into())
}

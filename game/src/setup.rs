//! Building an [`App`] from the command line's scene arguments.

use crate::cli::SceneArgs;
use crate::scenes;
use anyhow::{Context, Result};
use lumen::prelude::*;
use lumen::scene::AutoExposure;

/// Spawns the requested scene (built-in or glTF file) into `app` and applies the
/// exposure, tone mapping and quality overrides.
pub fn build_scene(app: &mut App, args: &SceneArgs) -> Result<()> {
    // Quality first: the glTF loader reads the texture budget.
    apply_quality(&mut app.world_mut().resource_mut::<Quality>(), args);
    match (&args.file, &args.scene) {
        (Some(file), _) => {
            let options = lumen::assets::gltf::GltfOptions {
                light_shadows: !args.no_gltf_light_shadows,
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

/// Applies `--quality` and the single-knob options.
fn apply_quality(quality: &mut Quality, args: &SceneArgs) {
    if let Some(preset) = args.quality {
        *quality = preset.quality();
    }
    if let Some(x) = args.shadow_resolution_scale {
        quality.shadow_resolution_scale = x;
    }
    if let Some(n) = args.cascades {
        quality.max_cascades = n;
    }
    if let Some(n) = args.ibl_samples {
        quality.ibl_samples = n;
    }
    if let Some(n) = args.brdf_lut_size {
        quality.brdf_lut_size = n;
    }
    if let Some(n) = args.brdf_lut_samples {
        quality.brdf_lut_samples = n;
    }
    if let Some(p) = args.hdr {
        quality.hdr_precision = p;
    }
    if let Some(t) = args.transparency {
        quality.transparency = t;
    }
    if args.no_light_culling {
        quality.light_culling = false;
    }
    if args.no_shadow_cache {
        quality.shadow_cache = false;
    }
    if args.dof_rings.is_some() {
        quality.dof_rings = args.dof_rings;
    }
    if let Some(v) = args.visibility {
        quality.visibility = v;
    }
    if args.no_shadows {
        quality.shadows = false;
    }
    if let Some(f) = args.shadow_filter {
        quality.shadow_filter = f;
    }
    if let Some(m) = args.shadow_mask {
        quality.shadow_mask = m;
    }
    if let Some(all) = args.light_shadows {
        quality.all_lights_cast_shadows = all;
    }
    if args.no_energy_compensation {
        quality.energy_compensation = false;
    }
    if let Some(n) = args.max_texture_size {
        quality.max_texture_size = n;
    }
    if let Some(r) = args.ao {
        quality.ao.resolution = r;
    }
    if let Some(n) = args.ao_slices {
        quality.ao.slices = n;
    }
    if let Some(n) = args.ao_steps {
        quality.ao.steps = n;
    }
    if let Some(r) = args.ao_radius {
        quality.ao.radius_m = r;
    }
    if args.no_ao_denoise {
        quality.ao.denoise = false;
    }
    if args.no_ao_multi_bounce {
        quality.ao.multi_bounce = false;
    }
    if args.no_ssr {
        quality.ssr.enabled = false;
    }
    if let Some(r) = args.ssr_max_roughness {
        quality.ssr.max_roughness = r;
    }
    if let Some(n) = args.ssr_rays {
        quality.ssr.rays = n;
    }
    if let Some(n) = args.ssr_steps {
        quality.ssr.steps = n;
    }
    if let Some(m) = args.ssr_thickness {
        quality.ssr.thickness_m = m;
    }
    if let Some(half) = args.ssr_resolution {
        quality.ssr.half_resolution = half;
    }
    if let Some(on) = args.gi {
        quality.gi.enabled = on;
    }
    if let Some(n) = args.gi_density {
        quality.gi.density = n;
    }
    if let Some(n) = args.gi_face {
        quality.gi.face_size = n;
    }
    if let Some(n) = args.gi_bounces {
        quality.gi.bounces = n;
    }
    if let Some(half) = args.gi_resolution {
        quality.gi.half_resolution = half;
    }
    if let Some(n) = args.gi_budget {
        quality.gi.probes_per_frame = n;
    }
    if args.no_auto_probes {
        quality.gi.auto_place = false;
        quality.reflection_probes.auto_place = false;
    }
    if let Some(on) = args.reflection_probes {
        quality.reflection_probes.enabled = on;
    }
    if let Some(n) = args.reflection_probe_size {
        quality.reflection_probes.face_size = n;
    }
    if let Some(m) = args.aa {
        quality.aa.method = m;
    }
    if let Some(n) = args.accumulate {
        quality.aa.accumulate = n;
    }
    if args.specular_aa {
        quality.aa.specular.enabled = true;
    }
    if args.no_specular_aa {
        quality.aa.specular.enabled = false;
    }
    if let Some(form) = args.specular_aa_form {
        quality.aa.specular = quality.aa.specular.with_form(form);
    }
    if let Some(x) = args.specular_aa_variance {
        quality.aa.specular.variance = x;
    }
    if let Some(x) = args.specular_aa_threshold {
        quality.aa.specular.threshold = x;
    }
    if let Some(x) = args.taa_sharpen {
        quality.aa.taa_sharpen = x;
    }
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
    if args.dof || args.dof_rings.is_some() {
        let mut dof = camera.depth_of_field.unwrap_or_default();
        if let Some(r) = args.dof_rings {
            dof.rings = r;
        }
        camera.depth_of_field = Some(dof);
    }
    if args.no_dof {
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
        ..*quality
    };
    lumen::quality::QualityPreset::ALL
        .into_iter()
        .find(|p| p.quality() == quality)
        .map_or_else(|| "custom".into(), |p| p.name().into())
}

/// Every quality knob as JSON (the `quality` object of `render --json` and `bench`).
pub fn quality_json(q: &Quality) -> serde_json::Value {
    serde_json::json!({
        "visibility": q.visibility.name(),
        "shadows": q.shadows,
        "shadow_filter": q.shadow_filter.name(),
        "shadow_mask": q.shadow_mask.name(),
        "light_shadows": if q.all_lights_cast_shadows { "all" } else { "scene" },
        "shadow_resolution_scale": q.shadow_resolution_scale,
        "max_cascades": q.max_cascades,
        "energy_compensation": q.energy_compensation,
        "ibl_samples": q.ibl_samples,
        "brdf_lut_size": q.brdf_lut_size,
        "brdf_lut_samples": q.brdf_lut_samples,
        "dof_rings": q.dof_rings,
        "hdr_precision": q.hdr_precision.name(),
        "transparency": q.transparency.name(),
        "light_culling": q.light_culling,
        "shadow_cache": q.shadow_cache,
        "max_texture_size": q.max_texture_size,
        "ao": {
            "resolution": q.ao.resolution.name(),
            "slices": q.ao.slices,
            "steps": q.ao.steps,
            "radius_m": q.ao.radius_m,
            "denoise": q.ao.denoise,
            "multi_bounce": q.ao.multi_bounce,
        },
        "ssr": {
            "enabled": q.ssr.enabled,
            "max_roughness": q.ssr.max_roughness,
            "rays": q.ssr.rays,
            "steps": q.ssr.steps,
            "thickness_m": q.ssr.thickness_m,
            "resolution": if q.ssr.half_resolution { "half" } else { "full" },
        },
        "gi": {
            "enabled": q.gi.enabled,
            "density": q.gi.density,
            "face_size": q.gi.face_size,
            "bounces": q.gi.bounces,
            "probes_per_frame": q.gi.probes_per_frame,
            "auto_place": q.gi.auto_place,
            "resolution": if q.gi.half_resolution { "half" } else { "full" },
        },
        "reflection_probes": {
            "enabled": q.reflection_probes.enabled,
            "face_size": q.reflection_probes.face_size,
            "auto_place": q.reflection_probes.auto_place,
        },
    })
}

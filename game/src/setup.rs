//! Building an [`App`] from the command line's scene arguments.

use crate::cli::SceneArgs;
use crate::scenes;
use anyhow::{Context, Result};
use lumen::prelude::*;

/// Spawns the requested scene (built-in or glTF file) into `app` and applies the
/// exposure, tone mapping and quality overrides.
pub fn build_scene(app: &mut App, args: &SceneArgs) -> Result<()> {
    match (&args.file, &args.scene) {
        (Some(file), _) => {
            let summary = lumen::assets::gltf::load_gltf(app, file)?;
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
            (info.build)(app).with_context(|| format!("building scene '{}'", info.name))?;
        }
    }
    let world = app.world_mut();
    let mut cameras = world.query::<&mut Camera>();
    for mut camera in cameras.iter_mut(world) {
        if let Some(ev) = args.ev100 {
            camera.exposure = Exposure::Ev100(ev);
        }
        if let Some(k) = args.exposure {
            camera.exposure = Exposure::Linear(k);
        }
        if let Some(t) = args.tonemap {
            camera.tonemapper = t;
        }
    }
    let mut quality = world.resource_mut::<Quality>();
    if let Some(v) = args.visibility {
        quality.visibility = v;
    }
    if args.no_shadows {
        quality.shadows = false;
    }
    if let Some(f) = args.shadow_filter {
        quality.shadow_filter = f;
    }
    Ok(())
}

/// Checks up front that a scene argument can be used, so that errors come before the GPU
/// is initialised.
pub fn check_scene_args(args: &SceneArgs) -> Result<()> {
    if let Some(file) = &args.file {
        std::fs::metadata(file).with_context(|| format!("cannot read {}", file.display()))?;
    } else if let Some(name) = &args.scene {
        scenes::find(name).map_err(anyhow::Error::msg)?;
    }
    Ok(())
}

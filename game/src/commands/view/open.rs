//! Files opened in the viewer, dropped on the window or given with `--open`.

use crate::setup::open_environment;
use anyhow::{Result, anyhow};
use lumen::App;
use lumen::prelude::*;
use std::path::Path;

/// The scene's root entities (transforms and environments without a parent).
fn scene_roots(world: &mut World) -> std::collections::HashSet<Entity> {
    world
        .query_filtered::<Entity, (Or<(With<Transform>, With<Environment>)>, Without<ChildOf>)>()
        .iter(world)
        .collect()
}

/// Opens a dropped or `--open`ed file: a glTF model replaces the scene (lights and camera
/// of the file, or the loader's defaults); an HDR or EXR image becomes the environment.
/// Returns a line for the log.
pub fn open_file(app: &mut App, path: &Path) -> Result<String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "gltf" | "glb" => {
            // The model replaces the scene but not its environment; a file that fails
            // to load leaves the scene as it was. Scene roots only: despawning a root
            // despawns its children, and resources are entities too.
            let before = scene_roots(app.world_mut());
            let loaded = lumen::assets::gltf::load_gltf(app, path);
            let world = app.world_mut();
            let remove: Vec<Entity> = match &loaded {
                Ok(_) => before
                    .into_iter()
                    .filter(|e| world.get::<Environment>(*e).is_none())
                    .collect(),
                Err(_) => scene_roots(world).difference(&before).copied().collect(),
            };
            for e in remove {
                if let Ok(entity) = world.get_entity_mut(e) {
                    entity.despawn();
                }
            }
            let summary = loaded?;
            for w in &summary.warnings {
                log::warn!("{}: {w}", path.display());
            }
            Ok(format!(
                "opened {}: {} primitives, {} triangles, {} lights",
                path.display(),
                summary.primitives,
                summary.triangles,
                summary.lights
            ))
        }
        "hdr" | "exr" => {
            open_environment(app, path)?;
            Ok(format!("environment {}", path.display()))
        }
        _ => Err(anyhow!(
            "{}: cannot open this file type (expected .gltf, .glb, .hdr or .exr)",
            path.display()
        )),
    }
}

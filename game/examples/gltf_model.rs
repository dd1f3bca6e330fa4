//! A glTF model under an HDR environment, seen through a physical camera (f/4, 1/250 s,
//! ISO 100: EV100 12, with depth of field focused on the model). Writes `out/examples/gltf_model.png`.
//! `cargo run --release --example gltf_model [WxH]`; `-- --window` shows it in the viewer.

use lumen::prelude::*;
use lumen::scene::{DepthOfField, Lens};
use std::sync::Arc;

fn main() -> anyhow::Result<()> {
    let args = lumen_game::examples::start((640, 360));
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut app = args.app()?;
    let summary = lumen::assets::gltf::load_gltf(&mut app, &root.join("assets/models/suzi.glb"))?;
    let sky = EquirectImage::load(&root.join("assets/hdri/studio.exr"))?;
    let world = app.world_mut();
    world.spawn(Environment::image(Arc::new(sky), 1000.0));
    let distance = summary
        .bounds
        .map_or(3.0, |b| (b.max - b.min).length() * 1.6);
    for mut camera in world.query::<&mut Camera>().iter_mut(world) {
        camera.lens = Lens {
            aperture_f_stops: 4.0,
            shutter_s: 1.0 / 250.0,
            iso: 100.0,
            focus_distance_m: distance,
            ..Lens::default()
        };
        camera.exposure = Exposure::Physical;
        camera.depth_of_field = Some(DepthOfField::default());
    }
    args.finish(app, "gltf_model.png", 1)
}

//! The seeds' sphere grid: metallic rising up the rows, roughness along the columns, under
//! one sun. `cargo run --release --example sphere_grid [WxH]` writes
//! `out/examples/sphere_grid.png`; `-- --window` shows it in the viewer instead.

use lumen::assets::procedural::uv_sphere;
use lumen::prelude::*;

fn main() -> anyhow::Result<()> {
    let args = lumen_game::examples::start((640, 360));
    let mut app = args.app()?;
    let sphere = app.add_mesh(uv_sphere(0.4, 48, 24))?;
    let world = app.world_mut();
    for (i, j) in (0..7).flat_map(|i| (0..5).map(move |j| (i, j))) {
        let material = Material::new(Vec3::new(0.9, 0.4, 0.2), j as f32 / 4.0, i as f32 / 6.0);
        let at = Transform::from_xyz(i as f32 - 3.0, j as f32 - 2.0, 0.0);
        world.spawn((Mesh3d(sphere), material, at));
    }
    let sun = Transform::from_xyz(1.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y);
    world.spawn((DirectionalLight::default(), sun));
    let eye = Transform::from_xyz(0.0, 0.0, 9.0).looking_at(Vec3::ZERO, Vec3::Y);
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(11.0),
            ..Camera::default()
        },
        eye,
    ));
    args.finish(app, "sphere_grid.png", 1)
}

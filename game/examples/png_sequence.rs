//! A headless animation: the camera orbits the `spheres` scene and every frame is written
//! as a numbered PNG, `out/examples/sequence/frame_0000.png` … (12 frames of 1/30 s:
//! the headless app's fixed step, so every run writes the same frames).
//! `cargo run --release --example png_sequence [WxH]`.

use lumen::prelude::*;

/// The camera's turn rate around the scene (rad/s).
const ORBIT_RAD_PER_S: f32 = 4.5;

/// Puts every camera on a circle around the origin, at the angle time has reached.
fn orbit_camera(time: Res<Time>, mut cameras: Query<&mut Transform, With<Camera>>) {
    let angle = time.elapsed_secs() as f32 * ORBIT_RAD_PER_S;
    for mut t in &mut cameras {
        *t = Transform::from_xyz(9.0 * angle.sin(), 3.0, 9.0 * angle.cos())
            .looking_at(Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
    }
}

fn main() -> lumen::Result<()> {
    let size = lumen_game::examples::start((320, 180)).size;
    let mut app = App::headless()?;
    app.set_fixed_delta(Some(1.0 / 30.0));
    let scene = lumen_game::scenes::find("spheres").map_err(lumen::Error::Scene)?;
    (scene.build)(&mut app)?;
    app.add_systems(orbit_camera);
    for k in 0..12 {
        app.update();
        app.render_headless(size)?;
        lumen_game::examples::save(
            &app.read_display_image()?,
            &format!("sequence/frame_{k:04}.png"),
        )?;
    }
    Ok(())
}

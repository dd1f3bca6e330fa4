//! Coloured point lights (colour temperatures from 2000 K to 9000 K) circling over a
//! ground plane, moved by an ordinary `bevy_ecs` system. Renders a few frames headless
//! and writes the last to `out/examples/animated_lights.png`, or, with `-- --window`,
//! keeps them circling in the viewer.
//! `cargo run --release --example animated_lights [WxH] [--window]`.

use lumen::assets::procedural::{plane, uv_sphere};
use lumen::prelude::*;

/// A light's place on its circle.
#[derive(Component)]
struct Orbit {
    radius_m: f32,
    phase_rad: f32,
}

/// How fast the lights circle (rad/s): one turn in about 1.05 s.
const ORBIT_RAD_PER_S: f32 = 6.0;

/// Turns every orbiting light by the time since the last frame.
fn orbit(time: Res<Time>, mut lights: Query<(&mut Orbit, &mut Transform)>) {
    for (mut o, mut t) in &mut lights {
        o.phase_rad += ORBIT_RAD_PER_S * time.delta_secs();
        t.translation = Vec3::new(
            o.radius_m * o.phase_rad.cos(),
            1.0,
            o.radius_m * o.phase_rad.sin(),
        );
    }
}

fn main() -> anyhow::Result<()> {
    let args = lumen_game::examples::start((640, 360));
    let mut app = args.app()?;
    let ground = app.add_mesh(plane(12.0, 12.0))?;
    let ball = app.add_mesh(uv_sphere(0.6, 48, 24))?;
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.6), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(ball),
        Material::new(Vec3::splat(0.9), 1.0, 0.3),
        Transform::from_xyz(0.0, 0.6, 0.0),
    ));
    for k in 0..6 {
        let kelvin = 2000.0 + 1400.0 * k as f32;
        world.spawn((
            PointLight {
                intensity: LuminousIntensity::Lumens(1500.0),
                color: LightColor::Kelvin(kelvin),
                range_m: 8.0,
                ..PointLight::default()
            },
            Orbit {
                radius_m: 2.5,
                phase_rad: k as f32 * std::f32::consts::TAU / 6.0,
            },
            Transform::IDENTITY,
        ));
    }
    let eye = Transform::from_xyz(0.0, 4.0, 7.0).looking_at(Vec3::ZERO, Vec3::Y);
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(6.0),
            ..Camera::default()
        },
        eye,
    ));
    app.add_systems(orbit);
    args.finish(app, "animated_lights.png", 5)
}

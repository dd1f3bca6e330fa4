//! Keys drive the scene from ordinary systems: `1` to `4` pick the quality preset, `V`
//! steps through the debug views, the arrow keys move the lamp at 2 m/s and `Space` puts
//! it back. The controls and the state are printed on screen.
//!
//! `cargo run --release --example controls -- --window` opens it in the viewer (whose
//! own camera keys stay on). Without `--window`, a scripted half second of key presses
//! plays headless: `1` (low), `V` (albedo) and the right arrow held for 30 frames of
//! 1/60 s; it prints where the lamp ended (1 m to the right) and writes
//! `out/examples/controls.png`.

use lumen::assets::procedural::{plane, uv_sphere};
use lumen::prelude::*;
use lumen::quality::QualityPreset;
use lumen_game::view::ScreenText;

/// The lamp the arrow keys move.
#[derive(Component)]
struct Lamp;

/// Where the lamp starts and goes back to (m).
const LAMP_HOME: Vec3 = Vec3::new(0.0, 1.5, 1.5);

/// The lamp's speed while an arrow key is held (m/s).
const LAMP_SPEED_M_S: f32 = 2.0;

/// The preset keys, cheapest first.
const PRESET_KEYS: [(KeyCode, QualityPreset); 4] = [
    (KeyCode::Digit1, QualityPreset::Low),
    (KeyCode::Digit2, QualityPreset::Medium),
    (KeyCode::Digit3, QualityPreset::High),
    (KeyCode::Digit4, QualityPreset::Ultra),
];

/// The preset the keys picked last (the app starts at `high`).
#[derive(Resource)]
struct Preset(QualityPreset);

/// `1` to `4`: the quality preset; `V`: the next debug view.
fn switch_quality(
    keys: Res<Keys>,
    mut preset: ResMut<Preset>,
    mut quality: ResMut<Quality>,
    mut view: ResMut<DebugView>,
) {
    for (key, p) in PRESET_KEYS {
        if keys.just_pressed(key) {
            preset.0 = p;
            *quality = p.quality();
        }
    }
    if keys.just_pressed(KeyCode::KeyV) {
        let at = DebugView::ALL.iter().position(|v| v == &*view).unwrap_or(0);
        *view = DebugView::ALL[(at + 1) % DebugView::ALL.len()];
    }
}

/// The arrow keys move the lamp in the ground plane, by speed × time; `Space` resets it.
fn move_lamp(time: Res<Time>, keys: Res<Keys>, mut lamps: Query<&mut Transform, With<Lamp>>) {
    let axis = |plus, minus| {
        f32::from(u8::from(keys.pressed(plus))) - f32::from(u8::from(keys.pressed(minus)))
    };
    let step = Vec3::new(
        axis(KeyCode::ArrowRight, KeyCode::ArrowLeft),
        0.0,
        axis(KeyCode::ArrowDown, KeyCode::ArrowUp),
    ) * LAMP_SPEED_M_S
        * time.delta_secs();
    for mut t in &mut lamps {
        t.translation = if keys.just_pressed(KeyCode::Space) {
            LAMP_HOME
        } else {
            t.translation + step
        };
    }
}

/// The controls and the state, for the viewer to print.
fn show_controls(
    preset: Res<Preset>,
    view: Res<DebugView>,
    lamps: Query<&Transform, With<Lamp>>,
    mut text: ResMut<ScreenText>,
) {
    let lamp = lamps.iter().next().map_or(Vec3::ZERO, |t| t.translation);
    text.lines = vec![
        "1-4     quality preset".into(),
        "V       next debug view".into(),
        "arrows  move the lamp".into(),
        "Space   lamp home".into(),
        String::new(),
        format!("preset  {}", preset.0.name()),
        format!("view    {}", view.name()),
        format!("lamp    x {:+.2} m, z {:+.2} m", lamp.x, lamp.z),
    ];
}

fn main() -> anyhow::Result<()> {
    let args = lumen_game::examples::start((640, 360));
    let mut app = args.app()?;
    let ground = app.add_mesh(plane(10.0, 10.0))?;
    let ball = app.add_mesh(uv_sphere(0.5, 48, 24))?;
    let world = app.world_mut();
    world.insert_resource(Preset(QualityPreset::High));
    world.init_resource::<ScreenText>();
    world.init_resource::<DebugView>();
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.5), 0.0, 0.7),
        Transform::IDENTITY,
    ));
    for (k, metallic) in [0.0f32, 1.0].into_iter().enumerate() {
        world.spawn((
            Mesh3d(ball),
            Material::new(Vec3::new(0.9, 0.5, 0.2), metallic, 0.35),
            Transform::from_xyz(k as f32 * 1.4 - 0.7, 0.5, 0.0),
        ));
    }
    world.spawn((
        Lamp,
        PointLight {
            intensity: LuminousIntensity::Lumens(3000.0),
            ..PointLight::default()
        },
        Transform::from_translation(LAMP_HOME),
    ));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(7.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 3.0, 5.0).looking_at(Vec3::new(0.0, 0.4, 0.0), Vec3::Y),
    ));
    app.add_systems((switch_quality, move_lamp, show_controls).chain());
    if args.window {
        return args.finish(app, "controls.png", 1);
    }
    let key = |code, pressed| InputEvent::Key { code, pressed };
    app.send_input(key(KeyCode::Digit1, true));
    app.send_input(key(KeyCode::ArrowRight, true));
    for frame in 0..30 {
        if frame == 10 {
            app.send_input(key(KeyCode::KeyV, true));
        }
        app.update();
    }
    app.send_input(key(KeyCode::ArrowRight, false));
    app.update();
    for line in &app.world().resource::<ScreenText>().lines[5..] {
        println!("{line}");
    }
    app.render_headless(args.size)?;
    lumen_game::examples::save(&app.read_display_image()?, "controls.png")?;
    Ok(())
}

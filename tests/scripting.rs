//! The scripting API: a user system changes the picture between frames, and WGSL reloaded
//! from disk takes effect, while a broken shader is an error and never fatal; a lost
//! device is an error, and a new one renders the same scene.

use crate::common;

use lumen::prelude::*;
use std::path::Path;

const SIZE: (u32, u32) = (64, 48);

/// A sphere on a floor lit by one point light, which `orbit_light` moves.
fn lit_sphere() -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let sphere = app
        .add_mesh(lumen::assets::procedural::uv_sphere(1.0, 32, 16))
        .expect("sphere");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::splat(0.8), 0.0, 0.5),
        Transform::IDENTITY,
    ));
    world.spawn((PointLight::default(), Transform::from_xyz(3.0, 0.0, 0.0)));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(5.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    app
}

/// Moves every point light half a turn around the sphere per update.
fn orbit_light(mut lights: Query<&mut Transform, With<PointLight>>) {
    for mut t in &mut lights {
        let p = Quat::from_rotation_y(std::f32::consts::PI) * t.translation;
        t.translation = p;
    }
}

/// Mean display value of the left and the right half of the image.
fn halves(image: &image::RgbaImage) -> (f64, f64) {
    let (w, h) = image.dimensions();
    let mut sums = [0.0f64; 2];
    for (x, _, p) in image.enumerate_pixels() {
        sums[usize::from(x >= w / 2)] += f64::from(p.0[0]);
    }
    let n = f64::from(w / 2 * h);
    (sums[0] / n, sums[1] / n)
}

#[test]
fn a_system_that_moves_the_light_changes_the_next_frame() {
    let mut app = lit_sphere();
    app.add_systems(orbit_light);
    app.render_headless(SIZE).expect("frame 1");
    let (left1, right1) = halves(&app.read_display_image().expect("image 1"));
    app.update();
    app.render_headless(SIZE).expect("frame 2");
    let (left2, right2) = halves(&app.read_display_image().expect("image 2"));
    // The light starts at +x (right side lit), then moves to −x (left side lit).
    assert!(
        right1 > 2.0 * left1,
        "frame 1: left {left1}, right {right1}"
    );
    assert!(
        left2 > 2.0 * right2,
        "frame 2: left {left2}, right {right2}"
    );
}

/// A copy of the repository's `shaders/` in a temporary folder.
fn shader_copy() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders");
    for entry in std::fs::read_dir(&source).expect("shaders/") {
        let path = entry.expect("entry").path();
        std::fs::copy(&path, dir.path().join(path.file_name().expect("name"))).expect("copy");
    }
    dir
}

fn edit(dir: &Path, file: &str, from: &str, to: &str) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).expect("read");
    assert!(text.contains(from), "{file} contains {from:?}");
    std::fs::write(&path, text.replacen(from, to, 1)).expect("write");
}

#[test]
fn an_unchanged_shader_folder_reloads_nothing() {
    let mut app = lit_sphere();
    let dir = shader_copy();
    assert_eq!(
        app.reload_shaders(dir.path()).expect("reload"),
        Vec::<&str>::new()
    );
}

#[test]
fn an_edited_shader_takes_effect_on_the_next_frame() {
    let mut app = lit_sphere();
    app.render_headless(SIZE).expect("frame");
    let before = app.read_display_image().expect("image");
    let dir = shader_copy();
    // The tone mapper's output replaced by pure green.
    edit(
        dir.path(),
        "tonemap.wgsl",
        "fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {",
        "fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {\n    if true { return vec4<f32>(0.0, 1.0, 0.0, 1.0); }",
    );
    let changed = app.reload_shaders(dir.path()).expect("reload");
    assert_eq!(changed, vec!["tonemap.wgsl"]);
    app.render_headless(SIZE)
        .expect("frame with the new shader");
    let after = app.read_display_image().expect("image");
    assert!(
        after.pixels().all(|p| p.0 == [0, 255, 0, 255]),
        "every pixel is green"
    );
    assert_ne!(before, after);
}

#[test]
fn a_syntax_error_in_a_pass_shader_is_reported_and_the_old_shaders_stay() {
    let mut app = lit_sphere();
    app.render_headless(SIZE).expect("frame");
    let before = app.read_display_image().expect("image");
    let dir = shader_copy();
    // The tone mapping pipeline is compiled by the frame.
    edit(dir.path(), "tonemap.wgsl", "fn fs_main(", "fn fs_main(((");
    app.reload_shaders(dir.path())
        .expect("the reload itself compiles no tone mapper");
    let err = app
        .render_headless(SIZE)
        .expect_err("the broken shader fails the frame");
    let message = format!("{err}");
    assert!(message.contains("tonemap"), "{message}");
    assert!(message.contains("previous ones are back"), "{message}");
    app.render_headless(SIZE)
        .expect("the next frame uses the previous shaders");
    assert_eq!(app.read_display_image().expect("image"), before);
}

#[test]
fn a_syntax_error_in_a_precompiled_shader_fails_the_reload() {
    let mut app = lit_sphere();
    app.render_headless(SIZE).expect("frame");
    let before = app.read_display_image().expect("image");
    let dir = shader_copy();
    // The G-buffer pipelines are compiled when the passes are rebuilt.
    edit(dir.path(), "gbuffer.wgsl", "fn ", "fn fn ");
    let err = app
        .reload_shaders(dir.path())
        .expect_err("the broken G-buffer shader fails the reload");
    let message = format!("{err}");
    assert!(message.contains("gbuffer"), "{message}");
    app.render_headless(SIZE)
        .expect("the previous shaders render");
    assert_eq!(app.read_display_image().expect("image"), before);
    assert!(
        app.reload_shaders(Path::new("/nonexistent/shaders"))
            .is_err(),
        "a missing folder is an error"
    );
}

/// Spawns one more sphere per update, to the right of the last.
fn spawn_sphere(mut commands: Commands, spheres: Query<&Mesh3d>, mut n: Local<u32>) {
    let Some(mesh) = spheres.iter().next().copied() else {
        return;
    };
    *n += 1;
    commands.spawn((
        mesh,
        Material::new(Vec3::splat(0.5), 0.0, 0.5),
        Transform::from_xyz(*n as f32 * 0.7, 0.0, -1.0).with_scale(Vec3::splat(0.3)),
    ));
}

#[test]
fn a_system_that_spawns_objects_adds_them_to_the_next_frames() {
    let mut app = lit_sphere();
    app.add_systems(spawn_sphere);
    let mut seen = Vec::new();
    for _ in 0..3 {
        app.update();
        let report = app.render_headless(SIZE).expect("frame");
        seen.push((report.stats.instances, report.stats.draws));
    }
    // One more instance per frame, all in one instanced draw (the same mesh).
    assert_eq!(seen, vec![(2, 1), (3, 1), (4, 1)]);
}

#[test]
fn a_lost_device_is_an_error_and_a_new_gpu_renders_the_same_scene() {
    let mut app = lit_sphere();
    app.render_headless(SIZE).expect("frame");
    let before = app.read_display_image().expect("image");
    let gpu = app.world().resource::<lumen::render::device::Gpu>().clone();
    gpu.device.destroy();
    let err = app
        .render_headless(SIZE)
        .expect_err("no frame on a lost device");
    assert!(format!("{err}").contains("device was lost"), "{err}");
    assert!(app.gpu_lost().is_some());
    app.attach_gpu(common::gpu()).expect("a new device");
    assert_eq!(app.gpu_lost(), None);
    app.render_headless(SIZE).expect("frame on the new device");
    assert_eq!(app.read_display_image().expect("image"), before);
}

/// Moves every point light along +x at 1 m/s, by the frame's time step.
fn slide_light(time: Res<Time>, mut lights: Query<&mut Transform, With<PointLight>>) {
    for mut t in &mut lights {
        t.translation.x += 1.0 * time.delta_secs();
    }
}

#[test]
fn a_light_moved_by_time_covers_the_same_distance_at_any_fixed_step() {
    for (step, updates) in [(1.0f32 / 60.0, 120), (1.0 / 30.0, 60)] {
        let mut app = App::new();
        app.set_fixed_delta(Some(step));
        let light = app
            .world_mut()
            .spawn((PointLight::default(), Transform::IDENTITY))
            .id();
        app.add_systems(slide_light);
        for _ in 0..updates {
            app.update();
        }
        let x = app
            .world()
            .get::<Transform>(light)
            .expect("light")
            .translation
            .x;
        let time = app.world().resource::<Time>();
        assert!((x - 2.0).abs() < 1e-4, "step {step}: x = {x} m");
        assert!((time.elapsed_secs() - 2.0).abs() < 1e-5, "step {step}");
        assert_eq!(time.frame_count(), updates, "step {step}");
    }
}

#[test]
fn a_headless_app_steps_by_a_sixtieth_and_a_frame_rendered_after_an_update_takes_no_second_step() {
    let mut app = lit_sphere();
    app.update();
    app.render_headless(SIZE).expect("frame");
    let time = *app.world().resource::<Time>();
    assert_eq!(time.frame_count(), 1, "update and render are one frame");
    assert_eq!(time.delta_secs(), lumen::time::HEADLESS_DELTA_S);
    app.render_headless(SIZE).expect("frame");
    assert_eq!(
        app.world().resource::<Time>().frame_count(),
        2,
        "a render alone steps"
    );
}

/// Counts the updates that saw `Space` just pressed, and those that saw it held.
#[derive(Resource, Default)]
struct SpaceSeen {
    just_pressed: u32,
    held: u32,
}

fn watch_space(keys: Res<Keys>, mut seen: ResMut<SpaceSeen>) {
    seen.just_pressed += u32::from(keys.just_pressed(KeyCode::Space));
    seen.held += u32::from(keys.pressed(KeyCode::Space));
}

#[test]
fn an_injected_key_press_is_just_pressed_for_exactly_one_update() {
    let mut app = App::new();
    app.world_mut().init_resource::<SpaceSeen>();
    app.add_systems(watch_space);
    app.update();
    app.send_input(InputEvent::Key {
        code: KeyCode::Space,
        pressed: true,
    });
    for _ in 0..4 {
        app.update();
    }
    let seen = app.world().resource::<SpaceSeen>();
    assert_eq!((seen.just_pressed, seen.held), (1, 4));
    app.send_input(InputEvent::Key {
        code: KeyCode::Space,
        pressed: false,
    });
    app.update();
    assert!(app.world().resource::<Keys>().just_released(KeyCode::Space));
    app.update();
    let keys = app.world().resource::<Keys>();
    assert!(!keys.pressed(KeyCode::Space) && !keys.just_released(KeyCode::Space));
    assert_eq!(app.world().resource::<SpaceSeen>().held, 4);
}

#[test]
fn an_app_sent_nothing_sees_no_input() {
    let mut app = App::new();
    app.update();
    let world = app.world();
    assert_eq!(world.resource::<Keys>().get_pressed().count(), 0);
    assert_eq!(world.resource::<MouseButtons>().get_pressed().count(), 0);
    assert_eq!(*world.resource::<Mouse>(), Mouse::default());
}

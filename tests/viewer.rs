//! The viewer's debug views, rendered headless: each shows the channel it names, with
//! the encoding `lumen::render::post::debug_view` documents, for a scene whose every value is
//! known. Tolerance: 1.5 of 255 per channel (8-bit rounding of the display image).

use lumen::FrameTarget;
use lumen::assets::procedural::plane;
use lumen::prelude::*;
use lumen::render::extract::ExtractedFrame;
use lumen::render::graph::PassId;
use lumen::render::post::debug_view::depth_grey;
use lumen::scene::camera::circle_of_confusion;
use lumen::scene::{DepthOfField, Lens};
use lumen::shading::color::srgb_encode;

const SIZE: (u32, u32) = (64, 48);
const NEAR_COLOR: Vec3 = Vec3::new(0.8, 0.2, 0.05);
const FAR_COLOR: Vec3 = Vec3::new(0.1, 0.5, 0.9);

/// Looking straight down from 2 m: the floor (far, right half of the frame) at 2 m and a
/// raised plate (near, left half) at 1 m; a shadowed sun; focus on the floor.
fn scene() -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let floor = app.add_mesh(plane(40.0, 40.0)).expect("floor");
    let plate = app.add_mesh(plane(20.0, 40.0)).expect("plate");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(FAR_COLOR, 1.0, 0.25),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(plate),
        Material {
            occlusion: 0.5,
            ..Material::new(NEAR_COLOR, 0.25, 0.75)
        },
        Transform::from_xyz(-10.0, 1.0, 0.0),
    ));
    world.spawn((
        DirectionalLight {
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(-1.0, 3.0, 0.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            lens: Lens {
                aperture_f_stops: 1.4,
                focus_distance_m: 2.0,
                ..Lens::default()
            },
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 2.0, 0.0).looking_at(Vec3::ZERO, Vec3::NEG_Z),
    ));
    app
}

fn render(app: &mut App, view: DebugView) -> image::RgbaImage {
    app.world_mut().insert_resource(view);
    let report = app.render_headless(SIZE).expect("frame");
    assert_eq!(report.plan.runs(PassId::DebugView), view != DebugView::Off);
    assert_eq!(report.plan.runs(PassId::Tonemap), view == DebugView::Off);
    app.read_display_image().expect("image")
}

/// The pixel at the middle of the near (left) and far (right) halves.
fn near_far(image: &image::RgbaImage) -> ([u8; 3], [u8; 3]) {
    let (w, h) = image.dimensions();
    let p = |x: u32| {
        let q = image.get_pixel(x, h / 2).0;
        [q[0], q[1], q[2]]
    };
    (p(w / 4), p(3 * w / 4))
}

fn bytes(v: Vec3) -> [f32; 3] {
    [v.x * 255.0, v.y * 255.0, v.z * 255.0]
}

fn assert_close(view: DebugView, side: &str, got: [u8; 3], want: [f32; 3]) {
    for c in 0..3 {
        assert!(
            (f32::from(got[c]) - want[c]).abs() <= 1.5,
            "{}: {side} pixel {got:?}, expected {want:?}",
            view.name()
        );
    }
}

#[test]
fn each_gbuffer_view_shows_its_channel() {
    let mut app = scene();
    let encode = |c: Vec3| Vec3::new(srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z));
    let up = bytes(Vec3::new(0.5, 1.0, 0.5));
    let occlusion_near = (0.5f32 * 127.0).round() / 127.0;
    let cases = [
        (
            DebugView::Albedo,
            bytes(encode(NEAR_COLOR)),
            bytes(encode(FAR_COLOR)),
        ),
        (DebugView::Normal, up, up),
        (
            DebugView::Metallic,
            bytes(Vec3::splat(0.25)),
            bytes(Vec3::ONE),
        ),
        (
            DebugView::Roughness,
            bytes(Vec3::splat(0.75)),
            bytes(Vec3::splat(0.25)),
        ),
        (
            DebugView::Occlusion,
            bytes(Vec3::splat(occlusion_near)),
            bytes(Vec3::ONE),
        ),
        (
            DebugView::Depth,
            bytes(Vec3::splat(depth_grey(1.0))),
            bytes(Vec3::splat(depth_grey(2.0))),
        ),
    ];
    let mut shown = Vec::new();
    for (view, near, far) in cases {
        let image = render(&mut app, view);
        let (got_near, got_far) = near_far(&image);
        assert_close(view, "near", got_near, near);
        assert_close(view, "far", got_far, far);
        shown.push((view, image));
    }
    // Back to the normal image: different from every debug view.
    let image = render(&mut app, DebugView::Off);
    for (view, debug) in &shown {
        assert_ne!(
            &image,
            debug,
            "the tone-mapped image is not the {} view",
            view.name()
        );
    }
}

#[test]
fn the_coc_view_matches_the_thin_lens() {
    let mut app = scene();
    // At 64×48 the plate's CoC is a fraction of a pixel: show radii up to half a pixel.
    let dof = DepthOfField {
        max_coc_px: 1.0,
        ..DepthOfField::default()
    };
    let world = app.world_mut();
    let mut cameras = world.query::<&mut Camera>();
    for mut c in cameras.iter_mut(world) {
        c.depth_of_field = Some(dof);
    }
    let image = render(&mut app, DebugView::CircleOfConfusion);
    let camera = app
        .world()
        .resource::<ExtractedFrame>()
        .camera
        .clone()
        .expect("camera");
    let lens = camera.lens;
    let radius_px = |z: f32| {
        circle_of_confusion(
            z,
            lens.focus_distance_m,
            camera.focal_length_m,
            camera.focal_length_m / lens.aperture_f_stops,
        ) * SIZE.1 as f32
            / (lens.sensor_height_mm * 1e-3)
            * 0.5
    };
    let max_radius = dof.max_coc_px * 0.5;
    let near = radius_px(1.0);
    assert!(near < 0.0, "the plate is in front of the focus plane");
    let (got_near, got_far) = near_far(&image);
    let grey = (near.abs() / max_radius).min(1.0) * 255.0;
    assert!(grey > 20.0, "a visible CoC: {grey}");
    assert_close(
        DebugView::CircleOfConfusion,
        "near",
        got_near,
        [grey, 0.0, 0.0],
    );
    // The floor is in focus.
    assert_close(DebugView::CircleOfConfusion, "far", got_far, [0.0; 3]);
}

#[test]
fn the_shadow_view_shows_the_atlas() {
    let mut app = scene();
    let image = render(&mut app, DebugView::ShadowAtlas);
    let h = SIZE.1 as f32;
    let atlas = match app.read_target(FrameTarget::ShadowAtlas) {
        Ok(atlas) => atlas,
        Err(e) => {
            // GL cannot read depth back: check that the atlas is drawn (some casters,
            // some cleared texels) and that nothing lies right of it.
            eprintln!("{e}; checking the view's layout only");
            let grey: Vec<u8> = image.pixels().map(|p| p.0[0]).collect();
            assert!(grey.iter().any(|&g| g > 0) && grey.contains(&0), "{e}");
            let right = image.get_pixel(SIZE.0 - 1, SIZE.1 / 2).0;
            assert_eq!(right[..3], [0, 0, 0]);
            return;
        }
    };
    let side = atlas.width();
    assert!(side > 1, "the sun has a shadow map");
    let (mut compared, mut covered) = (0, 0);
    for (x, y, p) in image.enumerate_pixels() {
        let t = |v: u32| ((v as f32 + 0.5) * side as f32 / h) as u32;
        if t(x) >= side {
            assert_eq!(p.0[..3], [0, 0, 0], "outside the atlas at ({x}, {y})");
            continue;
        }
        let depth = atlas.get_pixel(t(x), t(y)).0[0];
        assert_close(
            DebugView::ShadowAtlas,
            "atlas",
            [p.0[0], p.0[1], p.0[2]],
            [depth * 255.0; 3],
        );
        compared += 1;
        covered += usize::from(depth > 0.0);
    }
    assert!(compared == (SIZE.1 * SIZE.1) as usize, "{compared} pixels");
    assert!(
        covered > compared / 10,
        "casters drawn: {covered} of {compared}"
    );
}

/// What the scene holds: meshes, active cameras, directional lights, environments.
fn census(app: &mut App) -> (usize, usize, usize, usize) {
    let world = app.world_mut();
    (
        world.query::<&Mesh3d>().iter(world).count(),
        world
            .query::<&Camera>()
            .iter(world)
            .filter(|c| c.active)
            .count(),
        world.query::<&DirectionalLight>().iter(world).count(),
        world.query::<&Environment>().iter(world).count(),
    )
}

#[test]
fn opening_files_replaces_the_model_keeps_the_environment_and_survives_bad_files() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut app = scene();
    let open = lumen_game::view::open_file;
    let hdr = root.join("assets/hdri/sunset.exr");
    let line = open(&mut app, &hdr).expect("an EXR environment");
    assert!(line.contains("sunset.exr"), "{line}");
    assert_eq!(census(&mut app), (2, 1, 1, 1));

    // A broken model, an unknown type and a missing file leave the scene as it was.
    for bad in [
        root.join("tests/data/gltf/nan_position.gltf"),
        root.join("tests/data/gltf/missing_bin.gltf"),
        root.join("README.md"),
        root.join("no-such-model.glb"),
    ] {
        let err = open(&mut app, &bad).expect_err("a bad file");
        let name = bad.file_name().and_then(|n| n.to_str()).expect("name");
        assert!(format!("{err:#}").contains(name), "{err:#}");
        assert_eq!(census(&mut app), (2, 1, 1, 1), "after {name}");
    }

    // The bunny replaces the plates, its default camera and sun replace the scene's,
    // and the environment stays (the loader adds no sky).
    let line = open(&mut app, &root.join("assets/models/bunny.glb")).expect("bunny");
    assert!(line.contains("5648 triangles"), "{line}");
    assert_eq!(census(&mut app), (1, 1, 1, 1));
    // The new camera frames the bunny: it covers a good part of the frame.
    app.world_mut().insert_resource(DebugView::Depth);
    app.render_headless(SIZE).expect("frame");
    let image = app.read_display_image().expect("image");
    let covered = image.pixels().filter(|p| p.0[0] > 0).count();
    let share = covered as f32 / (SIZE.0 * SIZE.1) as f32;
    assert!((0.05..0.9).contains(&share), "bunny covers {share}");
}

#[test]
fn a_screenshot_is_the_display_image_and_the_linear_hdr() {
    let mut app = scene();
    let dir = tempfile::tempdir().expect("temp dir");
    let base = dir.path().join("shots/screenshot-1");
    let [png, exr] = lumen_game::view::save_screenshot(&mut app, SIZE, &base).expect("saved");
    assert_eq!(png, dir.path().join("shots/screenshot-1.png"));
    let display = image::open(&png).expect("PNG").to_rgba8();
    assert_eq!(display, app.read_display_image().expect("display image"));
    let hdr = image::open(&exr).expect("EXR").to_rgba32f();
    let live = app.read_hdr_image().expect("HDR");
    assert_eq!(hdr.dimensions(), live.dimensions());
    let (a, b) = (hdr.get_pixel(16, 24).0, live.get_pixel(16, 24).0);
    assert!(a[0] > 0.0, "lit: {a:?}");
    for c in 0..3 {
        assert!((a[c] - b[c]).abs() <= 1e-3 * b[c].abs(), "{a:?} vs {b:?}");
    }
}

#[test]
fn render_takes_a_debug_view_on_the_command_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let run = |view: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_lumen"))
            .args([
                "render",
                "--scene",
                "plane",
                "--size",
                "32x24",
                "--debug-view",
                view,
            ])
            .args(["--out", "n.png"])
            .current_dir(dir.path())
            .env_remove("DISPLAY")
            .output()
            .expect("lumen runs")
    };
    let out = run("normal");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let image = image::open(dir.path().join("n.png"))
        .expect("PNG")
        .to_rgba8();
    // `plane`'s quad faces the camera along +Z: (0.5, 0.5, 1) in the middle of the frame.
    let p = image.get_pixel(16, 12).0;
    assert!(
        p[0].abs_diff(128) <= 1 && p[1].abs_diff(128) <= 1 && p[2] >= 254,
        "{p:?}"
    );
    let out = run("albedoo");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("unknown debug view 'albedoo'") && err.contains("shadow-atlas"),
        "{err}"
    );
}

#[test]
fn the_validation_views_paint_the_validators_verdicts() {
    use lumen::validate::metal_rough_verdict;
    let mut app = scene();
    // The plate: a dark dielectric (45 sRGB: valid, but under the strict 50); the floor:
    // bare metal at 200 sRGB (valid). Exact sRGB codes survive the 8-bit G-buffer.
    let code = |c: f32| Vec3::splat(lumen::shading::color::srgb_decode(c / 255.0));
    let world = app.world_mut();
    let mut materials = world.query::<&mut Material>();
    for mut m in materials.iter_mut(world) {
        if m.metallic < 0.5 {
            *m = Material::new(code(45.0), 0.0, 0.5);
        } else {
            *m = Material::new(code(200.0), 1.0, 0.5);
        }
    }
    for (view, strict) in [
        (DebugView::Validation, false),
        (DebugView::ValidationStrict, true),
    ] {
        let image = render(&mut app, view);
        let (near, far) = near_far(&image);
        let want_near = metal_rough_verdict(code(45.0), 0.0, strict).color();
        let want_far = metal_rough_verdict(code(200.0), 1.0, strict).color();
        let to_f = |c: [u8; 3]| c.map(f32::from);
        assert_close(view, "near", near, to_f(want_near));
        assert_close(view, "far", far, to_f(want_far));
    }
    // The two views differ exactly on the plate.
    assert_eq!(
        metal_rough_verdict(code(45.0), 0.0, false),
        lumen::validate::Verdict::Valid
    );
    assert_eq!(
        metal_rough_verdict(code(45.0), 0.0, true),
        lumen::validate::Verdict::Invalid
    );
}

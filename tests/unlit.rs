//! Unlit materials (`Material::unlit`, glTF's `KHR_materials_unlit`): the frame shows the
//! base colour as it is, pre-exposed, whatever the lights, the environment and the
//! exposure; the path tracer agrees; a blended unlit pane covers what is behind it by its
//! alpha.

use crate::common;

use glam::{Quat, Vec3};
use lumen::App;
use lumen::prelude::*;
use lumen::reference::path::{ReferenceOptions, render};
use lumen::trace_input::trace_scene;

const SIZE: (u32, u32) = (64, 64);

/// The opaque wall's and the pane's colours (linear).
const WALL: Vec3 = Vec3::new(0.8, 0.3, 0.1);
const PANE: Vec3 = Vec3::new(0.1, 0.5, 0.9);

/// Facing +z (the camera): a plane's +y normal turned towards the viewer.
const FACING_CAMERA: Quat = Quat::from_xyzw(
    std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
);

/// An unlit wall filling the view at z = 0, a blended unlit pane (alpha 0.5) over its
/// right half, a bright sun and a grey environment; the camera's exposure is `ev100`.
fn scene(ev100: f32, sun_lux: f32) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let quad = app
        .add_mesh(lumen::assets::procedural::plane(4.0, 4.0))
        .expect("mesh");
    let pane = app
        .add_mesh(lumen::assets::procedural::plane(1.0, 2.0))
        .expect("mesh");
    let world = app.world_mut();
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(ev100),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Mesh3d(quad),
        Material::unlit(WALL),
        Transform::IDENTITY.with_rotation(FACING_CAMERA),
    ));
    world.spawn((
        Mesh3d(pane),
        Material {
            blend: true,
            base_color: PANE.extend(0.5),
            ..Material::unlit(PANE)
        },
        Transform::from_xyz(0.6, 0.0, 0.5).with_rotation(FACING_CAMERA),
    ));
    world.spawn((
        DirectionalLight {
            illuminance_lux: sun_lux,
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(1.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn(Environment::uniform(Vec3::splat(2500.0)));
    app
}

/// The mean over a 5×5 block around world point `p`.
fn at(app: &App, image: &image::Rgba32FImage, p: Vec3) -> Vec3 {
    common::block_mean(app, image, p, 2)
}

#[test]
fn unlit_surfaces_show_their_base_colour_under_any_light_and_exposure() {
    // Stored as 8-bit sRGB in the G-buffer: within 0.005 of the linear colour.
    let wall_point = Vec3::new(-0.8, 0.0, 0.0);
    let pane_point = Vec3::new(0.6, 0.0, 0.5);
    let blended = PANE * 0.5 + WALL * 0.5;
    for (ev100, sun) in [(12.0, 100_000.0), (6.0, 0.0), (15.0, 10.0)] {
        let mut app = scene(ev100, sun);
        app.render_headless(SIZE).expect("frame");
        let frame = app.read_hdr_image().expect("readback");
        let wall = at(&app, &frame, wall_point);
        let pane = at(&app, &frame, pane_point);
        println!("EV100 {ev100}, sun {sun} lx: wall {wall}, pane over it {pane}");
        assert!((wall - WALL).abs().max_element() < 0.005, "{wall}");
        assert!((pane - blended).abs().max_element() < 0.005, "{pane}");
    }
}

#[test]
fn the_path_tracer_sees_the_same_unlit_colours() {
    // Paths end at an unlit surface with its base colour: no noise from the lights or the
    // environment, so the wall holds to 0.005; the pane's coverage is stochastic in the
    // path tracer (64 samples per pixel, 0.03).
    let mut app = scene(12.0, 100_000.0);
    app.render_headless(SIZE).expect("frame");
    let scene = trace_scene(&mut app, SIZE).expect("trace scene");
    let options = ReferenceOptions {
        size: SIZE,
        samples_per_pixel: 64,
        max_bounces: 4,
        seed: 1,
    };
    let traced = render(&scene, &options, &|_| {}).image;
    let wall = at(&app, &traced, Vec3::new(-0.8, 0.0, 0.0));
    let pane = at(&app, &traced, Vec3::new(0.6, 0.0, 0.5));
    println!("path tracer: wall {wall}, pane over it {pane}");
    assert!((wall - WALL).abs().max_element() < 0.005, "{wall}");
    let blended = PANE * 0.5 + WALL * 0.5;
    assert!((pane - blended).abs().max_element() < 0.03, "{pane}");
}

#[test]
fn an_unlit_material_drops_its_transmission_and_stays_opaque() {
    // Unlit wins over transmission: the instance stays in the G-buffer (no transmission
    // source), and it still shows its colour.
    let mut app = scene(12.0, 100_000.0);
    let world = app.world_mut();
    let mut q = world.query::<&mut Material>();
    for mut m in q.iter_mut(world) {
        if !m.blend {
            m.transmission = Some(lumen::scene::Transmission::default());
        }
    }
    let report = app.render_headless(SIZE).expect("frame");
    let source = report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == lumen::render::graph::PassId::TransmissionSource)
        .map(|(_, d)| d.clone())
        .expect("the pass is in the plan");
    assert!(!source.enabled, "{}", source.reason);
    let frame = app.read_hdr_image().expect("readback");
    let wall = at(&app, &frame, Vec3::new(-0.8, 0.0, 0.0));
    assert!((wall - WALL).abs().max_element() < 0.005, "{wall}");
}

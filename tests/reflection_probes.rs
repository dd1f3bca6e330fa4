//! Reflection probes: the floor seen in the metal spheres of `spheres` against the path
//! tracer, capture bookkeeping (a probe captured once is not captured again while the
//! scene is unchanged), two probes' blend, the plan's reasons, and robustness (a probe
//! inside a mesh, a box of zero size).

use crate::common;

use lumen::assets::procedural::{cuboid, plane, uv_sphere};
use lumen::prelude::*;
use lumen::reference::path::{ReferenceOptions, render};
use lumen::trace_input::trace_scene;
use lumen_game::scenes::spheres::{SPHERE_RADIUS, sphere_center};

/// Within this fraction of the reference.
const TOLERANCE: f32 = 0.35;

#[test]
fn the_floor_appears_in_the_metal_spheres() {
    let size = (320, 180);
    let mut app = common::app_with("spheres");
    // Screen-space reflections off: what the lower halves show comes from the probe.
    app.world_mut().resource_mut::<Quality>().ssr.enabled = false;
    let traced = trace_scene(&mut app, size).expect("trace scene");
    let options = ReferenceOptions {
        size,
        samples_per_pixel: 128,
        max_bounces: 8,
        seed: 9,
    };
    let truth = render(&traced, &options, &|_| {}).image;
    let report = app.render_headless(size).expect("frame");
    assert!(decision(&report).0, "{:?}", decision(&report));
    let with_probe = app.read_hdr_image().expect("hdr");
    app.world_mut()
        .resource_mut::<Quality>()
        .reflection_probes
        .enabled = false;
    app.render_headless(size).expect("frame without probes");
    let without = app.read_hdr_image().expect("hdr");
    // Nine points on the lower front of each of the three smoothest fully metallic
    // spheres (the top row): 20°, 40° and 60° below the equator, straight ahead and 30° to
    // either side, one pixel each.
    let mut lines = Vec::new();
    for i in 0..3 {
        let (mut w, mut r, mut o) = (0.0, 0.0, 0.0);
        for below in [20f32, 40.0, 60.0] {
            for side in [-30f32, 0.0, 30.0] {
                let (b, a) = (below.to_radians(), side.to_radians());
                let n = Vec3::new(b.cos() * a.sin(), -b.sin(), b.cos() * a.cos());
                let at = common::pixel_of(&app, sphere_center(i, 6) + SPHERE_RADIUS * n, size);
                let sum = |image: &image::Rgba32FImage| {
                    let p = image.get_pixel(at.0, at.1).0;
                    p[0] + p[1] + p[2]
                };
                w += sum(&with_probe) / 9.0;
                r += sum(&truth) / 9.0;
                o += sum(&without) / 9.0;
            }
        }
        lines.push(format!(
            "sphere ({i}, 6), lower half: probe {w:.3}, reference {r:.3}, no probe {o:.3}"
        ));
        assert!((w / r - 1.0).abs() <= TOLERANCE, "{}", lines.join("\n"));
        assert!(o < 0.5 * r, "without the probe: {}", lines.join("\n"));
    }
    println!("{}", lines.join("\n"));
}

fn small_scene() -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let floor = app.add_mesh(plane(10.0, 10.0)).expect("floor");
    let sphere = app.add_mesh(uv_sphere(0.5, 32, 16)).expect("sphere");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::splat(0.6), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::splat(0.9), 1.0, 0.1),
        Transform::from_xyz(0.0, 0.5, 0.0),
    ));
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(12.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 1.5, 4.0).looking_at(Vec3::new(0.0, 0.4, 0.0), Vec3::Y),
    ));
    world.spawn((
        ReflectionProbe::new(Vec3::new(5.0, 3.0, 5.0)),
        Transform::from_xyz(0.0, 1.0, 1.0),
    ));
    let mut quality = world.resource_mut::<Quality>();
    quality.gi.enabled = false;
    quality.reflection_probes.face_size = 16;
    app
}

/// The one reflection probe of `small_scene`.
fn scene_probe(world: &mut World) -> Entity {
    world
        .query_filtered::<Entity, With<ReflectionProbe>>()
        .single(world)
        .expect("probe")
}

const SIZE: (u32, u32) = (48, 32);

fn decision(report: &FrameReport) -> (bool, String) {
    let d = report
        .plan
        .features
        .iter()
        .find(|d| d.name == "reflection probes")
        .expect("the plan has a reflection-probe decision");
    (d.enabled, d.reason.clone())
}

#[test]
fn a_probe_captured_once_is_not_captured_again_until_the_scene_changes() {
    let mut app = small_scene();
    let first = app.render_headless(SIZE).expect("frame");
    assert_eq!(first.probes.reflections.captured, 1);
    assert!(decision(&first).0, "{:?}", decision(&first));
    for _ in 0..2 {
        let again = app.render_headless(SIZE).expect("frame");
        assert_eq!(again.probes.reflections.captured, 0, "nothing changed");
    }
    let sphere = app
        .world_mut()
        .query_filtered::<Entity, With<Mesh3d>>()
        .iter(app.world())
        .nth(1)
        .expect("the sphere");
    app.world_mut()
        .entity_mut(sphere)
        .insert(Transform::from_xyz(0.2, 0.5, 0.0));
    let moved = app.render_headless(SIZE).expect("frame");
    assert_eq!(moved.probes.reflections.captured, 1, "the sphere moved");
    app.world_mut()
        .resource_mut::<Quality>()
        .reflection_probes
        .enabled = false;
    let off = app.render_headless(SIZE).expect("frame");
    assert_eq!(
        decision(&off),
        (
            false,
            "reflection probes off (reflection-probes = off)".into()
        )
    );
}

#[test]
fn no_nan_with_a_probe_inside_a_mesh_or_a_box_of_zero_size() {
    for (label, position, half) in [
        (
            "inside the sphere",
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::splat(3.0),
        ),
        ("zero-size box", Vec3::new(0.0, 1.0, 1.0), Vec3::ZERO),
    ] {
        let mut app = small_scene();
        let cube = app.add_mesh(cuboid(Vec3::ONE)).expect("box");
        let world = app.world_mut();
        world.spawn((
            Mesh3d(cube),
            Material::new(Vec3::splat(0.7), 0.0, 0.6),
            Transform::from_xyz(2.0, 0.5, 0.0),
        ));
        let probe = scene_probe(world);
        world.entity_mut(probe).insert((
            ReflectionProbe::new(half),
            Transform::from_translation(position),
        ));
        let report = app.render_headless(SIZE).expect(label);
        assert_eq!(report.probes.reflections.captured, 1, "{label}");
        common::assert_finite(&app);
    }
    // No probe of its own and automatic placement off: no probe work, with the reason.
    let mut app = small_scene();
    let world = app.world_mut();
    let probe = scene_probe(world);
    world.despawn(probe);
    world.resource_mut::<Quality>().reflection_probes.auto_place = false;
    let report = app.render_headless(SIZE).expect("frame");
    assert_eq!(
        decision(&report),
        (
            false,
            "no ReflectionProbe, and automatic placement is off".into()
        )
    );
    assert_eq!(report.probes.reflections.captured, 0);
    // No mesh at all: no probe, with its reason.
    let mut app = App::headless().expect("a GPU adapter");
    app.world_mut()
        .spawn((Camera::default(), Transform::from_xyz(0.0, 0.0, 3.0)));
    let report = app.render_headless(SIZE).expect("empty frame");
    assert_eq!(
        decision(&report),
        (false, "no mesh to place a probe among".into())
    );
    common::assert_finite(&app);
}
/// `small_scene` with a red and a green box standing off-centre, without screen-space
/// reflections, and with those of two probes on either side of the sphere that `which`
/// keeps. Captured from either side, the two probes reflect the boxes at different places
/// on the sphere.
fn two_probe_scene(which: [bool; 2]) -> App {
    let mut app = small_scene();
    let cube = app.add_mesh(cuboid(Vec3::splat(0.8))).expect("box");
    let world = app.world_mut();
    let probe = scene_probe(world);
    world.despawn(probe);
    for (colour, x, z) in [
        (Vec3::new(0.8, 0.05, 0.05), -1.3, 0.6),
        (Vec3::new(0.05, 0.8, 0.05), 1.3, -0.6),
    ] {
        world.spawn((
            Mesh3d(cube),
            Material::new(colour, 0.0, 0.6),
            Transform::from_xyz(x, 0.4, z),
        ));
    }
    for (keep, position) in which
        .into_iter()
        .zip([Vec3::new(-1.5, 1.0, 1.5), Vec3::new(1.5, 1.0, -1.5)])
    {
        if keep {
            world.spawn((
                ReflectionProbe::new(Vec3::new(5.0, 3.0, 5.0)),
                Transform::from_translation(position),
            ));
        }
    }
    world.resource_mut::<Quality>().ssr.enabled = false;
    app
}

/// Two probes whose boxes both hold the mirror sphere deep inside (weight 1 each) blend
/// equally there: the frame with both is, on the sphere's pixels, the mean of the frames
/// with each alone. It also runs the shaders compiled for two probe slots
/// (`REFLECTION_PROBE_SLOTS` 2).
#[test]
fn two_probes_blend_by_their_box_weights() {
    let size = (96, 64);
    let mut frames = Vec::new();
    for which in [[true, true], [true, false], [false, true]] {
        let mut app = two_probe_scene(which);
        let report = app.render_headless(size).expect("frame");
        let placed = which.iter().filter(|k| **k).count();
        assert_eq!(
            decision(&report),
            (
                true,
                format!("{placed} placed, {placed} captured (parallax-corrected boxes)")
            )
        );
        common::assert_finite(&app);
        frames.push((app.read_hdr_image().expect("hdr"), app));
    }
    // The sphere's pixels: points on the part of it that faces the camera (radius 0.5 at
    // (0, 0.5, 0)), every 10°, away from its rim, past which lies floor outside one box.
    let app = &frames[0].1;
    let mut pixels = Vec::new();
    for up in (-80..=80).step_by(10) {
        for side in (-80..=80).step_by(10) {
            let (b, a) = ((up as f32).to_radians(), (side as f32).to_radians());
            let n = Vec3::new(b.cos() * a.sin(), b.sin(), b.cos() * a.cos());
            let toward = (Vec3::new(0.0, 1.5, 4.0) - Vec3::new(0.0, 0.5, 0.0)).normalize();
            if n.dot(toward) > 0.6 {
                pixels.push(common::pixel_of(
                    app,
                    Vec3::new(0.0, 0.5, 0.0) + 0.5 * n,
                    size,
                ));
            }
        }
    }
    pixels.sort_unstable();
    pixels.dedup();
    let sum = |image: &image::Rgba32FImage, (x, y): (u32, u32)| {
        let p = image.get_pixel(x, y).0;
        p[0] + p[1] + p[2]
    };
    let (mut worst, mut apart) = (0f32, 0f32);
    for &at in &pixels {
        let (both, a, b) = (
            sum(&frames[0].0, at),
            sum(&frames[1].0, at),
            sum(&frames[2].0, at),
        );
        let mean = 0.5 * (a + b);
        worst = worst.max((both - mean).abs() / mean.max(1e-6));
        apart = apart.max((a - b).abs() / mean.max(1e-6));
    }
    println!(
        "{} sphere pixels: both against the mean of each alone, worst {worst:.4}; the two alone differ by up to {apart:.3} of their mean",
        pixels.len()
    );
    // The two alone must differ for the mean to say anything.
    assert!(apart > 0.2, "the probes reflect the same: {apart}");
    assert!(
        worst < 0.003,
        "both against the mean of each alone: {worst}"
    );
}

/// A mirror sphere on a floor, a red wall to its left, and a probe above and in front:
/// the probe's reflection of the floor (below) and of the wall (left) against the path
/// tracer, pixel by pixel. This checks the capture, the face orientation, the prefilter
/// and the parallax correction together.
#[test]
fn a_mirror_sphere_reflects_what_the_path_tracer_sees() {
    let size = (160, 120);
    let mut app = App::headless().expect("a GPU adapter");
    let floor = app.add_mesh(plane(10.0, 10.0)).expect("floor");
    let sphere = app.add_mesh(uv_sphere(0.5, 48, 24)).expect("sphere");
    let wall = app
        .add_mesh(cuboid(Vec3::new(0.5, 2.0, 2.0)))
        .expect("wall");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::splat(0.5), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::splat(0.9), 1.0, 0.05),
        Transform::from_xyz(0.0, 0.5, 0.0),
    ));
    world.spawn((
        Mesh3d(wall),
        Material::new(Vec3::new(0.9, 0.05, 0.05), 0.0, 0.8),
        Transform::from_xyz(-2.0, 1.0, 0.0),
    ));
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(0.5, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(12.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.6, 3.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
    world.spawn((
        ReflectionProbe::new(Vec3::splat(5.0)),
        Transform::from_xyz(0.0, 1.2, 1.0),
    ));
    {
        let mut quality = world.resource_mut::<Quality>();
        quality.gi.enabled = false;
        quality.ssr.enabled = false;
    }
    let traced = trace_scene(&mut app, size).expect("trace scene");
    let options = ReferenceOptions {
        size,
        samples_per_pixel: 64,
        max_bounces: 2,
        seed: 1,
    };
    let truth = render(&traced, &options, &|_| {}).image;
    app.render_headless(size).expect("frame");
    let with_probe = app.read_hdr_image().expect("hdr");
    app.world_mut()
        .resource_mut::<Quality>()
        .reflection_probes
        .enabled = false;
    app.render_headless(size).expect("frame without the probe");
    let without = app.read_hdr_image().expect("hdr");
    for (label, n) in [
        ("floor, below", Vec3::new(0.0, -0.6, 0.8)),
        ("red wall, left", Vec3::new(-0.7, 0.0, 0.7)),
    ] {
        let at = common::pixel_of(&app, Vec3::new(0.0, 0.5, 0.0) + 0.5 * n.normalize(), size);
        let (p, r, o) = (
            with_probe.get_pixel(at.0, at.1).0,
            truth.get_pixel(at.0, at.1).0,
            without.get_pixel(at.0, at.1).0,
        );
        println!("{label} at {at:?}: probe {p:?}, reference {r:?}, no probe {o:?}");
        let peak = r[0].max(r[1]).max(r[2]);
        for c in 0..3 {
            assert!(
                (p[c] - r[c]).abs() <= MIRROR_TOLERANCE * peak,
                "{label}, channel {c}: probe {p:?} against {r:?}"
            );
            assert!(o[c] < 0.05 * peak, "{label} without the probe: {o:?}");
        }
    }
}

/// Per channel, against the path tracer, on the mirror sphere: the difference as a
/// fraction of the reference pixel's brightest channel.
const MIRROR_TOLERANCE: f32 = 0.15;

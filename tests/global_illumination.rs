//! Diffuse global illumination from the irradiance volume: colour bleeding in `cornell`
//! against the path tracer, capture bookkeeping (a converged volume is not captured again
//! until the scene changes; progressive capture spreads probes over frames), the plan's
//! reasons, and robustness at the extremes (no mesh, a probe inside a mesh, a box of zero
//! size, one probe, bounds that are not finite).

use crate::common;

use lumen::assets::procedural::{cuboid, plane, uv_sphere};
use lumen::prelude::*;
use lumen::quality::GiSettings;
use lumen::reference::path::{ReferenceOptions, render};
use lumen::scene::IrradianceVolume;
use lumen::trace_input::trace_scene;
use lumen_game::scenes::cornell::{CORNELL_ROOM, CORNELL_WHITE};

/// Red ÷ green of the summed 3×3 windows around `pixels` of `image`.
fn red_to_green(image: &image::Rgba32FImage, pixels: &[(u32, u32)]) -> f32 {
    let (mut r, mut g) = (0.0, 0.0);
    for &(x, y) in pixels {
        for dy in 0..3 {
            for dx in 0..3 {
                let p = image.get_pixel(x + dx - 1, y + dy - 1).0;
                r += p[0];
                g += p[1];
            }
        }
    }
    r / g
}

/// Within this fraction of the reference's red-to-green ratio (the bound).
const RATIO_TOLERANCE: f32 = 0.15;

#[test]
fn cornell_colour_bleeding_matches_the_path_tracer() {
    let size = (64, 64);
    let mut app = common::app_with("cornell");
    let traced = trace_scene(&mut app, size).expect("trace scene");
    let options = ReferenceOptions {
        size,
        samples_per_pixel: 256,
        max_bounces: 8,
        seed: 5,
    };
    let truth = render(&traced, &options, &|_| {}).image;
    let report = app.render_headless(size).expect("frame");
    assert_eq!(
        report.probes.volume.passes,
        (3, 3),
        "{:?}",
        report.probes.volume
    );
    let with_gi = app.read_hdr_image().expect("hdr");
    // The white back wall, 5 cm from the red wall (x = room width), at four heights.
    let pixels: Vec<(u32, u32)> = [0.15, 0.25, 0.35, 0.45]
        .iter()
        .map(|&y| {
            common::pixel_of(
                &app,
                Vec3::new(CORNELL_ROOM.x - 0.05, y, CORNELL_ROOM.z - 0.001),
                size,
            )
        })
        .collect();
    app.world_mut().resource_mut::<Quality>().gi.enabled = false;
    app.render_headless(size).expect("frame without GI");
    let without = app.read_hdr_image().expect("hdr");
    let reference = red_to_green(&truth, &pixels);
    let gi = red_to_green(&with_gi, &pixels);
    let direct = red_to_green(&without, &pixels);
    println!(
        "red/green on the back wall by the red wall: reference {reference:.3}, with GI {gi:.3}, without {direct:.3}, white {:.3}",
        CORNELL_WHITE.x / CORNELL_WHITE.y
    );
    assert!(
        (gi / reference - 1.0).abs() <= RATIO_TOLERANCE,
        "with GI {gi:.3} against the reference's {reference:.3}"
    );
    // The check can fail: without bounce light the wall keeps its own colour.
    assert!(
        (direct / reference - 1.0).abs() > RATIO_TOLERANCE,
        "without GI {direct:.3} against the reference's {reference:.3}"
    );
}

/// A floor, a sphere and a box in sunlight, a camera, and a 2×1×2 volume of small
/// captures (one pass).
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
        Material::new(Vec3::new(0.8, 0.2, 0.1), 0.0, 0.5),
        Transform::from_xyz(0.0, 0.5, 0.0),
    ));
    world.spawn((
        DirectionalLight {
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(12.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 1.5, 4.0).looking_at(Vec3::new(0.0, 0.4, 0.0), Vec3::Y),
    ));
    world.spawn(IrradianceVolume {
        min: Vec3::new(-1.0, 0.2, -1.0),
        max: Vec3::new(1.0, 1.2, 1.0),
        spacing_m: Some(1.0),
    });
    world.resource_mut::<Quality>().gi = GiSettings {
        face_size: 8,
        bounces: 1,
        ..GiSettings::default()
    };
    app
}

const SIZE: (u32, u32) = (48, 32);

fn volume_reason(report: &FrameReport) -> (bool, String) {
    let d = report
        .plan
        .features
        .iter()
        .find(|d| d.name == "irradiance volume")
        .expect("the plan has an irradiance-volume decision");
    (d.enabled, d.reason.clone())
}

#[test]
fn a_converged_volume_is_captured_again_only_when_the_scene_changes() {
    let mut app = small_scene();
    let first = app.render_headless(SIZE).expect("frame");
    assert_eq!(first.probes.volume.counts, glam::UVec3::new(2, 1, 2));
    assert_eq!(first.probes.volume.faces_captured, 4 * 6);
    assert_eq!(first.probes.volume.passes, (1, 1));
    let again = app.render_headless(SIZE).expect("frame");
    assert_eq!(again.probes.volume.faces_captured, 0, "nothing changed");
    // The camera is not part of what the probes see.
    let camera = app
        .world_mut()
        .query_filtered::<Entity, With<Camera>>()
        .single(app.world())
        .expect("one camera");
    app.world_mut()
        .entity_mut(camera)
        .insert(Transform::from_xyz(1.0, 1.5, 4.0).looking_at(Vec3::ZERO, Vec3::Y));
    let moved_camera = app.render_headless(SIZE).expect("frame");
    assert_eq!(
        moved_camera.probes.volume.faces_captured, 0,
        "only the camera moved"
    );
    // A mesh that moves is.
    let sphere = app
        .world_mut()
        .query_filtered::<Entity, (With<Mesh3d>, Without<Camera>)>()
        .iter(app.world())
        .nth(1)
        .expect("the sphere");
    app.world_mut()
        .entity_mut(sphere)
        .insert(Transform::from_xyz(0.3, 0.5, 0.0));
    let moved = app.render_headless(SIZE).expect("frame");
    assert_eq!(
        moved.probes.volume.faces_captured,
        4 * 6,
        "the sphere moved"
    );
}

#[test]
fn progressive_capture_spreads_probes_over_frames() {
    let mut app = small_scene();
    app.set_progressive_probes(true);
    {
        let mut quality = app.world_mut().resource_mut::<Quality>();
        quality.gi.probes_per_frame = 1;
        quality.gi.bounces = 2;
    }
    let mut captured = Vec::new();
    for _ in 0..10 {
        let report = app.render_headless(SIZE).expect("frame");
        captured.push((
            report.probes.volume.faces_captured,
            report.probes.volume.passes.0,
        ));
    }
    // Four probes, two passes, one probe per frame: eight frames of six faces.
    let faces: Vec<u32> = captured.iter().map(|c| c.0).collect();
    assert_eq!(faces, [6, 6, 6, 6, 6, 6, 6, 6, 0, 0], "{captured:?}");
    assert_eq!(captured[3].1, 1, "the first pass completes on frame 4");
    assert_eq!(captured[7].1, 2);
}

#[test]
fn bounce_light_brightens_the_sphere_s_shadowed_underside() {
    let mut app = small_scene();
    app.render_headless(SIZE).expect("frame");
    // On the sphere's lower front, turned away from the sun and towards the lit floor.
    let at = common::pixel_of(&app, Vec3::new(0.0, 0.1, 0.3), SIZE);
    let lit = app.read_hdr_image().expect("hdr").get_pixel(at.0, at.1).0;
    app.world_mut().resource_mut::<Quality>().gi.enabled = false;
    let report = app.render_headless(SIZE).expect("frame");
    assert_eq!(
        volume_reason(&report),
        (false, "global illumination off (gi = off)".into())
    );
    let dark = app.read_hdr_image().expect("hdr").get_pixel(at.0, at.1).0;
    println!("the sphere's underside at {at:?}: with GI {lit:?}, without {dark:?}");
    let sum = |p: [f32; 4]| p[0] + p[1] + p[2];
    assert!(sum(lit) > sum(dark) * 1.5 + 1e-2, "{lit:?} vs {dark:?}");
}

/// Outside its box the volume's light fades into the environment's over one probe
/// spacing. `small_scene` has no environment, so the floor 1.5 spacings beyond the box
/// shows only the sun, as without GI; before the fade it took the light of the probes at
/// the grid's edge, which see the sunlit sphere beside them. The sphere's shadowed
/// underside, 0.1 spacings below the box, still gets the floor's bounce light.
#[test]
fn the_volume_s_light_fades_out_beyond_its_box() {
    let mut app = small_scene();
    app.render_headless(SIZE).expect("frame");
    let with_gi = app.read_hdr_image().expect("hdr");
    app.world_mut().resource_mut::<Quality>().gi.enabled = false;
    app.render_headless(SIZE).expect("frame");
    let without = app.read_hdr_image().expect("hdr");
    let luminance = |img: &image::Rgba32FImage, p: Vec3| {
        let (x, y) = common::pixel_of(&app, p, SIZE);
        let q = img.get_pixel(x, y).0;
        0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2]
    };
    let far = Vec3::new(-2.5, 0.0, 1.0);
    let (far_gi, far_off) = (luminance(&with_gi, far), luminance(&without, far));
    let near = Vec3::new(0.0, 0.1, 0.3);
    let (near_gi, near_off) = (luminance(&with_gi, near), luminance(&without, near));
    println!(
        "floor beyond the box: {far_gi} with GI, {far_off} without; \
         the sphere's underside: {near_gi}, {near_off}"
    );
    assert!(far_off > 0.05, "the far floor is sunlit: {far_off}");
    assert!(
        (far_gi - far_off).abs() <= 1e-3 * far_off,
        "{far_gi} vs {far_off}"
    );
    assert!(near_gi > near_off * 1.5, "{near_gi} vs {near_off}");
}

#[test]
fn no_nan_at_the_extremes() {
    // No mesh at all: no volume, with its reason.
    let mut app = App::headless().expect("a GPU adapter");
    app.world_mut()
        .spawn((Camera::default(), Transform::from_xyz(0.0, 0.0, 3.0)));
    let report = app.render_headless(SIZE).expect("empty frame");
    assert_eq!(
        volume_reason(&report),
        (false, "no mesh to place probes around".into())
    );
    common::assert_finite(&app);

    let volumes = [
        // A probe inside a closed box.
        (
            "probe inside a mesh",
            Vec3::new(2.0, 0.5, 0.0),
            Vec3::new(2.0, 0.5, 0.0),
            None,
            1,
        ),
        // A box of zero size: one probe.
        (
            "zero-size volume",
            Vec3::new(0.0, 1.5, 0.0),
            Vec3::new(0.0, 1.5, 0.0),
            None,
            1,
        ),
        // A spacing wider than the box: one probe.
        (
            "1×1×1 grid",
            Vec3::new(-1.0, 0.2, -1.0),
            Vec3::new(1.0, 1.2, 1.0),
            Some(100.0),
            1,
        ),
    ];
    for (label, min, max, spacing_m, probes) in volumes {
        let mut app = small_scene();
        let cube = app.add_mesh(cuboid(Vec3::ONE)).expect("box");
        let world = app.world_mut();
        world.spawn((
            Mesh3d(cube),
            Material::new(Vec3::splat(0.7), 0.0, 0.6),
            Transform::from_xyz(2.0, 0.5, 0.0),
        ));
        let volume = world
            .query_filtered::<Entity, With<IrradianceVolume>>()
            .single(world)
            .expect("volume");
        world.entity_mut(volume).insert(IrradianceVolume {
            min,
            max,
            spacing_m,
        });
        let report = app.render_headless(SIZE).expect(label);
        let c = report.probes.volume.counts;
        assert_eq!(c.x * c.y * c.z, probes, "{label}");
        assert_eq!(report.probes.volume.passes, (1, 1), "{label}");
        common::assert_finite(&app);
    }

    let mut app = small_scene();
    let world = app.world_mut();
    let volume = world
        .query_filtered::<Entity, With<IrradianceVolume>>()
        .single(world)
        .expect("volume");
    world
        .entity_mut(volume)
        .insert(IrradianceVolume::new(Vec3::splat(f32::NAN), Vec3::ONE));
    let report = app.render_headless(SIZE).expect("frame");
    assert_eq!(
        volume_reason(&report),
        (false, "the IrradianceVolume's bounds are not finite".into())
    );
    common::assert_finite(&app);
}

#[test]
fn the_half_resolution_lookup_agrees_with_the_per_pixel_one() {
    use lumen::render::graph::PassId;
    let size = (96, 96);
    let mut app = common::app_with("cornell");
    let report = app.render_headless(size).expect("frame at half resolution");
    assert!(report.plan.runs(PassId::VolumeIrradiance));
    let half = app.read_hdr_image().expect("hdr");
    app.world_mut().resource_mut::<Quality>().gi.half_resolution = false;
    let report = app.render_headless(size).expect("frame per pixel");
    let reason = report
        .plan
        .decision(PassId::VolumeIrradiance)
        .map(|d| (d.enabled, d.reason.clone()));
    assert_eq!(
        reason,
        Some((
            false,
            "full resolution (gi-resolution = full): the lighting pass looks the volume up per pixel"
                .into()
        ))
    );
    let full = app.read_hdr_image().expect("hdr");
    app.world_mut().resource_mut::<Quality>().gi.enabled = false;
    app.render_headless(size).expect("frame without GI");
    let direct = app.read_hdr_image().expect("hdr");
    // Over the pixels that hold the box: the mean relative difference of the half- and
    // full-resolution frames' luminance sums, and the same for the frame without GI (what
    // the volume adds), so the bound is a fraction of the volume's own contribution.
    let sum = |p: [f32; 4]| p[0] + p[1] + p[2];
    let (mut half_gap, mut gi_gap, mut pixels, mut changed) = (0.0f64, 0.0f64, 0u32, 0u32);
    for (x, y, f) in full.enumerate_pixels() {
        let (f, h, d) = (
            sum(f.0),
            sum(half.get_pixel(x, y).0),
            sum(direct.get_pixel(x, y).0),
        );
        if f <= 0.0 {
            continue;
        }
        pixels += 1;
        changed += u32::from(h != f);
        half_gap += f64::from((h - f).abs() / f);
        gi_gap += f64::from((d - f).abs() / f);
    }
    let (half_gap, gi_gap) = (half_gap / f64::from(pixels), gi_gap / f64::from(pixels));
    println!(
        "{pixels} pixels: half against full {half_gap:.4}, without GI against full {gi_gap:.4}, {changed} changed"
    );
    assert!(pixels > 4000, "{pixels}");
    // The pass is what lit the half-resolution frame: the two frames differ.
    assert!(changed > pixels / 4, "{changed} of {pixels}");
    assert!(gi_gap > 0.3, "{gi_gap}");
    assert!(half_gap < 0.02, "{half_gap}");
}

#[test]
fn a_restarted_volume_converges_to_the_light_of_a_fresh_one() {
    // A quality change restarts the volume's captures. The new round's first pass must
    // read no probe light: it once read the old round's atlases (the uniform still said
    // "ready"), which added the old bounces to the new ones, 8 % more light in `cornell`.
    let size = (48, 48);
    let mut app = common::app_with("cornell");
    let report = app.render_headless(size).expect("fresh frame");
    let fresh = app.read_hdr_image().expect("hdr");
    let faces = report.probes.volume.faces_captured;
    for half in [false, true] {
        app.world_mut().resource_mut::<Quality>().gi.half_resolution = half;
        let report = app.render_headless(size).expect("frame after a change");
        assert_eq!(report.probes.volume.faces_captured, faces, "captured again");
    }
    let again = app.read_hdr_image().expect("hdr");
    let sum = |im: &image::Rgba32FImage| -> f64 {
        im.pixels()
            .map(|p| f64::from(p.0[0] + p.0[1] + p.0[2]))
            .sum()
    };
    let (a, b) = (sum(&fresh), sum(&again));
    println!("light in the frame: fresh {a:.4}, after two restarts {b:.4}");
    assert!(a > 0.0);
    assert!((b / a - 1.0).abs() < 1e-4, "fresh {a}, restarted {b}");
}

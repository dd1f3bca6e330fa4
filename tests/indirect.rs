//! Indirect light: the ambient-occlusion pass against ray-traced ambient occlusion from
//! the path tracer (`render_ambient_occlusion`, the same radius and falloff), its plan,
//! and that it darkens indirect light only.
//!
//! The scene: a sphere of radius 0.5 m resting on a floor, in a uniform environment, seen
//! from 2.6 m in front and 1.2 m up. The AO pass's result is read through the occlusion
//! debug view (display value = AO × 255).

use glam::{Vec2, Vec4Swizzles};
use lumen::assets::procedural::{plane, uv_sphere};
use lumen::prelude::*;
use lumen::quality::{AoResolution, AoSettings};
use lumen::reference::path::{ReferenceOptions, render_ambient_occlusion};
use lumen::render::extract::ExtractedFrame;
use lumen::render::graph::PassId;
use lumen::trace_input::trace_scene;

const SIZE: (u32, u32) = (128, 96);
const SPHERE_RADIUS: f32 = 0.5;

/// The AO settings of the tests: full resolution, 8 slices × 16 steps, 1 m.
fn fine_ao() -> AoSettings {
    AoSettings {
        resolution: AoResolution::Full,
        slices: 8,
        steps: 16,
        radius_m: 1.0,
        denoise: true,
        multi_bounce: true,
    }
}

fn scene(environment: Option<Vec3>, sun: bool) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let floor = app.add_mesh(plane(20.0, 20.0)).expect("floor");
    let sphere = app
        .add_mesh(uv_sphere(SPHERE_RADIUS, 64, 32))
        .expect("sphere");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::splat(0.5), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::splat(0.5), 0.0, 0.5),
        Transform::from_xyz(0.0, SPHERE_RADIUS, 0.0),
    ));
    if let Some(radiance) = environment {
        world.spawn(Environment::uniform(radiance));
    }
    if sun {
        world.spawn((
            DirectionalLight::default(),
            Transform::from_xyz(1.0, 2.0, 1.5).looking_at(Vec3::ZERO, Vec3::Y),
        ));
    }
    world.spawn((
        Camera {
            exposure: Exposure::Linear(1.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 1.2, 2.6).looking_at(Vec3::new(0.0, 0.3, 0.0), Vec3::Y),
    ));
    // The probes off: these tests measure AO on environment light alone (AO darkens the
    // probes' light too, which would make the sun's bounce light depend on it).
    let mut quality = world.resource_mut::<Quality>();
    quality.ao = fine_ao();
    quality.gi.enabled = false;
    quality.reflection_probes.enabled = false;
    app
}

/// The pixel where world point `p` appears.
fn pixel_of(app: &App, p: Vec3) -> (u32, u32) {
    let camera = app
        .world()
        .resource::<ExtractedFrame>()
        .camera
        .clone()
        .expect("camera");
    let clip = camera.clip_from_view * camera.view_from_world * p.extend(1.0);
    let ndc = clip.xy() / clip.w;
    (
        ((ndc.x + 1.0) * 0.5 * SIZE.0 as f32) as u32,
        ((1.0 - ndc.y) * 0.5 * SIZE.1 as f32) as u32,
    )
}

/// The mean of a 3×3 window of channel 0, scaled to 0..1.
fn window(get: &dyn Fn(u32, u32) -> f32, (x, y): (u32, u32)) -> f32 {
    let mut sum = 0.0;
    for dy in 0..3 {
        for dx in 0..3 {
            sum += get(x + dx - 1, y + dy - 1);
        }
    }
    sum / 9.0
}

/// Labelled points: on the floor in front of the contact and to its side, on the
/// sphere's lower front and top, and on the open floor.
fn labelled() -> Vec<(&'static str, Vec3)> {
    let r = SPHERE_RADIUS;
    let on_sphere = |deg: f32| {
        let a = deg.to_radians();
        Vec3::new(0.0, r - r * a.cos(), r * a.sin()) + Vec3::new(0.0, 0.0, 0.0)
    };
    vec![
        (
            "floor 0.1 m in front of the contact",
            Vec3::new(0.0, 0.0, 0.1 + 0.05),
        ),
        (
            "floor 0.3 m in front of the contact",
            Vec3::new(0.0, 0.0, 0.3),
        ),
        ("floor beside the sphere", Vec3::new(0.55, 0.0, 0.15)),
        (
            "sphere's lower front (40° from the bottom)",
            on_sphere(40.0),
        ),
        ("sphere's front (70°)", on_sphere(70.0)),
        ("sphere's upper front (120°)", on_sphere(120.0)),
        ("floor 0.8 m aside", Vec3::new(-0.8, 0.0, 0.0)),
        (
            "open floor behind, 1.3 m from the sphere",
            Vec3::new(0.9, 0.0, -1.5),
        ),
    ]
}

#[test]
fn ao_at_a_sphere_floor_contact_matches_ray_traced_ao() {
    let mut app = scene(Some(Vec3::ONE), false);
    let traced = trace_scene(&mut app, SIZE).expect("trace scene");
    let options = ReferenceOptions {
        size: SIZE,
        samples_per_pixel: 512,
        max_bounces: 1,
        seed: 3,
    };
    let truth = render_ambient_occlusion(&traced, &options, fine_ao().radius_m, &|_| {}).image;
    app.world_mut().insert_resource(DebugView::Occlusion);
    // At full resolution, and at half (the default: one trace per 2×2 pixels, filtered
    // and upsampled by the full-resolution resolve).
    for (resolution, tolerance) in [
        (AoResolution::Full, AO_TOLERANCE),
        (AoResolution::Half, AO_HALF_TOLERANCE),
    ] {
        app.world_mut().resource_mut::<Quality>().ao.resolution = resolution;
        let report = app.render_headless(SIZE).expect("frame");
        assert!(report.plan.runs(PassId::AmbientOcclusion));
        let shown = app.read_display_image().expect("image");
        let mut worst = (0.0f32, "");
        let mut lines = Vec::new();
        for (label, p) in labelled() {
            let at = pixel_of(&app, p);
            let gtao = window(&|x, y| f32::from(shown.get_pixel(x, y).0[0]) / 255.0, at);
            let rtao = window(&|x, y| truth.get_pixel(x, y).0[0], at);
            lines.push(format!(
                "{resolution:?}: {label} at {at:?}: pass {gtao:.3}, ray-traced {rtao:.3}"
            ));
            if (gtao - rtao).abs() > worst.0 {
                worst = ((gtao - rtao).abs(), label);
            }
        }
        println!("{}", lines.join("\n"));
        assert!(
            worst.0 <= tolerance,
            "{resolution:?}: largest difference {:.3} at the {}:\n{}",
            worst.0,
            worst.1,
            lines.join("\n")
        );
    }
}

/// Largest difference allowed between the pass and ray-traced AO at a labelled point
/// (measured: 0.064 at the sphere's front, 0.050 at the contact; GTAO's horizons assume
/// every surface is a height field of infinite thickness, and it weights the falloff on
/// the horizon, not per direction).
const AO_TOLERANCE: f32 = 0.08;

/// The same at half resolution (measured: 0.129 at the contact, 0.286 against 0.157: at
/// 128×96 the contact's darkening spans a few pixels, and each trace stands for four).
const AO_HALF_TOLERANCE: f32 = 0.15;

/// The floor fills the frame (from 1.1 m to 14 m away; n·v from 0.07 to 0.7), with
/// and without the filter.
#[test]
fn ao_is_one_on_an_open_plane_at_any_resolution() {
    for (resolution, denoise) in [
        (AoResolution::Full, false),
        (AoResolution::Full, true),
        (AoResolution::Half, true),
    ] {
        let mut app = App::headless().expect("a GPU adapter");
        let floor = app.add_mesh(plane(200.0, 200.0)).expect("floor");
        let world = app.world_mut();
        world.spawn((
            Mesh3d(floor),
            Material::new(Vec3::splat(0.5), 0.0, 0.8),
            Transform::IDENTITY,
        ));
        world.spawn(Environment::uniform(Vec3::ONE));
        world.spawn((
            Camera::default(),
            Transform::from_xyz(0.0, 1.0, 3.0).looking_at(Vec3::new(0.0, 0.0, 1.0), Vec3::Y),
        ));
        world.resource_mut::<Quality>().ao = AoSettings {
            resolution,
            denoise,
            ..fine_ao()
        };
        world.insert_resource(DebugView::Occlusion);
        app.render_headless(SIZE).expect("frame");
        let shown = app.read_display_image().expect("image");
        let floor_pixels: Vec<u8> = shown.pixels().map(|p| p.0[0]).filter(|&v| v > 0).collect();
        assert_eq!(
            floor_pixels.len(),
            (SIZE.0 * SIZE.1) as usize,
            "the floor fills the frame"
        );
        let darkest = floor_pixels.iter().min().copied().unwrap_or(0);
        // The filter averages 16 slice rotations; one pixel's 8 slices alone are a
        // quadrature within 0.6 % of the integral.
        let bound = if denoise { 254 } else { 252 };
        assert!(
            darkest >= bound,
            "{resolution:?}, denoise {denoise}: an open plane's AO went down to {darkest}/255"
        );
    }
}

#[test]
fn the_plan_runs_ao_only_where_there_is_indirect_light_to_occlude() {
    let cases = [
        (None, AoResolution::Half, false, "no indirect light"),
        (Some(Vec3::ONE), AoResolution::Off, false, "ao = off"),
        (Some(Vec3::ONE), AoResolution::Half, true, "half resolution"),
    ];
    for (environment, resolution, runs, reason) in cases {
        let mut app = scene(environment, true);
        app.world_mut().resource_mut::<Quality>().ao.resolution = resolution;
        let report = app.render_headless(SIZE).expect("frame");
        let decision = report
            .plan
            .passes
            .iter()
            .find(|(id, _)| *id == PassId::AmbientOcclusion)
            .map(|(_, d)| d.clone())
            .expect("the AO pass is registered");
        assert_eq!(decision.enabled, runs, "{reason}: {}", decision.reason);
        assert!(
            decision.reason.contains(reason),
            "expected '{reason}' in '{}'",
            decision.reason
        );
        let timed = report.passes.iter().any(|p| p.name.starts_with("ao "));
        assert_eq!(timed, runs, "{reason}: AO steps recorded only when it runs");
    }
}

/// The frame's mean luminance and the luminance at the contact's floor point.
fn lit(app: &mut App) -> (f32, f32) {
    app.render_headless(SIZE).expect("frame");
    let image = app.read_hdr_image().expect("image");
    assert!(image.pixels().all(|p| p.0.iter().all(|v| v.is_finite())));
    let at = pixel_of(app, Vec3::new(0.0, 0.0, 0.15));
    let lum = |x: u32, y: u32| {
        let p = image.get_pixel(x, y).0;
        0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
    };
    let mean = image
        .enumerate_pixels()
        .map(|(x, y, _)| lum(x, y))
        .sum::<f32>()
        / (SIZE.0 * SIZE.1) as f32;
    (mean, window(&lum, at))
}

#[test]
fn ao_darkens_environment_light_and_never_direct_light() {
    // Direct light only (a black environment still lets the pass run): identical frames.
    let mut with = scene(Some(Vec3::ZERO), true);
    let mut without = scene(Some(Vec3::ZERO), true);
    without.world_mut().resource_mut::<Quality>().ao.resolution = AoResolution::Off;
    let (a, b) = (lit(&mut with), lit(&mut without));
    assert_eq!(a, b, "AO changed direct light");
    // Environment light: the contact is darker with AO, by what the pass measures there.
    let mut with = scene(Some(Vec3::ONE), false);
    let mut without = scene(Some(Vec3::ONE), false);
    without.world_mut().resource_mut::<Quality>().ao.resolution = AoResolution::Off;
    let ((_, occluded), (_, open)) = (lit(&mut with), lit(&mut without));
    assert!(
        occluded < 0.85 * open,
        "the contact with AO {occluded} vs without {open}"
    );
}

#[test]
fn ao_stays_finite_on_degenerate_input() {
    // Nothing drawn, a zero radius and one slice of one step: finite frames, no AO
    // darkening where it cannot see anything.
    let mut empty = App::headless().expect("a GPU adapter");
    empty.world_mut().spawn(Environment::uniform(Vec3::ONE));
    empty
        .world_mut()
        .spawn((Camera::default(), Transform::IDENTITY));
    let report = empty.render_headless(SIZE).expect("frame");
    assert!(!report.plan.runs(PassId::AmbientOcclusion));
    let mut tiny = scene(Some(Vec3::ONE), true);
    tiny.world_mut().resource_mut::<Quality>().ao = AoSettings {
        radius_m: 0.0,
        slices: 1,
        steps: 1,
        ..fine_ao()
    };
    tiny.world_mut().insert_resource(DebugView::Occlusion);
    tiny.render_headless(SIZE).expect("frame");
    let shown = tiny.read_display_image().expect("image");
    assert!(
        shown.pixels().all(|p| p.0[0] == 0 || p.0[0] == 255),
        "a zero radius occludes nothing"
    );
    let mut nan = scene(Some(Vec3::ONE), true);
    nan.world_mut().resource_mut::<Quality>().ao.radius_m = f32::NAN;
    let (mean, _) = lit(&mut nan);
    assert!(mean.is_finite() && mean > 0.0);
}

#[test]
fn every_light_can_cast_shadows_for_the_judge() {
    let mut app = scene(None, true);
    app.world_mut().spawn((
        PointLight {
            range_m: 20.0,
            ..PointLight::default()
        },
        Transform::from_xyz(0.0, -1.0, 0.0),
    ));
    app.render_headless(SIZE).expect("frame");
    assert_eq!(
        app.world().resource::<ExtractedFrame>().shadowed_counts,
        [0, 0, 0],
        "the scene's lights cast no shadows"
    );
    app.world_mut()
        .resource_mut::<Quality>()
        .all_lights_cast_shadows = true;
    app.render_headless(SIZE).expect("frame");
    assert_eq!(
        app.world().resource::<ExtractedFrame>().shadowed_counts,
        [1, 1, 0],
        "--light-shadows all: the sun and the point light"
    );
    // The path tracer's frame-visibility mode then tests every light too.
    let traced = trace_scene(&mut app, SIZE).expect("trace scene");
    assert!(traced.lights.iter().all(|l| l.casts_shadows()));
}

/// A mirror floor (metal, roughness 0) under an emissive sphere of radius 0.3 m at
/// `SPHERE_AT`, nothing else lit: the floor shows only what the reflection pass adds.
const SPHERE_AT: Vec3 = Vec3::new(0.3, 0.6, -0.2);

fn mirror(environment: Option<Vec3>, ssr: bool) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let floor = app.add_mesh(plane(20.0, 20.0)).expect("floor");
    let sphere = app.add_mesh(uv_sphere(0.3, 48, 24)).expect("sphere");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(floor),
        Material::new(Vec3::ONE, 1.0, 0.0),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(sphere),
        Material {
            emissive: Vec3::splat(2.0),
            ..Material::new(Vec3::ZERO, 0.0, 1.0)
        },
        Transform::from_translation(SPHERE_AT),
    ));
    if let Some(radiance) = environment {
        world.spawn(Environment::uniform(radiance));
    }
    world.spawn((
        Camera {
            exposure: Exposure::Linear(1.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 1.4, 3.0).looking_at(Vec3::new(0.0, 0.0, -0.3), Vec3::Y),
    ));
    world.resource_mut::<Quality>().ssr.enabled = ssr;
    app
}

/// The centroid (pixels) of the pixels brighter than `threshold` inside `rows`.
fn centroid(image: &image::Rgba32FImage, rows: std::ops::Range<u32>, threshold: f32) -> Vec2 {
    let (mut sum, mut n) = (Vec2::ZERO, 0.0);
    for (x, y, p) in image.enumerate_pixels() {
        if rows.contains(&y) && p.0[0] > threshold {
            sum += Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            n += 1.0;
        }
    }
    assert!(n > 10.0, "no bright pixels in rows {rows:?}");
    sum / n
}

#[test]
fn a_mirror_floor_shows_the_sphere_at_its_mirrored_position() {
    for half in [true, false] {
        mirrored_at_resolution(half);
    }
}

fn mirrored_at_resolution(half: bool) {
    let mut app = mirror(None, true);
    app.world_mut()
        .resource_mut::<Quality>()
        .ssr
        .half_resolution = half;
    let report = app.render_headless(SIZE).expect("frame");
    assert!(report.plan.runs(PassId::Reflections));
    assert!(report.plan.runs(PassId::DepthPyramid));
    let image = app.read_hdr_image().expect("image");
    let project = |p: Vec3| {
        let (x, y) = pixel_of(&app, p);
        Vec2::new(x as f32 + 0.5, y as f32 + 0.5)
    };
    // The sphere and its reflection, split at the floor line below the sphere.
    let contact = project(Vec3::new(SPHERE_AT.x, 0.0, SPHERE_AT.z)).y as u32;
    let direct = centroid(&image, 0..contact, 0.5);
    let reflected = centroid(&image, contact..SIZE.1, 0.2);
    let expected = project(SPHERE_AT * Vec3::new(1.0, -1.0, 1.0));
    let calibration = direct - project(SPHERE_AT);
    println!(
        "direct {direct} ({calibration} from its centre), reflection {reflected}, mirrored centre {expected}"
    );
    assert!(
        calibration.length() < 1.0,
        "the sphere's own centroid is {calibration} px from its projected centre"
    );
    assert!(
        (reflected - expected).length() <= 2.0,
        "the reflection's centroid {reflected} is {} px from the mirrored centre {expected}",
        (reflected - expected).length()
    );
    // Without the pass the floor reflects nothing (there is no environment).
    let mut dark = mirror(None, false);
    dark.render_headless(SIZE).expect("frame");
    let unlit = dark.read_hdr_image().expect("image");
    let (x, y) = (expected.x as u32, expected.y as u32);
    assert!(unlit.get_pixel(x, y).0[0] < 0.01 && image.get_pixel(x, y).0[0] > 0.2);
}

#[test]
fn reflection_rays_that_leave_the_screen_keep_the_environment() {
    // Looking down at the mirror: every reflected ray leaves the screen upwards.
    let render = |ssr: bool| {
        let mut app = mirror(Some(Vec3::splat(0.5)), ssr);
        app.render_headless(SIZE).expect("frame");
        app.read_hdr_image().expect("image")
    };
    let (with, without) = (render(true), render(false));
    // The floor's bottom rows: the environment's 0.5 in both, never black.
    for x in (0..SIZE.0).step_by(9) {
        let y = SIZE.1 - 2;
        let (a, b) = (with.get_pixel(x, y).0[0], without.get_pixel(x, y).0[0]);
        assert!(b > 0.4, "the environment's reflection: {b}");
        assert!(
            (a - b).abs() < 0.01,
            "pixel ({x}, {y}): {a} with SSR, {b} without"
        );
    }
}

/// The pass shades only the pixels it marked: with the floor (roughness 0.8) above the
/// cutoff, every pixel outside the sphere's (0.5) screen box is bit for bit the frame
/// without reflections, at both resolutions, while the sphere reflects the floor.
#[test]
fn reflections_leave_every_pixel_too_rough_to_trace_as_lighting_wrote_it() {
    for half in [true, false] {
        let render = |ssr: bool| {
            let mut app = scene(Some(Vec3::splat(0.5)), true);
            {
                let mut quality = app.world_mut().resource_mut::<Quality>();
                quality.ssr.enabled = ssr;
                quality.ssr.max_roughness = 0.6;
                quality.ssr.half_resolution = half;
            }
            let report = app.render_headless(SIZE).expect("frame");
            assert_eq!(report.plan.runs(PassId::Reflections), ssr);
            let image = app.read_hdr_image().expect("image");
            (app, image)
        };
        let ((app, with), (_, without)) = (render(true), render(false));
        // The sphere's screen box, from the corners of its world box.
        let (mut low, mut high) = ((SIZE.0, SIZE.1), (0, 0));
        for i in 0..8 {
            let corner = Vec3::new(0.0, SPHERE_RADIUS, 0.0)
                + Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                ) * SPHERE_RADIUS;
            let (x, y) = pixel_of(&app, corner);
            low = (low.0.min(x), low.1.min(y));
            high = (high.0.max(x), high.1.max(y));
        }
        let on_sphere =
            |x: u32, y: u32| (low.0..=high.0).contains(&x) && (low.1..=high.1).contains(&y);
        let (mut outside, mut changed) = (0, 0);
        for (x, y, p) in with.enumerate_pixels() {
            let q = without.get_pixel(x, y);
            if on_sphere(x, y) {
                changed += usize::from(p != q);
            } else {
                assert_eq!(
                    p, q,
                    "pixel ({x}, {y}) off the sphere, half resolution: {half}"
                );
                outside += 1;
            }
        }
        println!("half {half}: {outside} pixels off the sphere unchanged, {changed} on it changed");
        assert!(
            outside > 8000,
            "the floor fills most of the frame: {outside}"
        );
        assert!(
            changed > 50,
            "the sphere reflects the floor: {changed} pixels changed"
        );
    }
}

#[test]
fn the_plan_traces_reflections_only_where_a_surface_is_smooth_enough() {
    // The contact scene's roughest-first materials: floor 0.8, sphere 0.5; the cutoff.
    let cases = [
        (0.4, true, false, "no surface smoother than the cutoff"),
        (0.6, true, true, "ray(s) per 2×2 pixels"),
        (0.6, false, false, "ssr = off"),
    ];
    for (cutoff, enabled, runs, reason) in cases {
        let mut app = scene(None, true);
        {
            let world = app.world_mut();
            let mut quality = world.resource_mut::<Quality>();
            quality.ssr.max_roughness = cutoff;
            quality.ssr.enabled = enabled;
        }
        let report = app.render_headless(SIZE).expect("frame");
        let decision = |id: PassId| {
            report
                .plan
                .passes
                .iter()
                .find(|(p, _)| *p == id)
                .map(|(_, d)| d.clone())
                .expect("registered")
        };
        let ssr = decision(PassId::Reflections);
        assert_eq!(ssr.enabled, runs, "{reason}: {}", ssr.reason);
        assert!(
            ssr.reason.contains(reason),
            "'{reason}' in '{}'",
            ssr.reason
        );
        assert_eq!(decision(PassId::DepthPyramid).enabled, runs);
        let image = app.read_hdr_image().expect("image");
        assert!(image.pixels().all(|p| p.0.iter().all(|v| v.is_finite())));
    }
}

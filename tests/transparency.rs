//! Blended surfaces (`Material::blend`): the transparent pass composites each one over the
//! lit frame with premultiplied "over", farthest first, and runs only when a scene has one.
//! Expectations come from the same scene rendered with the panes opaque or absent,
//! composited on the CPU with `lumen::shading::color::over`.

use crate::common;

use glam::{Quat, Vec3, Vec4};
use lumen::App;
use lumen::prelude::*;
use lumen::quality::Transparency;
use lumen::render::graph::PassId;

const SIZE: (u32, u32) = (96, 64);

/// A pane in front of the camera: 1.6 m square, facing +Z, centred at `at`.
#[derive(Clone, Copy)]
struct Pane {
    at: Vec3,
    color: Vec3,
    /// `None`: opaque; `Some(α)`: blended with coverage α.
    alpha: Option<f32>,
}

/// A grey wall at z = −2, the sun from the camera's side, no shadows or indirect light,
/// and `panes` spawned in the order given, composited sorted.
fn render(panes: &[Pane]) -> (image::Rgba32FImage, lumen::FrameReport, App) {
    render_with(panes, Transparency::Sorted)
}

/// [`render`] compositing as `mode` says.
fn render_with(
    panes: &[Pane],
    mode: Transparency,
) -> (image::Rgba32FImage, lumen::FrameReport, App) {
    let mut app = App::headless().expect("a GPU adapter");
    common::indirect_off(&mut app);
    {
        let mut q = app.world_mut().resource_mut::<Quality>();
        q.shadows = false;
        q.transparency = mode;
    }
    let wall = app
        .add_mesh(lumen::assets::procedural::plane(20.0, 20.0))
        .expect("wall");
    let pane = app
        .add_mesh(lumen::assets::procedural::plane(1.6, 1.6))
        .expect("pane");
    let facing_camera = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let world = app.world_mut();
    world.spawn((
        Mesh3d(wall),
        Material::new(Vec3::splat(0.5), 0.0, 0.8),
        Transform::from_xyz(0.0, 0.0, -2.0).with_rotation(facing_camera),
    ));
    for p in panes {
        let mut material = Material::new(p.color, 0.0, 0.6);
        if let Some(a) = p.alpha {
            material.base_color.w = a;
            material.blend = true;
        }
        world.spawn((
            Mesh3d(pane),
            material,
            Transform::from_translation(p.at).with_rotation(facing_camera),
        ));
    }
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 2.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera::default(),
        Transform::from_xyz(0.0, 0.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let report = app.render_headless(SIZE).expect("frame");
    let image = app.read_hdr_image().expect("readback");
    (image, report, app)
}

/// A red pane (α 0.6) 1 m in front of a blue one (α 0.5), overlapping over a third of
/// their width: front, then back.
fn overlapping_panes() -> [Pane; 2] {
    [
        Pane {
            at: Vec3::new(-0.5, 0.0, 1.0),
            color: Vec3::new(0.9, 0.1, 0.1),
            alpha: Some(0.6),
        },
        Pane {
            at: Vec3::new(0.5, 0.0, 0.0),
            color: Vec3::new(0.1, 0.2, 0.9),
            alpha: Some(0.5),
        },
    ]
}

fn at(image: &image::Rgba32FImage, (x, y): (u32, u32)) -> Vec4 {
    Vec4::from(image.get_pixel(x, y).0)
}

fn transparent_decision(report: &lumen::FrameReport) -> (bool, String) {
    let d = report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == PassId::Transparent)
        .map(|(_, d)| d.clone())
        .expect("the transparent pass is in the plan");
    (d.enabled, d.reason)
}

/// The largest relative difference (floor 1e-3) between two colours' rgb.
fn relative(got: Vec4, want: Vec4) -> f32 {
    ((got - want).truncate().abs() / want.truncate().abs().max(Vec3::splat(1e-3))).max_element()
}

#[test]
fn overlapping_panes_are_composited_back_to_front() {
    // A red pane 1 m in front of a blue one, overlapping over a third of their width. The
    // front one is spawned first, so drawing in spawn order would put it underneath.
    let [front, back] = overlapping_panes();
    let (blended, report, app) = render(&[front, back]);
    let (runs, reason) = transparent_decision(&report);
    assert!(runs && reason.contains("2 blended surface(s)"), "{reason}");
    // The points to look at: the front pane alone, the overlap, the back pane alone.
    let only_front = common::pixel_of(&app, Vec3::new(-1.0, 0.0, 1.0), SIZE);
    let overlap = common::pixel_of(&app, Vec3::new(0.0, 0.0, 0.5), SIZE);
    let only_back = common::pixel_of(&app, Vec3::new(0.95, 0.0, 0.0), SIZE);

    let (wall, _, _) = render(&[]);
    let (front_opaque, _, _) = render(&[Pane {
        alpha: None,
        ..front
    }]);
    let (back_opaque, _, _) = render(&[Pane {
        alpha: None,
        ..back
    }]);
    // Premultiplied colours of the panes: their opaque radiance × α.
    let paint =
        |opaque: &image::Rgba32FImage, pixel, a: f32| (at(opaque, pixel).truncate() * a).extend(a);
    let over = lumen::shading::color::over;
    let cases = [
        (
            "front pane",
            only_front,
            over(paint(&front_opaque, only_front, 0.6), at(&wall, only_front)),
        ),
        (
            "overlap",
            overlap,
            over(
                paint(&front_opaque, overlap, 0.6),
                over(paint(&back_opaque, overlap, 0.5), at(&wall, overlap)),
            ),
        ),
        (
            "back pane",
            only_back,
            over(paint(&back_opaque, only_back, 0.5), at(&wall, only_back)),
        ),
    ];
    for (name, pixel, want) in cases {
        let got = at(&blended, pixel);
        let err = relative(got, want);
        println!("{name} at {pixel:?}: {got} expected {want} (relative {err:.2e})");
        // f16 targets: each value carries 2⁻¹¹ of relative rounding.
        assert!(err < 8e-3, "{name}: {got} vs {want}");
        // Coverage: the wall is opaque, so the composite stays 1.
        assert!((got.w - 1.0).abs() < 1e-3, "{name}: coverage {}", got.w);
    }
    // The other order, for scale: drawn front first, the overlap would be far off.
    let wrong = over(
        paint(&back_opaque, overlap, 0.5),
        over(paint(&front_opaque, overlap, 0.6), at(&wall, overlap)),
    );
    assert!(relative(at(&blended, overlap), wrong) > 0.1);
}

#[test]
fn blended_surfaces_are_lit_and_skipped_when_absent() {
    // A pane of α = 0.25 adds a quarter of its opaque radiance (the same lighting, scaled)
    // to three quarters of the wall behind it; α = 0 leaves the wall as it was.
    let raised = Vec3::new(0.0, 0.8, 1.0);
    let pane = |alpha| Pane {
        at: raised,
        color: Vec3::new(0.2, 0.7, 0.3),
        alpha,
    };
    let (opaque, opaque_report, app) = render(&[pane(None)]);
    let (runs, reason) = transparent_decision(&opaque_report);
    assert!(
        !runs && reason.contains("no blended or transmissive surface"),
        "without a blended surface the pass must not run: {reason}"
    );
    let pixel = common::pixel_of(&app, raised, SIZE);
    let (quarter, report, _) = render(&[pane(Some(0.25))]);
    let (wall, _, _) = render(&[]);
    assert!(transparent_decision(&report).0);
    // The opaque pane is in view there: green, where the wall is grey.
    let seen = at(&opaque, pixel);
    assert!(
        seen.y > 1.5 * seen.x,
        "the pane is not at {pixel:?}: {seen}"
    );
    let want = lumen::shading::color::over(
        (at(&opaque, pixel).truncate() * 0.25).extend(0.25),
        at(&wall, pixel),
    );
    let got = at(&quarter, pixel);
    println!("α = 0.25 at {pixel:?}: {got} expected {want}");
    assert!(relative(got, want) < 8e-3, "{got} vs {want}");
    // Fully transparent: the wall alone, up to f16 rounding.
    let (clear, _, _) = render(&[pane(Some(0.0))]);
    assert!(relative(at(&clear, pixel), at(&wall, pixel)) < 1e-3);
}

#[test]
fn weighted_oit_is_exact_for_one_layer_and_order_independent() {
    // Weighted blended OIT against sorting on the same two overlapping panes: where one
    // pane covers the wall the two agree to f16 rounding; where both overlap the coverage
    // is exact and the colour is a depth-weighted average instead of "over"; spawning the
    // panes in the other order changes nothing.
    let [front, back] = overlapping_panes();
    let (sorted, _, app) = render(&[front, back]);
    let (weighted, report, _) = render_with(&[front, back], Transparency::WeightedBlended);
    let (swapped, _, _) = render_with(&[back, front], Transparency::WeightedBlended);
    let (runs, reason) = transparent_decision(&report);
    assert!(runs && reason.contains("weighted blended OIT"), "{reason}");
    let only_front = common::pixel_of(&app, Vec3::new(-1.0, 0.0, 1.0), SIZE);
    let overlap = common::pixel_of(&app, Vec3::new(0.0, 0.0, 0.5), SIZE);
    let single = relative(at(&weighted, only_front), at(&sorted, only_front));
    let both = relative(at(&weighted, overlap), at(&sorted, overlap));
    println!(
        "weighted against sorted: one layer {single:.2e}, overlap {both:.3} ({} vs {})",
        at(&weighted, overlap),
        at(&sorted, overlap)
    );
    assert!(single < 8e-3, "one layer: {single}");
    // The overlap's colour differs (measured 0.098 here): within 15 % of sorting.
    assert!(both > 0.01 && both < 0.15, "overlap: {both}");
    let order = relative(at(&swapped, overlap), at(&weighted, overlap));
    assert!(
        order < 2e-3,
        "spawn order changed the weighted result by {order}"
    );
    assert!((at(&weighted, overlap).w - 1.0).abs() < 1e-3);
}

/// Three double-sided panes along the view axis, a sun on each side, no wall, seen from
/// z = `eye_z` towards the origin; each pane blended with its α, or opaque, or absent.
fn three_panes(eye_z: f32, panes: [Option<Option<f32>>; 3]) -> image::Rgba32FImage {
    let mut app = App::headless().expect("a GPU adapter");
    common::indirect_off(&mut app);
    app.world_mut().resource_mut::<Quality>().shadows = false;
    let mesh = app
        .add_mesh(lumen::assets::procedural::plane(1.6, 1.6))
        .expect("pane");
    let facing = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let colours = [
        Vec3::new(0.9, 0.1, 0.1),
        Vec3::new(0.1, 0.8, 0.1),
        Vec3::new(0.1, 0.2, 0.9),
    ];
    let world = app.world_mut();
    for (k, pane) in panes.into_iter().enumerate() {
        let Some(alpha) = pane else {
            continue;
        };
        let mut material = Material::new(colours[k], 0.0, 0.6);
        material.double_sided = true;
        if let Some(a) = alpha {
            material.base_color.w = a;
            material.blend = true;
        }
        let at = Vec3::new(0.4 * (k as f32 - 1.0), 0.0, 1.0 - k as f32);
        world.spawn((
            Mesh3d(mesh),
            material,
            Transform::from_translation(at).with_rotation(facing),
        ));
    }
    for side in [1.0, -1.0] {
        world.spawn((
            DirectionalLight::default(),
            Transform::from_xyz(1.0, 2.0, 4.0 * side).looking_at(Vec3::ZERO, Vec3::Y),
        ));
    }
    world.spawn((
        Camera::default(),
        Transform::from_xyz(0.0, 0.0, eye_z).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    app.render_headless(SIZE).expect("frame");
    app.read_hdr_image().expect("readback")
}

#[test]
fn three_panes_composite_in_order_from_both_sides() {
    // Panes at z = 1, 0 and −1 (α 0.6, 0.5, 0.4) all cross the view axis. Seen from +z
    // the one at z = 1 is in front, seen from −z the one at z = −1: the centre pixel is
    // "over" of the three in that order over the background, each pane's premultiplied
    // colour taken from a render of it alone and opaque.
    let alphas = [0.6, 0.5, 0.4];
    let centre = (SIZE.0 / 2, SIZE.1 / 2);
    for eye_z in [6.0f32, -6.0] {
        let blended = at(&three_panes(eye_z, alphas.map(|a| Some(Some(a)))), centre);
        let background = at(&three_panes(eye_z, [None; 3]), centre);
        let layer = |k: usize| {
            let mut only = [None; 3];
            only[k] = Some(None);
            (at(&three_panes(eye_z, only), centre).truncate() * alphas[k]).extend(alphas[k])
        };
        let layers = [layer(0), layer(1), layer(2)];
        // Front to back as this eye sees them.
        let order: [usize; 3] = if eye_z > 0.0 { [0, 1, 2] } else { [2, 1, 0] };
        let over = lumen::shading::color::over;
        let want = over(
            layers[order[0]],
            over(layers[order[1]], over(layers[order[2]], background)),
        );
        let reversed = over(
            layers[order[2]],
            over(layers[order[1]], over(layers[order[0]], background)),
        );
        let err = relative(blended, want);
        println!(
            "eye z = {eye_z}: {blended} expected {want} (relative {err:.2e}); the other order {reversed}"
        );
        assert!(err < 8e-3, "eye z = {eye_z}: {blended} vs {want}");
        assert!(
            relative(blended, reversed) > 0.05,
            "the order makes no difference here"
        );
        assert!(
            (blended.w - want.w).abs() < 2e-3,
            "coverage {} vs {}",
            blended.w,
            want.w
        );
    }
}

/// A blended pane (α 0.5, facing the camera, nothing behind it) under a shadow-casting sun,
/// with or without a small opaque plate 1 m towards the sun from the pane's point
/// (−0.4, 0, 0): the pane's pixels at that point and at (0.4, 0, 0).
fn shadowed_pane(with_blocker: bool) -> (Vec4, Vec4) {
    let mut app = App::headless().expect("a GPU adapter");
    common::indirect_off(&mut app);
    let pane = app
        .add_mesh(lumen::assets::procedural::plane(1.6, 1.6))
        .expect("pane");
    let plate = app
        .add_mesh(lumen::assets::procedural::plane(0.3, 0.3))
        .expect("plate");
    let facing_camera = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let sun_from = Vec3::new(1.0, 2.0, 4.0).normalize();
    let world = app.world_mut();
    let mut material = Material::new(Vec3::splat(0.8), 0.0, 0.6);
    material.base_color.w = 0.5;
    material.blend = true;
    world.spawn((
        Mesh3d(pane),
        material,
        Transform::IDENTITY.with_rotation(facing_camera),
    ));
    let shaded = Vec3::new(-0.4, 0.0, 0.0);
    if with_blocker {
        world.spawn((
            Mesh3d(plate),
            Material {
                double_sided: true,
                ..Material::new(Vec3::splat(0.5), 0.0, 0.8)
            },
            Transform::from_translation(shaded + sun_from)
                .with_rotation(Quat::from_rotation_arc(Vec3::Y, sun_from)),
        ));
    }
    world.spawn((
        DirectionalLight {
            cast_shadows: true,
            ..DirectionalLight::default()
        },
        ShadowSettings::directional(),
        Transform::from_translation(sun_from * 4.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera::default(),
        Transform::from_xyz(0.0, 0.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    app.render_headless(SIZE).expect("frame");
    let image = app.read_hdr_image().expect("readback");
    let pixel = |p: Vec3| {
        let q = common::image_point(&app, p, SIZE);
        at(&image, (q.x as u32, q.y as u32))
    };
    (pixel(shaded), pixel(Vec3::new(0.4, 0.0, 0.0)))
}

#[test]
fn blended_surfaces_receive_shadows() {
    // Nothing is behind the pane, so its pixels are its own lit colour × α: the plate's
    // shadow takes the sun's light away from the shaded point only.
    let (open, open_other) = shadowed_pane(false);
    let (shaded, other) = shadowed_pane(true);
    println!(
        "pane luminance: shaded {shaded} against {open} unshaded; elsewhere {other} against {open_other}"
    );
    let y = |c: Vec4| lumen::shading::color::luminance(c.truncate());
    assert!(y(open) > 0.05, "the pane is lit: {open}");
    assert!(
        y(shaded) < 0.1 * y(open),
        "the plate's shadow falls on the pane: {shaded} against {open}"
    );
    assert!(
        relative(other, open_other) < 0.01,
        "{other} against {open_other}"
    );
}

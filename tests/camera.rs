//! The physical camera on the GPU: depth of field measured on the image, focus at the
//! extremes, automatic exposure converging on a dark and a bright scene, and pre-exposure
//! keeping a 1e9 cd/m² sky and a starlit night inside the 16-bit HDR target.

use crate::common;

use common::{app_with, lum};
use lumen::App;
use lumen::assets::procedural::{plane, uv_sphere};
use lumen::prelude::*;
use lumen::render::post::exposure::{HISTOGRAM_LOG2_RANGE, HISTOGRAM_MIN_LOG2};
use lumen::scene::AutoExposure;
use lumen::scene::camera::metered_ev100;
use lumen_game::scenes::{DOF_DISTANCES, DOF_PANEL_FRACTION, DOF_SCREEN_X};

const DOF_SIZE: (u32, u32) = (320, 180);

fn with_camera(app: &mut App, f: impl Fn(&mut Camera)) {
    let world = app.world_mut();
    let mut cams = world.query::<&mut Camera>();
    for mut c in cams.iter_mut(world) {
        f(&mut c);
    }
}

/// The `dof` scene's exposed HDR image, with or without depth of field.
fn dof_image(dof: bool) -> image::Rgba32FImage {
    let mut app = app_with("dof");
    if !dof {
        with_camera(&mut app, |c| c.depth_of_field = None);
    }
    let report = app.render_headless(DOF_SIZE).expect("frame");
    let ran = report.passes.iter().any(|p| p.name.starts_with("dof"));
    assert_eq!(ran, dof, "DoF passes: {:?}", report.passes);
    app.read_hdr_image().expect("readback")
}

/// Pixel column of NDC x.
fn column(ndc_x: f32) -> f32 {
    (ndc_x + 1.0) * 0.5 * DOF_SIZE.0 as f32
}

/// Half the NDC width of a panel (panels are square, `DOF_PANEL_FRACTION` of the height).
fn panel_half_width_ndc() -> f32 {
    DOF_PANEL_FRACTION * DOF_SIZE.1 as f32 / DOF_SIZE.0 as f32
}

/// Mean |horizontal luminance gradient| over columns `x0..x1` and the middle half of the
/// panels' rows: how much stripe detail survives.
fn detail(img: &image::Rgba32FImage, x0: u32, x1: u32) -> f32 {
    let h = DOF_SIZE.1 as f32;
    let (y0, y1) = (
        (h * (0.5 - DOF_PANEL_FRACTION * 0.25)) as u32,
        (h * (0.5 + DOF_PANEL_FRACTION * 0.25)) as u32,
    );
    let (mut sum, mut n) = (0.0, 0);
    for y in y0..y1 {
        for x in x0..x1 {
            sum += (lum(img.get_pixel(x + 1, y)) - lum(img.get_pixel(x, y))).abs();
            n += 1;
        }
    }
    sum / n as f32
}

/// Mean |a − b| luminance over columns `x0..x1` of the panels' middle rows, relative to
/// the mean luminance of `b` there.
fn difference(a: &image::Rgba32FImage, b: &image::Rgba32FImage, x0: u32, x1: u32) -> f32 {
    let h = DOF_SIZE.1 as f32;
    let (y0, y1) = (
        (h * (0.5 - DOF_PANEL_FRACTION * 0.4)) as u32,
        (h * (0.5 + DOF_PANEL_FRACTION * 0.4)) as u32,
    );
    let (mut diff, mut base) = (0.0, 0.0);
    for y in y0..y1 {
        for x in x0..x1 {
            diff += (lum(a.get_pixel(x, y)) - lum(b.get_pixel(x, y))).abs();
            base += lum(b.get_pixel(x, y));
        }
    }
    diff / base
}

#[test]
fn dof_keeps_the_focus_plane_and_blurs_near_and_far() {
    let sharp = dof_image(false);
    let blurred = dof_image(true);
    let half = panel_half_width_ndc() * 0.7;
    let mut ratios = [0.0; 3];
    for (k, ratio) in ratios.iter_mut().enumerate() {
        let x0 = column(DOF_SCREEN_X[k] - half) as u32;
        let x1 = column(DOF_SCREEN_X[k] + half) as u32;
        let before = detail(&sharp, x0, x1);
        assert!(before > 0.05, "panel {k} has no stripes to blur: {before}");
        *ratio = detail(&blurred, x0, x1) / before;
    }
    println!("detail kept (near, focus, far at {DOF_DISTANCES:?} m): {ratios:?}");
    assert!(ratios[1] > 0.9, "focus plane lost detail: {ratios:?}");
    assert!(ratios[0] < 0.2, "near plane kept detail: {ratios:?}");
    assert!(ratios[2] < 0.3, "far plane kept detail: {ratios:?}");
}

#[test]
fn foreground_blur_spills_over_the_focus_plane_but_background_does_not_bleed() {
    let sharp = dof_image(false);
    let blurred = dof_image(true);
    let hw = panel_half_width_ndc();
    // The near panel's right edge overlaps the focused panel's left edge; the far panel
    // peeks out beside the focused panel's right edge.
    let near_edge = column(DOF_SCREEN_X[0] + hw) as u32;
    let focus_right = column(DOF_SCREEN_X[1] + hw) as u32;
    let spill = difference(&blurred, &sharp, near_edge + 1, near_edge + 3);
    let bleed = difference(&blurred, &sharp, focus_right - 8, focus_right - 2);
    let inside = difference(&blurred, &sharp, column(-0.1) as u32, column(0.1) as u32);
    println!("relative change: near spill {spill}, far bleed {bleed}, centre {inside}");
    assert!(
        spill > 0.1,
        "near-field blur does not reach the focus plane: {spill}"
    );
    assert!(
        bleed < 0.05,
        "the far field bleeds onto the focus plane: {bleed}"
    );
    assert!(inside < 0.05, "the focus plane changed: {inside}");
}

#[test]
fn focus_at_the_extremes_stays_finite() {
    let focal_length_m = lumen_game::scenes::DOF_FOCAL_LENGTH_MM * 1e-3;
    for focus in [0.2, f32::INFINITY, focal_length_m, 0.0, 1e-9, 1e30] {
        let mut app = app_with("dof");
        with_camera(&mut app, |c| c.lens.focus_distance_m = focus);
        app.render_headless((96, 54)).expect("frame");
        let hdr = app.read_hdr_image().expect("readback");
        let bad = hdr
            .pixels()
            .filter(|p| p.0.iter().any(|c| !c.is_finite() || *c < 0.0))
            .count();
        assert_eq!(bad, 0, "focus {focus} m: {bad} non-finite pixels");
        let mean = hdr.pixels().map(lum).sum::<f32>() / (96.0 * 54.0);
        assert!((0.01..10.0).contains(&mean), "focus {focus} m: mean {mean}");
    }
}

/// A grey ground and ball under a sun of `lux` with a sky of `lux / 8` cd/m², seen with
/// automatic exposure.
fn metered_scene(lux: f32) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let ground = app.add_mesh(plane(50.0, 50.0)).expect("mesh");
    let ball = app.add_mesh(uv_sphere(1.0, 32, 16)).expect("mesh");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ground),
        Material::new(Vec3::splat(0.3), 0.0, 0.8),
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(ball),
        Material::new(Vec3::new(0.7, 0.6, 0.5), 0.0, 0.4),
        Transform::from_xyz(0.0, 1.0, 0.0),
    ));
    world.spawn((
        DirectionalLight {
            illuminance_lux: lux,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(1.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn(Environment::uniform(Vec3::splat(lux / 8.0)));
    world.spawn((
        Camera {
            exposure: Exposure::Auto(AutoExposure::default()),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 2.0, 6.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
    app
}

/// The meter's reading of an exposed HDR image on the CPU: the mean log2 luminance
/// (scene cd/m²) of the pixels brighter than black, between the default percentiles.
fn cpu_meter(hdr: &image::Rgba32FImage, exposure: f32) -> f32 {
    let mut logs: Vec<f32> = hdr
        .pixels()
        .map(|p| lum(p) / exposure)
        .filter(|&l| l > HISTOGRAM_MIN_LOG2.exp2())
        .map(|l| l.log2().min(HISTOGRAM_MIN_LOG2 + HISTOGRAM_LOG2_RANGE))
        .collect();
    logs.sort_by(f32::total_cmp);
    let auto = AutoExposure::default();
    let n = logs.len() as f32;
    let kept = &logs[(n * auto.low_percentile) as usize..(n * auto.high_percentile) as usize];
    kept.iter().sum::<f32>() / kept.len() as f32
}

#[test]
fn auto_exposure_converges_on_a_dark_and_a_bright_scene() {
    // Moonlight (0.3 lux) and full sun (100 000 lux): 18 stops apart.
    let mut converged = Vec::new();
    for lux in [0.3f32, 100_000.0] {
        let mut app = metered_scene(lux);
        app.set_fixed_delta(Some(1.0 / 30.0));
        let size = (128, 72);
        let mut evs = Vec::new();
        let mut report = app.render_headless(size).expect("frame");
        for _ in 0..90 {
            report = app.render_headless(size).expect("frame");
            evs.push(report.ev100);
        }
        let metered = report.metered;
        let target = metered.target_ev100.expect("a metered target");
        let adapted = metered.ev100.expect("an adapted EV100");
        // Smooth: every step moves towards the target, none overshoots it.
        let sign = (target - evs[0]).signum();
        assert!(
            evs.windows(2).all(|w| (w[1] - w[0]) * sign >= -1e-4)
                && evs.iter().all(|e| (target - e) * sign >= -0.02),
            "{lux} lux: not a smooth approach to {target}: {evs:?}"
        );
        assert!(
            (adapted - target).abs() < 0.02,
            "{lux} lux: adapted {adapted} target {target}"
        );
        // The GPU meter agrees with a CPU meter on the same pixels within a histogram bin.
        let hdr = app.read_hdr_image().expect("readback");
        let cpu = cpu_meter(&hdr, report.exposure);
        let bin = HISTOGRAM_LOG2_RANGE / 255.0;
        let gpu = metered.average_log2_luminance.expect("an average");
        assert!(
            (cpu - gpu).abs() < bin,
            "{lux} lux: CPU log2 average {cpu}, GPU {gpu}"
        );
        assert!(
            (metered_ev100(cpu.exp2()) - target).abs() < bin,
            "{lux} lux: target {target}"
        );
        // The stated target: the exposed log-average luminance is 1 / 9.6 (K = 12.5).
        let exposed = (cpu.exp2() * report.exposure).log2();
        assert!(
            (exposed - (1.0f32 / 9.6).log2()).abs() < 0.1,
            "{lux} lux: exposed log2 average {exposed}"
        );
        converged.push(adapted);
    }
    let stops = converged[1] - converged[0];
    assert!(
        (stops - (100_000.0f32 / 0.3).log2()).abs() < 0.3,
        "{converged:?}"
    );
}

#[test]
fn auto_exposure_adapts_by_the_time_step() {
    // The exposure closes 1 − exp(−Δt · rate) of its distance to the target each frame,
    // Δt from `Time`: at 1/60 s and 1/10 s steps (rate 3/s), 4.9 % and 25.9 %.
    let rate = AutoExposure::default().rate_per_s;
    for step in [1.0f32 / 60.0, 0.1] {
        let mut app = metered_scene(100_000.0);
        app.set_fixed_delta(Some(step));
        let size = (64, 36);
        let mut metered = Vec::new();
        for _ in 0..6 {
            let report = app.render_headless(size).expect("frame");
            metered.push((
                report.metered.ev100.expect("an adapted EV100"),
                report.metered.target_ev100.expect("a target"),
            ));
        }
        let expected = 1.0 - (-step * rate).exp();
        for w in metered[2..].windows(2) {
            let ((before, target), (after, _)) = (w[0], w[1]);
            let closed = (after - before) / (target - before);
            println!("step {step} s: closed {closed:.4} of the distance, expected {expected:.4}");
            assert!(
                (closed - expected).abs() < 0.01 * expected,
                "step {step} s: {closed} against {expected}"
            );
        }
    }
}

#[test]
fn auto_exposure_ignores_black_and_keeps_its_state_on_an_all_black_frame() {
    // No light at all: every pixel is black, nothing is metered, the camera keeps its
    // initial EV100 instead of running off to the dark end.
    let mut app = metered_scene(0.0);
    app.set_fixed_delta(Some(1.0));
    let mut report = app.render_headless((64, 36)).expect("frame");
    for _ in 0..5 {
        report = app.render_headless((64, 36)).expect("frame");
    }
    let initial = AutoExposure::default().initial_ev100;
    assert!((report.ev100 - initial).abs() < 1e-3, "{}", report.ev100);
}

#[test]
fn auto_exposure_stays_inside_its_range() {
    // Starlight (0.005 lux: a sky of 6e-4 cd/m², EV100 ≈ −7.6) below the default lowest
    // EV100 (−6) but above black (2⁻¹² cd/m²): the camera stops at −6.
    let mut app = metered_scene(0.005);
    app.set_fixed_delta(Some(1.0));
    let mut report = app.render_headless((64, 36)).expect("frame");
    for _ in 0..20 {
        report = app.render_headless((64, 36)).expect("frame");
    }
    let auto = AutoExposure::default();
    let average = report.metered.average_log2_luminance.expect("metered");
    assert!(average + 3.0 < auto.min_ev100 - 1.0, "{average}");
    assert_eq!(report.metered.target_ev100, Some(auto.min_ev100));
    assert!(
        (report.ev100 - auto.min_ev100).abs() < 1e-3,
        "{}",
        report.ev100
    );
}

/// A white diffuse ball under a uniform sky of `luminance` cd/m², exposed at `ev100`;
/// returns the exposed HDR luminance of the sky and of the ball's centre.
fn exposed_sky_and_ball(luminance: f32, ev100: f32) -> (f32, f32) {
    let mut app = App::headless().expect("a GPU adapter");
    let ball = app.add_mesh(uv_sphere(1.0, 32, 16)).expect("mesh");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ball),
        Material::new(Vec3::ONE, 0.0, 1.0),
        Transform::IDENTITY,
    ));
    world.spawn(Environment::uniform(Vec3::splat(luminance)));
    world.spawn((
        Camera {
            exposure: Exposure::Ev100(ev100),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 5.0),
    ));
    app.render_headless((48, 48)).expect("frame");
    let hdr = app.read_hdr_image().expect("readback");
    (lum(hdr.get_pixel(1, 1)), lum(hdr.get_pixel(24, 24)))
}

#[test]
fn pre_exposure_keeps_a_blinding_and_a_dark_scene_in_range() {
    // 1e9 cd/m² overflows f16 (max 65504) unless exposure is applied first; 1e-4 cd/m²
    // would sink below its smallest normal (6.1e-5).
    for (luminance, ev100) in [(1e9f32, 30.0f32), (1e-4, -10.0)] {
        let exposure = 1.0 / (1.2 * ev100.exp2());
        let (sky, ball) = exposed_sky_and_ball(luminance, ev100);
        let expected = luminance * exposure;
        assert!(
            (sky / expected - 1.0).abs() < 0.01,
            "{luminance} cd/m²: sky {sky}, expected {expected}"
        );
        // A white diffuse ball under a uniform sky reflects the sky's luminance (a white
        // furnace), less what the default AO and roughness do not take away.
        assert!(
            ball.is_finite() && (ball / expected - 1.0).abs() < 0.05,
            "{luminance} cd/m²: ball {ball}, expected {expected}"
        );
    }
}

#[test]
fn vignetting_follows_the_cos4_law() {
    let size = (96u32, 54u32);
    let mut app = App::headless().expect("a GPU adapter");
    let world = app.world_mut();
    world.spawn(Environment::uniform(Vec3::splat(0.5)));
    world.spawn((
        Camera {
            exposure: Exposure::Linear(1.0),
            tonemapper: lumen::shading::color::Tonemapper::None,
            vignette: Some(lumen::scene::Vignette { strength: 1.0 }),
            ..Camera::default()
        },
        Transform::IDENTITY,
    ));
    app.render_headless(size).expect("frame");
    let display = app.read_display_image().expect("readback");
    let decoded = |x: u32, y: u32| {
        lumen::shading::color::srgb_decode(display.get_pixel(x, y).0[1] as f32 / 255.0)
    };
    let fov = Camera::default().projection.fov_y_rad;
    let tan_y = (fov * 0.5).tan();
    let tan_x = tan_y * size.0 as f32 / size.1 as f32;
    let centre = decoded(size.0 / 2, size.1 / 2);
    for (x, y) in [
        (0, 0),
        (size.0 - 1, 0),
        (0, size.1 / 2),
        (size.0 / 2, size.1 - 1),
    ] {
        let ndc_x = (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0;
        let ndc_y = (y as f32 + 0.5) / size.1 as f32 * 2.0 - 1.0;
        let tan2 = (ndc_x * tan_x).powi(2) + (ndc_y * tan_y).powi(2);
        let cos4 = (1.0 / (1.0 + tan2)).powi(2);
        let ratio = decoded(x, y) / centre;
        assert!(
            (ratio - cos4).abs() < 0.02,
            "pixel ({x}, {y}): {ratio} vs cos⁴θ = {cos4}"
        );
    }
    assert!((centre - 0.5).abs() < 0.01, "centre {centre}");
}

#[test]
fn dof_gather_approaches_the_thin_lens_reference() {
    use lumen::reference::relative_luminance_error;
    use lumen::reference::thin_lens::render_thin_lens_reference;
    let mut app = app_with("dof");
    let reference =
        render_thin_lens_reference(&mut app, DOF_SIZE, 128, |_, _| {}).expect("reference");
    let mut error = |dof: Option<u32>| {
        with_camera(&mut app, |c| {
            c.depth_of_field = dof.map(|rings| lumen::scene::DepthOfField {
                rings,
                ..Default::default()
            })
        });
        app.render_headless(DOF_SIZE).expect("frame");
        let hdr = app.read_hdr_image().expect("readback");
        relative_luminance_error(&hdr, &reference).expect("comparable")
    };
    let without = error(None);
    let rings: Vec<f64> = (1..=5).map(|r| error(Some(r))).collect();
    println!(
        "relative luminance error vs the thin-lens reference: no DoF {without:.4}, rings 1..5 {rings:.4?}"
    );
    for (k, e) in rings.iter().enumerate() {
        assert!(
            *e < without * 0.6,
            "{} rings: {e} vs no DoF {without}",
            k + 1
        );
    }
}

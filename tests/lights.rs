//! Tiled light culling: exact (the image with culling equals the image without, also when
//! a tile overflows its list), planned only where it pays, and finite everywhere.

use crate::common;

use lumen::App;
use lumen::prelude::*;
use lumen::render::graph::PassId;
use lumen::render::lighting::LightingPass;
use lumen_game::scenes::LightsSceneOptions;

const SIZE: (u32, u32) = (256, 144);

fn lights_app(count: u32) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    app.world_mut()
        .insert_resource(LightsSceneOptions { count });
    let info = lumen_game::scenes::find("lights").expect("scene");
    (info.build)(&mut app).expect("scene builds");
    // The probes off: these tests hold the frame's light paths to 1e-6, and probe light
    // passes through captures' f16 targets, where two exact paths can round one step
    // apart (measured: 1e-4 of the peak between the uniform and storage paths).
    let mut quality = app.world_mut().resource_mut::<Quality>();
    quality.gi.enabled = false;
    quality.reflection_probes.enabled = false;
    app
}

/// Renders with culling on or off and returns the HDR image and whether the culling pass
/// ran.
fn render(app: &mut App, culling: bool) -> (image::Rgba32FImage, bool) {
    app.world_mut().resource_mut::<Quality>().light_culling = culling;
    let report = app.render_headless(SIZE).expect("frame");
    (
        app.read_hdr_image().expect("readback"),
        report.plan.runs(PassId::LightCulling),
    )
}

/// Largest |a − b| relative to the brightest pixel of `b`.
fn worst_difference(a: &image::Rgba32FImage, b: &image::Rgba32FImage) -> f32 {
    let peak = b.pixels().map(common::lum).fold(0.0f32, f32::max);
    a.pixels()
        .zip(b.pixels())
        .map(|(p, q)| {
            (0..3)
                .map(|c| (p.0[c] - q.0[c]).abs())
                .fold(0.0f32, f32::max)
        })
        .fold(0.0f32, f32::max)
        / peak
}

#[test]
fn culling_is_exact() {
    let mut app = lights_app(200);
    let (all, ran_off) = render(&mut app, false);
    let (culled, ran_on) = render(&mut app, true);
    assert!(!ran_off && ran_on);
    let bad = culled
        .pixels()
        .filter(|p| p.0.iter().any(|c| !c.is_finite()))
        .count();
    assert_eq!(bad, 0);
    let worst = worst_difference(&culled, &all);
    println!("worst difference with culling: {worst:e} of the peak");
    // Only the summation order differs (f16 target: 2⁻¹¹ relative steps).
    assert!(worst < 2e-3, "{worst}");
    // And the lights do light the scene.
    let lit = culled.pixels().filter(|p| common::lum(p) > 0.01).count();
    assert!(lit > (SIZE.0 * SIZE.1 / 4) as usize, "{lit}");
}

#[test]
fn an_overflowing_tile_falls_back_to_every_light() {
    // 300 lights without a range reach every tile: more than a tile lists (255).
    let mut app = lights_app(0);
    let world = app.world_mut();
    for k in 0..300 {
        let a = k as f32 * 0.37;
        world.spawn((
            PointLight {
                intensity: LuminousIntensity::Lumens(30.0),
                range_m: f32::INFINITY,
                ..PointLight::default()
            },
            Transform::from_xyz(a.cos() * 15.0, 1.0, a.sin() * 15.0),
        ));
    }
    let (all, _) = render(&mut app, false);
    let (culled, ran) = render(&mut app, true);
    assert!(ran);
    let worst = worst_difference(&culled, &all);
    assert!(worst < 2e-3, "{worst}");
}

#[test]
fn culling_runs_only_where_it_pays() {
    let min = lumen::render::lighting::light_culling::LIGHT_CULLING_MIN_LIGHTS;
    for (count, expect) in [(min - 1, false), (min, true)] {
        let mut app = lights_app(count);
        let report = app.render_headless((64, 36)).expect("frame");
        assert_eq!(
            report.plan.runs(PassId::LightCulling),
            expect,
            "{count} lights"
        );
        let ran = report.passes.iter().any(|p| p.name == "light culling");
        assert_eq!(ran, expect);
    }
    // `spheres` has 4 point lights: no culling pass.
    let mut app = common::app_with("spheres");
    let report = app.render_headless((64, 64)).expect("frame");
    assert!(!report.plan.runs(PassId::LightCulling));
}

#[test]
fn uniform_and_storage_light_paths_agree() {
    // 200 lights fit the uniform copy; 1200 more dark lights far away push the scene past
    // its capacity (1365 compact lights in 64 KiB), onto the storage-buffer path, without
    // changing the light.
    // A shadowed sun and a shadowed spot light exercise the packed shadowed-light copy
    // (the spot comes after every point light, so its slot is not its index).
    let add_shadowed = |app: &mut App| {
        let world = app.world_mut();
        world.spawn((
            DirectionalLight {
                illuminance_lux: 2.0,
                cast_shadows: true,
                ..DirectionalLight::default()
            },
            Transform::from_xyz(0.0, 10.0, 0.0).looking_at(Vec3::new(3.0, 0.0, 1.0), Vec3::Y),
        ));
        world.spawn((
            SpotLight {
                intensity: LuminousIntensity::Lumens(5_000.0),
                range_m: 30.0,
                cast_shadows: true,
                ..SpotLight::default()
            },
            Transform::from_xyz(-4.0, 8.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y),
        ));
    };
    let mut small = lights_app(200);
    add_shadowed(&mut small);
    let (uniform_path, _) = render(&mut small, false);
    let mut large = lights_app(200);
    add_shadowed(&mut large);
    let world = large.world_mut();
    for k in 0..1200 {
        world.spawn((
            PointLight {
                intensity: LuminousIntensity::Lumens(0.0),
                range_m: 1.0,
                ..PointLight::default()
            },
            Transform::from_xyz(1000.0 + k as f32, 50.0, 0.0),
        ));
    }
    let report = large.render_headless(SIZE).expect("frame");
    assert!(
        !report
            .plan
            .variant::<LightingPass>()
            .is_some_and(|v| v.uniform_lights),
        "1400 lights must use storage"
    );
    let (storage_path, _) = render(&mut large, false);
    let worst = worst_difference(&storage_path, &uniform_path);
    assert!(worst < 1e-6, "{worst}");
    // The culling pass reads the storage buffer too; its lists give the same image.
    let (storage_culled, ran) = render(&mut large, true);
    assert!(ran);
    let (uniform_culled, _) = render(&mut small, true);
    let worst = worst_difference(&storage_culled, &uniform_path);
    assert!(worst < 2e-3, "{worst}");
    let worst = worst_difference(&storage_culled, &uniform_culled);
    assert!(worst < 1e-6, "{worst}");
}

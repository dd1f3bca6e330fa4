//! Clearcoat (`Material::clearcoat`, glTF's `KHR_materials_clearcoat`): the coat's own
//! light against a CPU integration of its lobe, energy in the white furnace, the
//! rasterizer against the path tracer on coated spheres, extreme factors, and a scene
//! without a coat building no clearcoat pass.

use crate::common;

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};
use lumen::App;
use lumen::clearcoat::clearcoat_albedo;
use lumen::ibl::{dfg_integrate, energy_compensation};
use lumen::prelude::*;
use lumen::reference::path::{ReferenceOptions, render};
use lumen::render::graph::PassId;
use lumen::scene::Clearcoat;
use lumen::trace_input::trace_scene;
use lumen_game::scenes::{FURNACE_COLUMNS, FURNACE_RADIUS, furnace_center};

/// The furnace's frame size.
const FURNACE_SIZE: (u32, u32) = (256, 96);

/// What the plan of `report` decided for `pass`.
fn decision(report: &lumen::FrameReport, pass: PassId) -> lumen::render::graph::Decision {
    report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == pass)
        .map(|(_, d)| d.clone())
        .expect("the pass is in the plan")
}

/// The `furnace` scene (a uniform environment of 1 cd/m², exposure 1, no AO or
/// reflections), every sphere's material passed through `coat` with its column (coat
/// roughness i/10), rendered with energy compensation; the HDR image and the frame report.
fn coated_furnace(coat: impl Fn(&mut Material, f32)) -> (App, image::Rgba32FImage) {
    let mut app = common::app_with("furnace");
    common::indirect_off(&mut app);
    app.world_mut()
        .resource_mut::<Quality>()
        .energy_compensation = true;
    let world = app.world_mut();
    let mut query = world.query::<(&mut Material, &Transform)>();
    for (mut m, t) in query.iter_mut(world) {
        let column = (t.translation.x + 5.0).round() / (FURNACE_COLUMNS - 1) as f32;
        coat(&mut m, column);
    }
    let report = app.render_headless(FURNACE_SIZE).expect("frame");
    let coat_pass = decision(&report, PassId::Layers);
    assert!(coat_pass.enabled, "{}", coat_pass.reason);
    let image = app.read_hdr_image().expect("readback");
    (app, image)
}

/// For each pixel of the last frame that sees sphere (`column`, `row`) of the furnace
/// (its centre ray meets the analytic sphere), the pixel and n·v there.
fn sphere_pixels(app: &App, column: u32, row: u32) -> Vec<((u32, u32), f32)> {
    let camera = app
        .world()
        .resource::<lumen::render::extract::ExtractedFrame>()
        .camera
        .clone()
        .expect("camera");
    let world_from_clip: Mat4 = (camera.clip_from_view * camera.view_from_world).inverse();
    let centre = furnace_center(column, row);
    let (w, h) = FURNACE_SIZE;
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let ndc = Vec2::new(
                (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
            );
            let unproject = |z: f32| {
                let p = world_from_clip * ndc.extend(z).extend(1.0);
                p.xyz() / p.w
            };
            let (near, far) = (unproject(1.0), unproject(0.5));
            let d = (far - near).normalize();
            // |near + t d − c|² = r²: the nearer root.
            let oc = near - centre;
            let b = oc.dot(d);
            let disc = b * b - (oc.length_squared() - FURNACE_RADIUS * FURNACE_RADIUS);
            if disc <= 0.0 {
                continue;
            }
            let p = near + d * (-b - disc.sqrt());
            let n = (p - centre).normalize();
            out.push(((x, y), n.dot(-d)));
        }
    }
    out
}

/// The coat lobe's albedo E(n·v, r) with energy compensation, from a CPU integration of
/// the split-sum table (1024 samples): what the coat reflects of a uniform environment
/// of 1.
fn expected_albedo(n_dot_v: f32, roughness: f32) -> f32 {
    let dfg = dfg_integrate(n_dot_v, roughness, 1024);
    clearcoat_albedo(dfg, energy_compensation(Vec3::splat(0.04), dfg).x)
}

#[test]
fn a_coat_over_black_reflects_its_albedo_in_the_furnace() {
    // A black rough base of F0 = 0 reflects only Schlick's grazing term B(n·v, 1) of a
    // uniform environment of 1. Under a whole coat each pixel is the coat lobe's albedo
    // E_coat at its n·v (0.04 at normal view, rising towards grazing) plus the base's B
    // dimmed by 1 − E_coat.
    let (app, image) = coated_furnace(|m, r| {
        *m = Material {
            specular_level: 0.0,
            clearcoat: Some(Clearcoat {
                factor: 1.0,
                perceptual_roughness: r,
            }),
            ..Material::new(Vec3::ZERO, 0.0, 1.0)
        };
    });
    let mut worst = (0.0f32, 0.0, 0.0, 0u32);
    let mut counted = 0;
    for column in 0..FURNACE_COLUMNS {
        let r = column as f32 / (FURNACE_COLUMNS - 1) as f32;
        for ((x, y), n_dot_v) in sphere_pixels(&app, column, 0) {
            // Silhouette pixels mix the sphere with the background.
            if n_dot_v < 0.3 {
                continue;
            }
            let got = image.get_pixel(x, y).0[1];
            let coat = expected_albedo(n_dot_v, r);
            let want = coat + (1.0 - coat) * dfg_integrate(n_dot_v, 1.0, 1024).y;
            counted += 1;
            if (got - want).abs() > (worst.0 - worst.1).abs() {
                worst = (got, want, n_dot_v, column);
            }
        }
    }
    let (got, want, n_dot_v, column) = worst;
    println!(
        "{counted} pixels; worst: {got:.4} against {want:.4} at n·v {n_dot_v:.3}, coat roughness {:.1}",
        column as f32 / 10.0
    );
    assert!(counted > 500, "{counted} sphere pixels");
    assert!((got - want).abs() < 0.01, "{got} against {want}");
}

#[test]
fn a_coated_white_furnace_returns_the_light_it_receives() {
    // White metals (F0 = 1) and white dielectrics under a whole coat of every roughness:
    // what the coat reflects, E_coat, is exactly what it takes from the base, so every
    // sphere still returns 1 (with energy compensation), as the uncoated furnace does.
    let (_, image) = coated_furnace(|m, r| {
        m.clearcoat = Some(Clearcoat {
            factor: 1.0,
            perceptual_roughness: r,
        });
    });
    let worst = image
        .pixels()
        .filter(|p| p.0[3] > 0.5)
        .map(|p| (p.0[0] - 1.0).abs().max((p.0[1] - 1.0).abs()))
        .fold(0.0f32, f32::max);
    println!("worst |pixel − 1| = {worst:.5}");
    assert!(worst <= 0.02, "a coated sphere pixel is {worst} from 1");
}

/// Three dark red spheres with rough bases at x = −1.1, 0, 1.1 under a sun and a point light,
/// black background, no environment; each gets `coats[i]`.
fn coated_spheres(coats: [Option<Clearcoat>; 3]) -> App {
    let mut app = App::headless().expect("a GPU adapter");
    let sphere = app
        .add_mesh(lumen::assets::procedural::uv_sphere(0.5, 96, 48))
        .expect("mesh");
    let world = app.world_mut();
    for (i, coat) in coats.into_iter().enumerate() {
        world.spawn((
            Mesh3d(sphere),
            Material {
                clearcoat: coat,
                ..Material::new(Vec3::new(0.1, 0.01, 0.01), 0.0, 0.7)
            },
            Transform::from_xyz(i as f32 * 1.1 - 1.1, 0.0, 0.0),
        ));
    }
    world.spawn((
        DirectionalLight {
            illuminance_lux: 10.0,
            cast_shadows: false,
            ..DirectionalLight::default()
        },
        Transform::from_xyz(1.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        PointLight {
            intensity: lumen::scene::LuminousIntensity::Candela(20.0),
            range_m: 100.0,
            ..PointLight::default()
        },
        Transform::from_xyz(-2.0, 1.0, 2.0),
    ));
    world.spawn((
        Camera {
            projection: Projection {
                fov_y_rad: 17f32.to_radians(),
                ..Projection::default()
            },
            exposure: Exposure::Linear(1.0),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    common::indirect_off(&mut app);
    app
}

/// The mean rgb of each sphere's pixels within 0.8 of its radius in `image`.
fn sphere_means(app: &App, image: &image::Rgba32FImage) -> [Vec3; 3] {
    let size = image.dimensions();
    std::array::from_fn(|i| {
        let c = Vec3::new(i as f32 * 1.1 - 1.1, 0.0, 0.0);
        let centre = common::image_point(app, c, size);
        let radius = (common::image_point(app, c + Vec3::Y * 0.5, size) - centre).length() * 0.8;
        let (mut sum, mut n) = (Vec3::ZERO, 0);
        for (x, y, p) in image.enumerate_pixels() {
            if (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - centre).length() < radius {
                sum += Vec3::new(p.0[0], p.0[1], p.0[2]);
                n += 1;
            }
        }
        sum / n.max(1) as f32
    })
}

#[test]
fn the_rasterizer_and_the_path_tracer_agree_on_coated_spheres() {
    // Direct light only (one bounce), a sun and a point light: the rasterizer's coat pass
    // against the path tracer's layered BSDF (256 paths per pixel), per sphere, within
    // 1.5 % (measured: 0.55 %, the uncoated spheres 0.43 %); and the coats change each
    // sphere by more than 6 %, so the agreement is not the bases' alone. The spheres are
    // about 65 px wide: at a third of that the rasterizer's one sample per pixel misses
    // part of the coat's small highlight.
    const SIZE: (u32, u32) = (240, 80);
    let coats = [(1.0, 0.25), (0.5, 0.5), (1.0, 0.8)].map(|(factor, perceptual_roughness)| {
        Some(Clearcoat {
            factor,
            perceptual_roughness,
        })
    });
    let mut app = coated_spheres(coats);
    let report = app.render_headless(SIZE).expect("frame");
    let coat = decision(&report, PassId::Layers);
    assert!(
        coat.enabled && coat.reason.contains("3 clearcoat layer"),
        "{}",
        coat.reason
    );
    let raster_image = app.read_hdr_image().expect("readback");
    let raster = sphere_means(&app, &raster_image);
    let scene = trace_scene(&mut app, SIZE).expect("trace scene");
    let options = ReferenceOptions {
        size: SIZE,
        samples_per_pixel: 256,
        max_bounces: 1,
        seed: 3,
    };
    let traced_image = render(&scene, &options, &|_| {}).image;
    let traced = sphere_means(&app, &traced_image);

    let mut bare = coated_spheres([None; 3]);
    let report = bare.render_headless(SIZE).expect("frame");
    let skipped = decision(&report, PassId::Layers);
    assert!(
        !skipped.enabled
            && skipped
                .reason
                .contains("no surface with a sheen or a clearcoat"),
        "{}",
        skipped.reason
    );
    let uncoated = sphere_means(&bare, &bare.read_hdr_image().expect("readback"));
    let bare_scene = trace_scene(&mut bare, SIZE).expect("trace scene");
    let bare_traced = sphere_means(&bare, &render(&bare_scene, &options, &|_| {}).image);
    for i in 0..3 {
        let error = (raster[i] - traced[i]).length() / traced[i].length();
        let change = (raster[i] - uncoated[i]).length() / uncoated[i].length();
        let bare_error = (uncoated[i] - bare_traced[i]).length() / bare_traced[i].length();
        println!(
            "coat {:?}: raster {}, path tracer {}, error {:.2} %; uncoated {} ({:.1} % change, error {:.2} %)",
            coats[i],
            raster[i],
            traced[i],
            error * 100.0,
            uncoated[i],
            change * 100.0,
            bare_error * 100.0
        );
        assert!(error < 0.015, "sphere {i}: {} vs {}", raster[i], traced[i]);
        assert!(change > 0.06, "sphere {i}: the coat changes it by {change}");
    }
}

#[test]
fn extreme_coats_stay_finite() {
    // Roughness 0 (a mirror coat under a sun), factors beyond the range, NaN and ∞:
    // clamped, never NaN.
    let coats = [(1.0, 0.0), (f32::NAN, f32::NAN), (f32::INFINITY, -3.0)].map(
        |(factor, perceptual_roughness)| {
            Some(Clearcoat {
                factor,
                perceptual_roughness,
            })
        },
    );
    let mut app = coated_spheres(coats);
    app.render_headless((96, 32)).expect("frame");
    common::assert_finite(&app);
    let scene = trace_scene(&mut app, (96, 32)).expect("trace scene");
    let options = ReferenceOptions {
        size: (96, 32),
        samples_per_pixel: 4,
        max_bounces: 2,
        seed: 1,
    };
    let traced = render(&scene, &options, &|_| {}).image;
    assert!(traced.pixels().all(|p| p.0.iter().all(|v| v.is_finite())));
}

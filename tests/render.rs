//! Rendering tests: headless frames read back and checked against analytic expectations
//! and the CPU BRDF. All at 256×256 or less.

use crate::common;

use common::{app_with, lum};
use glam::{Quat, Vec3};
use lumen::prelude::*;
use lumen::render::device::GpuRequest;
use lumen::render::graph::PassId;
use lumen::shading::brdf::{Surface, VisibilityModel};
use lumen::{App, FrameTarget};
use lumen_game::scenes::{
    PLANE_ILLUMINANCE_LUX, PLANE_LIGHT_DIRECTION, PLANE_MATERIAL, SPHERE_RADIUS, sphere_center,
};

const SIZE: u32 = 256;

/// Direction of the ray through the centre of pixel (x, y) for a camera at the origin
/// looking down −Z with vertical FOV `fov` (rad), +Y up.
fn pixel_ray(x: u32, y: u32, size: (u32, u32), fov: f32) -> Vec3 {
    let (w, h) = (size.0 as f32, size.1 as f32);
    let t = (fov * 0.5).tan();
    let ndc_x = (x as f32 + 0.5) / w * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f32 + 0.5) / h * 2.0;
    Vec3::new(ndc_x * t * w / h, ndc_y * t, -1.0).normalize()
}

fn hits_sphere(origin: Vec3, dir: Vec3, center: Vec3, radius: f32) -> bool {
    let oc = origin - center;
    let b = oc.dot(dir);
    let c = oc.length_squared() - radius * radius;
    b * b - c >= 0.0 && -b - (b * b - c).max(0.0).sqrt() > 0.0
}

/// Whether the ray through a pixel of the `spheres` camera hits a sphere or the ground.
fn spheres_scene_covers(x: u32, y: u32) -> bool {
    let eye = Vec3::new(0.0, 0.0, 12.0);
    let dir = pixel_ray(x, y, (SIZE, SIZE), 45f32.to_radians());
    let sphere =
        (0..7).any(|j| (0..7).any(|i| hits_sphere(eye, dir, sphere_center(i, j), SPHERE_RADIUS)));
    let ground = dir.y < 0.0 && {
        let t = (-4.0 - eye.y) / dir.y;
        let p = eye + dir * t;
        p.x.abs() <= 10.0 && p.z.abs() <= 10.0
    };
    sphere || ground
}

/// Projects a world point with the `spheres` camera into pixel coordinates.
fn spheres_project(p: Vec3) -> (f32, f32) {
    let v = p - Vec3::new(0.0, 0.0, 12.0);
    let t = (45f32.to_radians() * 0.5).tan();
    let ndc = (v.x / (-v.z * t), v.y / (-v.z * t));
    (
        (ndc.0 + 1.0) * 0.5 * SIZE as f32,
        (1.0 - ndc.1) * 0.5 * SIZE as f32,
    )
}

#[test]
fn spheres_is_finite_and_covers_the_expected_area() {
    let mut app = app_with("spheres");
    app.render_headless((SIZE, SIZE)).expect("frame");
    let hdr = app.read_hdr_image().expect("readback");
    let ldr = app.read_display_image().expect("readback");
    assert!(
        hdr.pixels()
            .all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0)),
        "NaN/Inf/negative in HDR"
    );

    // Coverage (HDR alpha) against a CPU ray cast of the true spheres and ground.
    let (mut covered, mut expected, mut mismatched) = (0u32, 0u32, 0u32);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let gpu = hdr.get_pixel(x, y).0[3] > 0.5;
            let cpu = spheres_scene_covers(x, y);
            covered += gpu as u32;
            expected += cpu as u32;
            mismatched += (gpu != cpu) as u32;
        }
    }
    let total = SIZE * SIZE;
    eprintln!("covered {covered}, expected {expected}, mismatched {mismatched} of {total}");
    assert!(
        expected > total / 5,
        "the reference itself is broken: {expected}"
    );
    assert!((covered as f32 - expected as f32).abs() < 0.02 * expected as f32);
    assert!(
        mismatched < total / 100,
        "{mismatched} pixels disagree with the ray cast"
    );

    // Every sphere's centre pixel is lit geometry, and the background is black.
    for j in 0..7 {
        for i in 0..7 {
            let (px, py) = spheres_project(sphere_center(i, j));
            let p = hdr.get_pixel(px as u32, py as u32);
            assert!(
                p.0[3] > 0.5 && lum(p) > 0.0,
                "sphere ({i}, {j}) missing at ({px}, {py})"
            );
        }
    }
    assert_eq!(ldr.get_pixel(2, 2).0, [0, 0, 0, 255]);
}

#[test]
fn specular_peak_of_a_row_falls_as_roughness_rises() {
    let mut app = app_with("spheres");
    app.render_headless((SIZE, SIZE)).expect("frame");
    let hdr = app.read_hdr_image().expect("readback");
    // Column 0 (roughness 0.05) is left out: a point light's highlight on a near-mirror
    // sphere is far smaller than a pixel, so its sampled peak depends on where pixel
    // centres fall (1.9 against 130 for column 1 at 256×256), not on the BRDF.
    let radius_px = SPHERE_RADIUS / 12.0 * (SIZE as f32 * 0.5) / (45f32.to_radians() * 0.5).tan();
    // Rows of metallic 1, 5/6 and 4/6: specular dominates.
    for j in [6, 5, 4] {
        let peaks: Vec<f32> = (0..7)
            .map(|i| {
                let (cx, cy) = spheres_project(sphere_center(i, j));
                let r = radius_px * 0.85;
                let mut peak = 0.0f32;
                for y in (cy - r) as u32..=(cy + r) as u32 {
                    for x in (cx - r) as u32..=(cx + r) as u32 {
                        if (x as f32 + 0.5 - cx).hypot(y as f32 + 0.5 - cy) <= r {
                            peak = peak.max(lum(hdr.get_pixel(x, y)));
                        }
                    }
                }
                peak
            })
            .collect();
        eprintln!("row {j}: peaks {peaks:?}");
        assert!(peaks.iter().all(|p| p.is_finite() && *p > 0.0));
        for i in 2..7 {
            assert!(
                peaks[i] < peaks[i - 1],
                "row {j}: peak {i} = {} ≥ peak {} = {}",
                peaks[i],
                i - 1,
                peaks[i - 1]
            );
        }
    }
}

#[test]
fn extremes_render_finite() {
    let mut app = app_with("extremes");
    let report = app.render_headless((192, 128)).expect("frame");
    let hdr = app.read_hdr_image().expect("readback");
    let bad = hdr
        .pixels()
        .filter(|p| p.0.iter().any(|c| !c.is_finite() || *c < 0.0))
        .count();
    assert_eq!(bad, 0, "{bad} non-finite or negative HDR pixels");
    // The scene is not just black: the 1e9 lux sun and 1e7 cd light reach it.
    let lit = hdr
        .pixels()
        .filter(|p| p.0[3] > 0.5 && lum(p) > 0.0)
        .count();
    assert!(lit > 1000, "only {lit} lit pixels");
    // Every light kind made it into the shader.
    let features = &report.plan.features;
    for kind in ["directional lights", "point lights", "spot lights"] {
        assert!(
            features.iter().any(|f| f.name == kind && f.enabled),
            "{kind}: {features:?}"
        );
    }
}

/// Expected exposed luminance of the `plane` scene at pixel (x, y), from lumen::shading::brdf; with
/// `compensation`, the specular lobe × `energy_compensation(F0, E)` with E from a converged
/// CPU integration of the split-sum table.
fn plane_expected(
    (x, y): (u32, u32),
    size: (u32, u32),
    base: Vec3,
    roughness: f32,
    metallic: f32,
    compensation: bool,
) -> Vec3 {
    let eye = Vec3::new(0.0, 0.0, 5.0);
    let dir = pixel_ray(x, y, size, 30f32.to_radians());
    let p = eye + dir * (-eye.z / dir.z);
    let n = Vec3::Z;
    let v = (eye - p).normalize();
    let l = PLANE_LIGHT_DIRECTION.normalize();
    let surface = Surface {
        base_color: base,
        metallic,
        perceptual_roughness: roughness,
        specular_level: PLANE_MATERIAL.specular_level,
    };
    let lobes =
        lumen::shading::brdf::surface_brdf_lobes(n, v, l, &surface, VisibilityModel::default());
    let energy = if compensation {
        let f0 = lumen::shading::brdf::compute_f0(base, metallic, surface.specular_level);
        lumen::shading::ibl::energy_compensation(
            f0,
            lumen::shading::ibl::dfg_integrate(n.dot(v), roughness, 8192),
        )
    } else {
        Vec3::ONE
    };
    (lobes.diffuse + lobes.specular * energy) * PLANE_ILLUMINANCE_LUX * n.dot(l) / 1000.0
}

#[test]
fn flat_surface_matches_the_cpu_brdf() {
    let size = (96, 96);
    for compensation in [false, true] {
        let mut app = app_with("plane");
        app.world_mut()
            .resource_mut::<Quality>()
            .energy_compensation = compensation;
        app.keep_target(FrameTarget::GBuffer0);
        app.keep_target(FrameTarget::GBuffer1);
        app.render_headless(size).expect("frame");
        let hdr = app.read_hdr_image().expect("readback");
        let base = PLANE_MATERIAL.base_color.truncate();
        // The material as the G-buffer stores it (8-bit sRGB base colour, f16 roughness and
        // metallic), to hold the lighting pass to brdf.rs without the storage rounding.
        let g0 = app.read_target(FrameTarget::GBuffer0).expect("readback");
        let g1 = app.read_target(FrameTarget::GBuffer1).expect("readback");
        let mut worst = (0.0f32, 0.0f32);
        for y in (4..96).step_by(8) {
            for x in (4..96).step_by(8) {
                let got = Vec3::from_slice(&hdr.get_pixel(x, y).0[..3]);
                let m = PLANE_MATERIAL;
                let exact = plane_expected(
                    (x, y),
                    size,
                    base,
                    m.perceptual_roughness,
                    m.metallic,
                    compensation,
                );
                let (s0, s1) = (g0.get_pixel(x, y).0, g1.get_pixel(x, y).0);
                let stored = plane_expected(
                    (x, y),
                    size,
                    Vec3::new(s0[0], s0[1], s0[2]),
                    s1[2],
                    s1[3],
                    compensation,
                );
                let rel =
                    |e: Vec3| ((got - e).abs() / e.abs().max(Vec3::splat(1e-6))).max_element();
                worst = (worst.0.max(rel(exact)), worst.1.max(rel(stored)));
                assert!(
                    rel(exact) < 0.01,
                    "compensation {compensation}, pixel ({x}, {y}): GPU {got} vs CPU {exact}"
                );
                // Without compensation the lighting pass is held to 0.2 %; with it the
                // 64² BRDF table (f16, bilinear) adds its own error (README).
                let bound = if compensation { 0.005 } else { 0.002 };
                assert!(
                    rel(stored) < bound,
                    "compensation {compensation}, pixel ({x}, {y}): GPU {got} vs CPU as stored {stored}"
                );
            }
        }
        eprintln!(
            "energy compensation {compensation}: worst relative error {:.3e} (exact inputs), {:.3e} (as stored)",
            worst.0, worst.1
        );
    }
}

#[test]
fn one_ev100_step_halves_the_output() {
    let mut values = Vec::new();
    for ev in [8.0, 9.0] {
        let mut app = app_with("plane");
        let world = app.world_mut();
        let mut cams = world.query::<&mut Camera>();
        for mut c in cams.iter_mut(world) {
            c.exposure = Exposure::Ev100(ev);
        }
        app.render_headless((32, 32)).expect("frame");
        values.push(lum(app
            .read_hdr_image()
            .expect("readback")
            .get_pixel(16, 16)));
    }
    let ratio = values[0] / values[1];
    assert!((ratio - 2.0).abs() < 0.02, "EV100 8 / EV100 9 = {ratio}");
}

#[test]
fn a_target_not_kept_is_an_error_naming_keep_target() {
    // Without keep_target the G-buffer's memory may serve later passes, so reading it
    // after the frame is refused; HDR is kept by default.
    let mut app = app_with("plane");
    app.render_headless((32, 32)).expect("frame");
    let err = app
        .read_target(FrameTarget::GBuffer1)
        .expect_err("gbuffer1 was not kept");
    assert!(
        err.to_string()
            .contains("App::keep_target(FrameTarget::GBuffer1)"),
        "{err}"
    );
    assert!(app.read_target(FrameTarget::Hdr).is_ok());
}

#[test]
fn gbuffer_normals_round_trip() {
    // A cube rotated off every axis: each visible face has one exact normal.
    let mut app = App::headless().expect("GPU");
    let cube = app
        .add_mesh(lumen::assets::procedural::cube(2.0))
        .expect("mesh");
    let rotation = Quat::from_euler(glam::EulerRot::YXZ, 0.7, 0.5, 0.2);
    let world = app.world_mut();
    world.spawn((
        Mesh3d(cube),
        Material::default(),
        Transform::IDENTITY.with_rotation(rotation),
    ));
    world.spawn((
        Camera::default(),
        Transform::from_xyz(0.0, 0.0, 6.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    app.keep_target(FrameTarget::GBuffer1);
    app.render_headless((128, 128)).expect("frame");
    let g1 = app.read_target(FrameTarget::GBuffer1).expect("readback");
    let faces: Vec<Vec3> = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
        .iter()
        .map(|n| rotation * *n)
        .collect();
    let (mut checked, mut worst) = (0, 0.0f32);
    for p in g1.pixels().filter(|p| p.0[0] != 0.0 || p.0[1] != 0.0) {
        let n = lumen::shading::encoding::oct_decode(glam::Vec2::new(p.0[0], p.0[1]));
        let angle = faces
            .iter()
            .map(|f| n.angle_between(*f))
            .fold(f32::MAX, f32::min)
            .to_degrees();
        worst = worst.max(angle);
        checked += 1;
    }
    eprintln!("{checked} pixels, worst normal error {worst:.4}°");
    assert!(checked > 2000, "{checked}");
    assert!(worst < 0.1, "worst G-buffer normal error {worst}°");
    // Roughness and metallic of the default material, as stored.
    let p = g1.get_pixel(64, 64).0;
    assert!((p[2] - 0.5).abs() < 1e-3 && p[3] == 0.0, "{p:?}");
}

#[test]
fn vulkan_and_gl_render_the_same_image() {
    let mut images = Vec::new();
    for backend in [wgpu::Backends::VULKAN, wgpu::Backends::GL] {
        let mut app = App::headless_with(&GpuRequest::backends(&[backend]))
            .unwrap_or_else(|e| panic!("{backend:?} adapter: {e}"));
        (lumen_game::scenes::find("spheres").expect("scene").build)(&mut app).expect("scene");
        app.render_headless((128, 96)).expect("frame");
        assert_eq!(
            app.adapter().map(|a| a.backend.as_str()),
            Some(if backend == wgpu::Backends::GL {
                "gl"
            } else {
                "vulkan"
            })
        );
        images.push(app.read_display_image().expect("readback"));
    }
    let max = images[0]
        .as_raw()
        .iter()
        .zip(images[1].as_raw())
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(255);
    assert!(max <= 2, "Vulkan and GL differ by up to {max}/255");
}

#[test]
fn no_adapter_is_a_clear_error() {
    let err = App::headless_with(&GpuRequest::backends(&[wgpu::Backends::METAL]))
        .err()
        .map(|e| e.to_string());
    assert!(
        err.as_deref()
            .is_some_and(|e| e.starts_with("no usable GPU adapter")),
        "{err:?}"
    );
    let err = App::headless_with(&GpuRequest {
        adapter_name: Some("no such adapter".into()),
        ..GpuRequest::default()
    })
    .err()
    .map(|e| e.to_string());
    assert!(
        err.as_deref()
            .is_some_and(|e| e.contains("no such adapter")),
        "{err:?}"
    );
}

#[test]
fn passes_follow_the_scene() {
    // spheres: no spot light → the spot loop is not compiled in.
    let mut app = app_with("spheres");
    let report = app.render_headless((32, 32)).expect("frame");
    let feature = |name: &str| {
        report
            .plan
            .features
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.enabled)
    };
    assert_eq!(feature("directional lights"), Some(true));
    assert_eq!(feature("point lights"), Some(true));
    assert_eq!(feature("spot lights"), Some(false));
    assert!(report.plan.runs(PassId::GBuffer));
    let names: Vec<_> = report.passes.iter().map(|p| p.name).collect();
    // The probes' captures drew the sun's atlas with the same view: the frame keeps it.
    // The sun's shadow is resolved in the mask pass (its depth copy, then the lookups).
    assert_eq!(
        names,
        [
            "gbuffer",
            "depth pyramid",
            "shadow mask depth",
            "shadow mask",
            "volume irradiance depth",
            "volume irradiance",
            "lighting",
            "ssr",
            "tonemap"
        ]
    );
    let shadow = report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == PassId::Shadow)
        .map(|(_, d)| d.reason.clone())
        .unwrap_or_default();
    assert!(shadow.starts_with("cached"), "{shadow}");
    assert!(
        report
            .passes
            .iter()
            .all(|p| p.cpu_ms >= 0.0 && p.gpu_ms.is_none_or(|g| g >= 0.0))
    );

    // No mesh: the G-buffer pass does not run, and the frame is the background.
    let mut app = App::headless().expect("GPU");
    app.world_mut().spawn((
        Camera {
            background: Vec3::splat(1000.0),
            ..Camera::default()
        },
        Transform::IDENTITY,
    ));
    let report = app.render_headless((16, 16)).expect("frame");
    assert!(!report.plan.runs(PassId::GBuffer));
    assert!(report.passes.iter().all(|p| p.name != "gbuffer"));
    let hdr = app.read_hdr_image().expect("readback");
    let expected = 1000.0 * lumen::scene::Exposure::default().multiplier();
    assert!(
        hdr.pixels()
            .all(|p| (p.0[0] - expected).abs() < 1e-3 * expected && p.0[3] == 0.0)
    );

    // No camera: a clear error, not a panic.
    let mut app = App::headless().expect("GPU");
    let err = app.render_headless((16, 16)).err().map(|e| e.to_string());
    assert!(
        err.as_deref()
            .is_some_and(|e| e.contains("no active camera")),
        "{err:?}"
    );
}

#[test]
fn moving_a_light_in_a_system_changes_the_image() {
    let mut app = app_with("plane");
    app.add_systems(|mut lights: Query<&mut DirectionalLight>| {
        for mut l in &mut lights {
            l.illuminance_lux *= 0.5;
        }
    });
    app.render_headless((16, 16)).expect("frame");
    let before = lum(app.read_hdr_image().expect("readback").get_pixel(8, 8));
    app.update();
    app.render_headless((16, 16)).expect("frame");
    let after = lum(app.read_hdr_image().expect("readback").get_pixel(8, 8));
    assert!((after / before - 0.5).abs() < 1e-3, "{before} → {after}");
}

#[test]
fn bad_sizes_are_errors() {
    let mut app = app_with("plane");
    for size in [(0, 10), (10, 0), (100_000, 10)] {
        let err = app.render_headless(size).err().map(|e| e.to_string());
        assert!(
            err.as_deref().is_some_and(|e| e.contains("out of range")),
            "{size:?}: {err:?}"
        );
    }
}

/// The G-buffer pass's decision in `report`: (runs, reason).
fn gbuffer_decision(report: &lumen::FrameReport) -> (bool, String) {
    report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == PassId::GBuffer)
        .map(|(_, d)| (d.enabled, d.reason.clone()))
        .expect("the G-buffer pass is registered")
}

#[test]
fn meshes_outside_the_view_are_not_drawn() {
    // The G-buffer pass draws only the instances whose bounding sphere touches the view
    // frustum. Spheres behind the camera and far to its side add no draw and no triangle,
    // and the image stays bit-identical; a sphere across the image's edge is drawn; with
    // nothing in view the pass does not run.
    let size = (96, 64);
    let mut app = App::headless().expect("a GPU adapter");
    common::indirect_off(&mut app);
    let mesh = lumen::assets::procedural::uv_sphere(1.0, 32, 16);
    let triangles = mesh.triangle_count() as u64;
    let sphere = app.add_mesh(mesh).expect("sphere");
    let material = Material::new(Vec3::splat(0.8), 0.0, 0.5);
    let world = app.world_mut();
    world.spawn((Mesh3d(sphere), material, Transform::IDENTITY));
    world.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    world.spawn((
        Camera::default(),
        Transform::from_xyz(0.0, 0.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let one = app.render_headless(size).expect("frame");
    let alone = app.read_display_image().expect("image");
    assert_eq!((one.stats.draws, one.stats.triangles), (1, triangles));

    let world = app.world_mut();
    // Not casters, so that the sun's shadow views (fitted to the casters' depth) stay
    // the same and the image can be compared bit for bit.
    for at in [Vec3::new(0.0, 0.0, 9.0), Vec3::new(-60.0, 0.0, 0.0)] {
        world.spawn((
            Mesh3d(sphere),
            material,
            Transform::from_translation(at),
            NotShadowCaster,
        ));
    }
    let culled = app.render_headless(size).expect("frame");
    assert_eq!(culled.stats.instances, 3);
    assert_eq!((culled.stats.draws, culled.stats.triangles), (1, triangles));
    let (runs, reason) = gbuffer_decision(&culled);
    assert!(
        runs && reason.contains("1 of 3 instance(s) in view"),
        "{reason}"
    );
    let image = app.read_display_image().expect("image");
    assert!(
        image.as_raw() == alone.as_raw(),
        "culled spheres changed the image"
    );

    // At x = 3.2 the sphere crosses the right edge (the half-width at z = 0 is
    // 5 · tan(22.5°) · 1.5 ≈ 3.1 m for the default 45° vertical field of view).
    app.world_mut()
        .spawn((Mesh3d(sphere), material, Transform::from_xyz(3.2, 0.0, 0.0)));
    let edge = app.render_headless(size).expect("frame");
    assert_eq!((edge.stats.draws, edge.stats.triangles), (1, 2 * triangles));

    let mut cameras = app.world_mut().query::<(&Camera, &mut Transform)>();
    for (_, mut t) in cameras.iter_mut(app.world_mut()) {
        *t = Transform::from_xyz(0.0, 0.0, 5.0).looking_at(Vec3::new(0.0, 0.0, 10.0), Vec3::Y);
    }
    // Looking away, the sphere at z = 9 is in view again; turned up, nothing is.
    let back = app.render_headless(size).expect("frame");
    assert_eq!((back.stats.draws, back.stats.triangles), (1, triangles));
    for (_, mut t) in cameras.iter_mut(app.world_mut()) {
        *t = Transform::from_xyz(0.0, 50.0, 0.0).looking_at(Vec3::new(0.0, 100.0, 0.0), Vec3::Z);
    }
    let none = app.render_headless(size).expect("frame");
    let (runs, reason) = gbuffer_decision(&none);
    assert!(
        !runs && reason.contains("none of 4 instance(s) in view"),
        "{reason}"
    );
    assert_eq!((none.stats.draws, none.stats.triangles), (0, 0));
}

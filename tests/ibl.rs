//! Image-based lighting: the white furnace, the BRDF table against a CPU integration, the
//! prefiltered maps of a constant environment, every shipped HDRI, and bad files.

use crate::common;

use glam::{Vec2, Vec3};
use lumen::App;
use lumen::prelude::*;
use lumen::render::device::Gpu;
use lumen::render::indirect::environment_maps::Ibl;
use lumen::render::readback::{f16_bytes_to_f32, read_texture, read_texture_level};
use lumen::shading::ibl::dfg_integrate;
use lumen_game::scenes::{FURNACE_COLUMNS, FURNACE_RADIUS, furnace_center};

const HDRIS: [&str; 5] = ["forest", "sky", "studio", "sunset", "warehouse"];

fn hdri(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../assets/hdri")
        .join(format!("{name}.exr"))
}

/// Renders `furnace` at exposure 1, without AO and reflections, and returns the mean of each sphere's interior pixels
/// (row 0: metal, row 1: dielectric), the worst |pixel − 1| over all sphere pixels, and
/// the background value.
fn furnace(compensation: bool) -> ([[f32; 11]; 2], f32, f32) {
    let size = (256u32, 96u32);
    let mut app = common::app_with("furnace");
    {
        let world = app.world_mut();
        let mut quality = world.resource_mut::<Quality>();
        quality.energy_compensation = compensation;
        // AO treats occluders as absorbing; a furnace's are lossless (its truth is 1 with
        // or without neighbours), and this checks the BRDF alone: no AO, no reflections.
        quality.ao.resolution = lumen::quality::AoResolution::Off;
        quality.ssr.enabled = false;
    }
    app.render_headless(size).expect("frame");
    let hdr = app.read_hdr_image().expect("readback");
    let eye = Vec3::new(0.0, 0.0, 18.0);
    let t = (20f32.to_radians() * 0.5).tan();
    let project = |p: Vec3| {
        let v = p - eye;
        let aspect = size.0 as f32 / size.1 as f32;
        (
            (v.x / (-v.z * t * aspect) + 1.0) * 0.5 * size.0 as f32,
            (1.0 - v.y / (-v.z * t)) * 0.5 * size.1 as f32,
        )
    };
    let radius_px = FURNACE_RADIUS / 18.0 * size.1 as f32 * 0.5 / t;
    let mut means = [[0.0f32; 11]; 2];
    let mut worst = 0.0f32;
    for row in 0..2 {
        for i in 0..FURNACE_COLUMNS {
            let (cx, cy) = project(furnace_center(i, row));
            let (mut sum, mut n) = (0.0, 0);
            for y in 0..size.1 {
                for x in 0..size.0 {
                    let d = (x as f32 + 0.5 - cx).hypot(y as f32 + 0.5 - cy);
                    let p = hdr.get_pixel(x, y).0;
                    if d < radius_px * 0.9 && p[3] > 0.5 {
                        let v = (p[0] + p[1] + p[2]) / 3.0;
                        sum += v;
                        n += 1;
                        worst = worst.max(
                            (p[0] - 1.0)
                                .abs()
                                .max((p[1] - 1.0).abs())
                                .max((p[2] - 1.0).abs()),
                        );
                    }
                }
            }
            assert!(n > 50, "sphere ({i}, {row}) not found ({n} pixels)");
            means[row as usize][i as usize] = sum / n as f32;
        }
    }
    // Every geometry pixel, silhouettes included.
    for p in hdr.pixels().filter(|p| p.0[3] > 0.5) {
        worst = worst.max(
            (p.0[0] - 1.0)
                .abs()
                .max((p.0[1] - 1.0).abs())
                .max((p.0[2] - 1.0).abs()),
        );
    }
    let background = hdr.get_pixel(2, 2).0[0];
    (means, worst, background)
}

#[test]
fn white_furnace_spheres_vanish_with_energy_compensation() {
    let (means, worst, background) = furnace(true);
    eprintln!("compensated: worst |pixel − 1| = {worst:.5}, background {background}");
    assert!((background - 1.0).abs() < 1e-3, "background {background}");
    assert!(
        worst <= 0.02,
        "a sphere pixel is {worst} away from the background (1.0)"
    );
    assert!(means.iter().flatten().all(|m| (m - 1.0).abs() < 0.02));

    let (lost, worst_off, _) = furnace(false);
    eprintln!("without compensation, energy returned per roughness (mean over each sphere):");
    for (i, (metal, dielectric)) in lost[0].iter().zip(&lost[1]).enumerate() {
        eprintln!(
            "  r = {:.1}: metal F0 = 1 {metal:.4} (lost {:5.2} %), white dielectric {dielectric:.4}",
            i as f32 / (FURNACE_COLUMNS - 1) as f32,
            (1.0 - metal) * 100.0,
        );
    }
    // Single scattering loses energy, more as roughness rises (the test can fail if the
    // switch stops doing anything).
    assert!(
        lost[0][10] < 0.9 && lost[0][10] < lost[0][5] && lost[0][5] < lost[0][1],
        "{:?}",
        lost[0]
    );
    assert!(worst_off > 0.1);
}

fn read_lut(gpu: &Gpu, ibl: &Ibl) -> (u32, Vec<f32>) {
    let (target, size, _) = ibl.lut.as_ref().expect("table built");
    (
        *size,
        f16_bytes_to_f32(&read_texture(gpu, &target.texture, 4).expect("readback")),
    )
}

#[test]
fn brdf_table_matches_the_cpu_integral() {
    let gpu = common::gpu();
    let mut ibl = Ibl::new(&gpu).expect("ibl");
    let samples = Quality::default().brdf_lut_samples;
    ibl.ensure_lut(&gpu, 32, samples).expect("table");
    let (size, data) = read_lut(&gpu, &ibl);
    let (mut same, mut converged) = (0.0f32, 0.0f32);
    for j in 0..size {
        for i in 0..size {
            let nv = (i as f32 + 0.5) / size as f32;
            let r = (j as f32 + 0.5) / size as f32;
            let k = ((j * size + i) * 2) as usize;
            let gpu_value = Vec2::new(data[k], data[k + 1]);
            same = same.max(
                (gpu_value - dfg_integrate(nv, r, samples))
                    .abs()
                    .max_element(),
            );
            converged = converged.max(
                (gpu_value - dfg_integrate(nv, r, 16384))
                    .abs()
                    .max_element(),
            );
        }
    }
    eprintln!(
        "BRDF table {size}², {samples} samples: max |GPU − CPU| {same:.2e} (same samples), {converged:.2e} (CPU with 16384 samples)"
    );
    // Same samples: f16 storage (≤ 2⁻¹¹ relative) and f32 rounding only.
    assert!(same < 1e-3, "{same}");
    // Against the converged integral: the stated accuracy of the default table.
    assert!(converged < 1e-2, "{converged}");
}

#[test]
fn constant_environment_prefilters_to_a_constant_at_every_mip() {
    let gpu = common::gpu();
    let mut ibl = Ibl::new(&gpu).expect("ibl");
    let image =
        EquirectImage::from_texels(128, 64, vec![[0.25, 0.5, 2.0]; 128 * 64]).expect("image");
    let prepared = ibl.prepare_image(&gpu, &image, 64).expect("prefilter");
    assert!(prepared.mips >= 5, "{} mips", prepared.mips);
    for mip in 0..prepared.mips {
        let mut worst = 0.0f32;
        for face in 0..6 {
            let texels = f16_bytes_to_f32(
                &read_texture_level(&gpu, &prepared.specular, mip, face, 8).expect("readback"),
            );
            for t in texels.chunks_exact(4) {
                let d = ((t[0] - 0.25) / 0.25)
                    .abs()
                    .max(((t[1] - 0.5) / 0.5).abs())
                    .max(((t[2] - 2.0) / 2.0).abs());
                worst = worst.max(d);
            }
        }
        eprintln!("mip {mip}: worst relative deviation {worst:.2e}");
        assert!(worst < 2e-3, "mip {mip}: {worst}");
    }
    // Irradiance of the constant: π × radiance.
    let e = lumen::shading::ibl::sh_irradiance(&prepared.sh, Vec3::new(0.3, -0.8, 0.5).normalize());
    assert!(
        (e / std::f32::consts::PI - Vec3::new(0.25, 0.5, 2.0))
            .abs()
            .max_element()
            < 5e-3,
        "{e}"
    );
}

fn luminance(t: &[f32]) -> f32 {
    0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2]
}

#[test]
fn every_shipped_hdri_loads_and_prefilters_cleanly() {
    let gpu = common::gpu();
    let mut ibl = Ibl::new(&gpu).expect("ibl");
    for name in HDRIS {
        let image = EquirectImage::load(&hdri(name)).unwrap_or_else(|e| panic!("{e}"));
        let s = image.sanitized;
        assert!(
            s.negative > 0,
            "{name}: the shipped files hold negative texels"
        );
        let prepared = ibl
            .prepare_image(&gpu, &image, 64)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(prepared.sh.iter().all(|c| c.is_finite()));
        let mut fireflies = 0;
        let mut worst_ratio = 0.0f32;
        for mip in 0..prepared.mips {
            let side = (prepared.specular.width() >> mip).max(1) as usize;
            for face in 0..6 {
                let t = f16_bytes_to_f32(
                    &read_texture_level(&gpu, &prepared.specular, mip, face, 8).expect("readback"),
                );
                assert!(
                    t.iter().all(|v| v.is_finite() && *v >= 0.0),
                    "{name}: non-finite or negative texel in mip {mip}"
                );
                // Fireflies: a texel of a rough mip (roughness ≥ 1/3) far brighter than the
                // mean of its 8 neighbours.
                if mip * 3 >= prepared.mips - 1 && side >= 4 {
                    for y in 1..side - 1 {
                        for x in 1..side - 1 {
                            let c = luminance(&t[(y * side + x) * 4..]);
                            let mut around = 0.0;
                            for (dx, dy) in [
                                (-1i32, -1i32),
                                (0, -1),
                                (1, -1),
                                (-1, 0),
                                (1, 0),
                                (-1, 1),
                                (0, 1),
                                (1, 1),
                            ] {
                                let i = ((y as i32 + dy) as usize * side
                                    + (x as i32 + dx) as usize)
                                    * 4;
                                around += luminance(&t[i..]) / 8.0;
                            }
                            let ratio = c / around.max(1e-6);
                            worst_ratio = worst_ratio.max(ratio);
                            fireflies += usize::from(ratio > 2.0);
                        }
                    }
                }
            }
        }
        eprintln!(
            "{name}: {}×{}, {} negative channels zeroed, {} mips, steps {:?}, brightest texel / neighbours in rough mips {worst_ratio:.2}",
            image.width, image.height, s.negative, prepared.mips, prepared.steps
        );
        assert_eq!(
            fireflies, 0,
            "{name}: {fireflies} fireflies (worst {worst_ratio})"
        );
    }
}

#[test]
fn sky_with_sun_has_no_black_holes_or_fireflies_on_a_lit_sphere() {
    // A glossy and a rough sphere under sky.exr (its sun 22672): every lit pixel finite
    // and positive, neighbouring pixels of the rough sphere within a factor 2.
    let mut app = App::headless().expect("GPU");
    let sphere = app
        .add_mesh(lumen::assets::procedural::uv_sphere(1.0, 64, 32))
        .expect("mesh");
    let image = EquirectImage::load(&hdri("sky")).expect("sky.exr");
    let world = app.world_mut();
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::splat(0.8), 1.0, 0.15),
        Transform::from_xyz(-1.2, 0.0, 0.0),
    ));
    world.spawn((
        Mesh3d(sphere),
        Material::new(Vec3::splat(0.8), 0.0, 0.8),
        Transform::from_xyz(1.2, 0.0, 0.0),
    ));
    world.spawn(Environment::image(std::sync::Arc::new(image), 1.0));
    world.spawn((
        Camera {
            exposure: Exposure::Linear(0.5),
            ..Camera::default()
        },
        Transform::from_xyz(0.0, 0.0, 7.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // This checks the prefiltered environment. A single reflection ray per pixel may
    // land on the other sphere where the mirror direction sees the sun, and replace the
    // sun's glow with that sphere's darker light: noise of the reflections, not of the
    // environment.
    world.resource_mut::<Quality>().ssr.enabled = false;
    let report = app.render_headless((192, 96)).expect("frame");
    let names: Vec<&str> = report
        .preprocessing
        .iter()
        .map(|(s, _)| s.as_str())
        .collect();
    assert!(
        names.contains(&"ggx prefilter") && names.contains(&"brdf lut"),
        "{names:?}"
    );
    let hdr = app.read_hdr_image().expect("readback");
    let mut worst_jump = 0.0f32;
    for (x, y, p) in hdr.enumerate_pixels() {
        assert!(
            p.0.iter().all(|c| c.is_finite() && *c >= 0.0),
            "({x}, {y}): {:?}",
            p.0
        );
        if p.0[3] > 0.5 {
            assert!(common::lum(p) > 0.0, "black hole at ({x}, {y})");
        }
        // The rough sphere (right half): compare with the right-hand neighbour.
        if x > 96 && x + 1 < 192 && p.0[3] > 0.5 && hdr.get_pixel(x + 1, y).0[3] > 0.5 {
            let a = common::lum(p);
            let b = common::lum(hdr.get_pixel(x + 1, y));
            worst_jump = worst_jump.max(a.max(b) / a.min(b).max(1e-6));
        }
    }
    eprintln!("rough sphere: largest ratio between neighbouring pixels {worst_jump:.3}");
    assert!(worst_jump < 2.0, "{worst_jump}");
    // The second frame reuses the prefiltered environment.
    let report = app.render_headless((192, 96)).expect("frame");
    assert!(
        report.preprocessing.is_empty(),
        "{:?}",
        report.preprocessing
    );
}

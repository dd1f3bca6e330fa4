//! `lumen bench` end to end: the JSON schema, the consistency of its numbers, CSV, the
//! chart, `--compare`, bad input, and every quality preset rendering finite images.
//! No timing thresholds: only the structure and the arithmetic of the timings.

use crate::common;

use lumen::choice::Choice;
use lumen::quality::QualityPreset;
use std::path::Path;
use std::process::{Command, Output};

fn lumen(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumen"))
        .args(args)
        .current_dir(cwd)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("lumen runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

const SUMMARY_KEYS: [&str; 8] = ["n", "mean", "median", "p95", "p99", "min", "max", "std"];

fn assert_summary(v: &serde_json::Value, n: usize, what: &str) {
    for k in SUMMARY_KEYS {
        assert!(v[k].is_number(), "{what}: missing {k}: {v}");
    }
    assert_eq!(v["n"].as_u64(), Some(n as u64), "{what}");
    let get = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    assert!(
        get("min") <= get("median") && get("median") <= get("p95") && get("p95") <= get("p99"),
        "{what}: {v}"
    );
    assert!(get("p99") <= get("max") && get("min") <= get("mean") && get("mean") <= get("max"));
    assert!(get("std") >= 0.0, "{what}: {v}");
}

#[test]
fn bench_writes_a_complete_consistent_report() {
    let dir = tempfile::tempdir().expect("temp dir");
    let frames = 6;
    // The shadow atlas drawn every frame (a still scene keeps it otherwise), so that every
    // pass has a timing in every frame.
    let out = lumen(
        &[
            "bench",
            "shadows",
            "--size",
            "96x64",
            "--frames",
            "6",
            "--warmup",
            "2",
            "--dof",
            "on",
            "--shadow-cache",
            "off",
            "--json",
            "r.json",
            "--csv",
            "r.csv",
            "--plot",
            "r.png",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("frame") && stdout.contains("lighting (gpu)"),
        "{stdout}"
    );
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("r.json")).expect("json written"))
            .expect("valid JSON");
    for key in [
        "schema",
        "lumen_version",
        "git_revision",
        "build_profile",
        "mode",
        "scene",
        "size",
        "width",
        "height",
        "preset",
        "quality",
        "adapter",
        "timestamps",
        "warmup_frames",
        "frames",
        "started_unix_s",
        "scene_stats",
        "frame_ms",
        "gpu_ms",
        "cpu_stages",
        "passes",
    ] {
        assert!(r.get(key).is_some(), "missing {key}");
    }
    assert_eq!(r["schema"], "lumen-bench/1");
    assert_eq!(
        (r["scene"].as_str(), r["mode"].as_str()),
        (Some("shadows"), Some("headless"))
    );
    assert_eq!(r["frames"].as_u64(), Some(frames));
    assert_eq!(r["warmup_frames"].as_u64(), Some(2));
    assert_eq!(r["preset"], "high");
    for k in ["name", "backend", "device_type", "driver"] {
        assert!(r["adapter"][k].is_string(), "adapter {k}");
    }
    // Every built-in knob, by name, with its value as a preset file writes it.
    for k in lumen::quality::knobs::builtin().iter() {
        assert!(r["quality"].get(k.name).is_some(), "quality {}", k.name);
    }
    assert_eq!(r["quality"]["shadow-cache"], false);
    assert_eq!(r["quality"]["shadow-filter"], "tent");
    assert_eq!(r["quality"]["cascades"], 4);
    assert!(r["scene_stats"]["triangles"].as_u64().unwrap_or(0) > 0);
    assert_summary(&r["frame_ms"], frames as usize, "frame");
    let stages: Vec<&str> = r["cpu_stages"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|s| s["name"].as_str())
        .collect();
    assert_eq!(
        stages,
        [
            "update",
            "propagate",
            "probes",
            "extract",
            "record",
            "submit",
            "wait"
        ]
    );
    let passes = r["passes"].as_array().cloned().unwrap_or_default();
    let names: Vec<&str> = passes.iter().filter_map(|p| p["name"].as_str()).collect();
    for want in ["shadow", "gbuffer", "lighting", "dof blur", "tonemap"] {
        assert!(names.contains(&want), "{want} missing: {names:?}");
    }
    if r["timestamps"] == true {
        assert_summary(&r["gpu_ms"], frames as usize, "gpu");
        let mut sum_of_means = 0.0;
        for p in &passes {
            assert_summary(&p["gpu_ms"], frames as usize, "pass");
            assert!(p["gpu_ms"]["min"].as_f64().unwrap_or(-1.0) > 0.0, "{p}");
            sum_of_means += p["gpu_ms"]["mean"].as_f64().unwrap_or(f64::NAN);
        }
        // The passes add up to the GPU total, and that to no more than the frame.
        let gpu_mean = r["gpu_ms"]["mean"].as_f64().unwrap_or(f64::NAN);
        assert!((sum_of_means - gpu_mean).abs() < 1e-6 * gpu_mean.max(1.0));
        assert!(
            gpu_mean <= r["frame_ms"]["mean"].as_f64().unwrap_or(0.0),
            "{r}"
        );
    }
    // Per frame, in the CSV: the GPU total is the sum of the passes and at most the frame.
    let csv = std::fs::read_to_string(dir.path().join("r.csv")).expect("csv written");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    assert_eq!(&header[..3], ["frame", "frame_ms", "gpu_ms"]);
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|c| c.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), frames as usize);
    for row in &rows {
        let pass_gpu: f64 = header
            .iter()
            .zip(row)
            .filter(|(h, _)| h.ends_with("_gpu_ms") && **h != "gpu_ms")
            .map(|(_, v)| *v)
            .sum();
        if row[2].is_finite() {
            assert!((pass_gpu - row[2]).abs() < 1e-4, "{row:?}");
            assert!(row[2] <= row[1], "GPU {} > frame {}", row[2], row[1]);
        }
    }
    let chart = image::open(dir.path().join("r.png")).expect("chart PNG");
    assert_eq!((chart.width(), chart.height()), (1200, 600));
    // The chart is not blank: the stacked areas and the line are drawn.
    let rgb = chart.to_rgb8();
    let coloured = rgb.pixels().filter(|p| p.0 != [255, 255, 255]).count();
    assert!(coloured > 20_000, "{coloured} non-white pixels");

    // Comparing a report with itself gives 1 everywhere.
    let out = lumen(&["bench", "--compare", "r.json", "r.json"], dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    let ratios: Vec<&str> = table
        .lines()
        .skip(2)
        .filter_map(|l| l.split_whitespace().last())
        .collect();
    assert!(ratios.len() >= 2 + names.len(), "{table}");
    for r in ratios.iter().filter(|r| **r != "—") {
        assert_eq!(*r, "1.000", "{table}");
    }
    let rows = lumen_game::commands::bench::compare::compare(
        &dir.path().join("r.json"),
        &dir.path().join("r.json"),
    )
    .expect("compare");
    assert!(rows.iter().filter_map(|r| r.ratio()).all(|x| x == 1.0));
    assert!(rows.iter().any(|r| r.name == "lighting (gpu)"));
}

#[test]
fn bench_bad_input_is_a_one_line_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("junk.json"), "{\"a\": 1}").expect("write");
    for (args, needle) in [
        (
            vec!["bench", "--compare", "junk.json", "junk.json"],
            "not a lumen bench report",
        ),
        (
            vec!["bench", "--compare", "missing.json", "junk.json"],
            "missing.json",
        ),
        (vec!["bench", "--frames", "0"], "--frames"),
        (vec!["bench", "--quality", "insane"], "insane"),
        (
            vec!["bench", "--size", "8x8", "--frames", "1", "--csv", "x.txt"],
            "x.txt",
        ),
        (vec!["bench", "nosuchscene"], "nosuchscene"),
    ] {
        let out = lumen(&args, dir.path());
        let err = text(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn every_preset_renders_finite_images() {
    let env = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/hdri/sky.exr");
    let image = std::sync::Arc::new(lumen::scene::EquirectImage::load(&env).expect("HDRI"));
    for &preset in QualityPreset::ALL {
        for scene in ["shadows", "dof", "spheres"] {
            let mut app = common::app_with(scene);
            let world = app.world_mut();
            let mut quality = preset.quality();
            // Two probes along the longest side: `ultra`'s volume (3 passes of 6 probes
            // along the side) took 4.9 s to capture on `shadows` and 15.9 s on `spheres`
            // (lavapipe, 96×64), and the count is not what this test checks (the presets'
            // other settings stay).
            quality.gi.density = quality.gi.density.min(2);
            *world.resource_mut::<lumen::prelude::Quality>() = quality;
            world.spawn(lumen::prelude::Environment::image(image.clone(), 1000.0));
            app.render_headless((96, 64)).expect("frame");
            let hdr = app.read_hdr_image().expect("readback");
            let bad = hdr
                .pixels()
                .filter(|p| p.0.iter().any(|c| !c.is_finite() || *c < 0.0))
                .count();
            assert_eq!(bad, 0, "{} on {scene}: {bad} bad pixels", preset.name());
            let lit = hdr.pixels().filter(|p| common::lum(p) > 1e-4).count();
            assert!(lit > 96 * 64 / 2, "{} on {scene}: {lit} lit", preset.name());
        }
    }
}

/// `lumen bench --rays`: the structure's counts and size for the Cornell box (30
/// triangles in 7 instances), an unchanged second frame kept, and the GPU's and the CPU's
/// hit counts equal (the command fails otherwise) with a positive throughput.
#[test]
fn bench_rays_reports_the_structure_and_the_throughput() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = lumen(
        &[
            "bench", "--scene", "cornell", "--rays", "5000", "--size", "64x64",
        ],
        dir.path(),
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}{}", stdout, text(&out.stderr));
    assert!(
        stdout.contains("7 instances in the TLAS (0 skipped), 30 triangles (0 dropped)"),
        "{stdout}"
    );
    assert!(stdout.contains("1 kept"), "{stdout}");
    let rate = |label: &str| -> f64 {
        stdout
            .lines()
            .find_map(|l| l.trim().strip_prefix(label))
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no '{label}' line in {stdout}"))
    };
    assert!(rate("GPU software traversal:") > 0.0);
    let cpu_line = stdout
        .lines()
        .find(|l| l.trim().starts_with("CPU traversal ("))
        .unwrap_or_else(|| panic!("no CPU line in {stdout}"));
    let cpu: f64 = cpu_line
        .split("): ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no rate in '{cpu_line}'"));
    assert!(cpu > 0.0);
    assert!(stdout.contains("rays: 5000 ("), "{stdout}");
}

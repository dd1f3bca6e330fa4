//! `lumen tradeoff`: one row per preset and knob, each timed and compared with the
//! reference; ultra is closer to the reference than low.

use crate::common;

use lumen_game::commands::tradeoff::{Row, pareto_front};

#[test]
fn the_tradeoff_report_has_every_row_and_ultra_beats_low() {
    let dir = tempfile::tempdir().expect("temp dir");
    tradeoff(
        dir.path(),
        &["--json", "t.json", "--out", "t.md", "--plot", "t.png"],
    );
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("t.json")).expect("json"))
            .expect("valid JSON");
    assert_eq!(doc["schema"], "lumen-tradeoff/1");
    let rows = doc["rows"].as_array().expect("rows");
    // 4 presets and 51 single knobs.
    assert_eq!(rows.len(), 56, "{rows:?}");
    for r in rows {
        for k in ["kind", "setting"] {
            assert!(r[k].is_string(), "{r}");
        }
        for k in ["frame_ms", "flip_mean", "psnr_db", "relative_mse"] {
            let v = r[k].as_f64().unwrap_or(f64::NAN);
            assert!(v.is_finite() && v >= 0.0, "{k} in {r}");
        }
        let flip = r["flip_mean"].as_f64().unwrap_or(2.0);
        assert!(flip <= 1.0, "{r}");
    }
    let flip = |preset: &str| {
        rows.iter()
            .find(|r| r["kind"] == "preset" && r["setting"] == preset)
            .and_then(|r| r["flip_mean"].as_f64())
            .expect(preset)
    };
    println!("FLIP low {}, ultra {}", flip("low"), flip("ultra"));
    assert!(flip("ultra") < flip("low"));
    // The reference was cached for the next run.
    assert_eq!(cached(dir.path(), "-64x36-16spp-8b").len(), 1);
    let table = std::fs::read_to_string(dir.path().join("t.md")).expect("markdown");
    // Header, separator and 56 rows.
    assert_eq!(table.lines().filter(|l| l.starts_with("| ")).count(), 58);
    let chart = image::open(dir.path().join("t.png")).expect("chart");
    assert_eq!((chart.width(), chart.height()), (1200, 600));
}

/// Runs `lumen tradeoff spheres` in `dir` at 64×36, 16 samples per pixel and one frame
/// per row, with `extra`, and asserts it succeeds. Every row's probe captures dominate
/// its time: the volume is 2×2×1 instead of the preset's 4×4×2 (the `--gi-density 8` row
/// still sets its own).
fn tradeoff(dir: &std::path::Path, extra: &[&str]) {
    let mut args = vec![
        "tradeoff",
        "spheres",
        "--size",
        "64x36",
        "--spp",
        "16",
        "--frames",
        "1",
        "--gi-density",
        "2",
    ];
    args.extend_from_slice(extra);
    lumen_tradeoff(dir, &args);
}

/// Runs `lumen` with `args` in `dir` and asserts it succeeds.
fn lumen_tradeoff(dir: &std::path::Path, args: &[&str]) {
    common::run_lumen(dir, args);
}

#[test]
fn the_pareto_front_keeps_only_undominated_rows() {
    let row = |ms: f64, flip: f64| Row {
        kind: "preset".into(),
        setting: format!("{ms}"),
        frame_ms: ms,
        gpu_ms: None,
        flip_mean: flip,
        psnr_db: 0.0,
        relative_mse: 0.0,
    };
    let rows = [
        row(10.0, 0.3),
        row(20.0, 0.2),
        row(15.0, 0.35),
        row(30.0, 0.1),
        row(25.0, 0.25),
    ];
    assert_eq!(pareto_front(&rows), vec![0, 1, 3]);
}

#[test]
fn the_decomposition_separates_shading_visibility_and_transport() {
    let dir = tempfile::tempdir().expect("temp dir");
    tradeoff(dir.path(), &["--decompose", "--json", "d.json"]);
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("d.json")).expect("json"))
            .expect("valid JSON");
    assert_eq!(doc["schema"], "lumen-tradeoff-decompose/1");
    let parts = doc["parts"].as_array().expect("parts");
    let names: Vec<&str> = parts.iter().filter_map(|p| p["part"].as_str()).collect();
    assert_eq!(
        names,
        [
            "implementation",
            "unshadowed lights",
            "indirect light",
            "total",
            "reference noise",
            "1 % brighter",
            "3 % brighter"
        ]
    );
    // One measure of one part.
    let value = |name: &str, measure: &str| {
        parts
            .iter()
            .find(|p| p["part"] == name)
            .and_then(|p| p[measure].as_f64())
            .expect(name)
    };
    let flip = |name: &str| value(name, "flip_mean");
    for name in names {
        let f = flip(name);
        assert!(f.is_finite() && (0.0..=1.0).contains(&f), "{name}: {f}");
    }
    // spheres' point lights below the floor cast no shadow in the frame, and its
    // reference has light bouncing off the floor that the frame does not transport:
    // both parts are far from 0.
    println!(
        "implementation {}, unshadowed {}, indirect {}, total {}",
        flip("implementation"),
        flip("unshadowed lights"),
        flip("indirect light"),
        flip("total")
    );
    assert!(flip("unshadowed lights") > 0.01);
    assert!(flip("indirect light") > flip("implementation"));
    // The reference's own noise at 16 spp is far from 0.
    assert!(flip("reference noise") > 0.01);
    // FLIP's scale: a uniform error costs more the larger it is, and its relative MSE is
    // at most (k − 1)² (the relative MSE divides by y² + 0.01).
    assert!(flip("1 % brighter") > 0.0);
    assert!(flip("3 % brighter") > flip("1 % brighter"));
    let relative = |name: &str| value(name, "relative_mse");
    assert!(relative("3 % brighter") <= 0.03f64.powi(2) * 1.001);
    assert!(relative("3 % brighter") > relative("1 % brighter"));
    // Four references, each cached under its own name.
    for name in ["1b-frame", "1b", "8b", "8b-seed1"] {
        let suffix = format!("-64x36-16spp-{name}");
        assert_eq!(cached(dir.path(), &suffix).len(), 1, "{suffix}");
    }
}

/// The cached references of `spheres` in `dir` whose names end with `suffix`
/// followed by the estimator's tag and `.exr`.
fn cached(dir: &std::path::Path, suffix: &str) -> Vec<String> {
    let suffix = format!("{suffix}-{}.exr", lumen::reference::path::ESTIMATOR);
    std::fs::read_dir(dir.join("out/reference-cache"))
        .expect("the cache folder")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("spheres-") && n.ends_with(&suffix))
        .collect()
}

#[test]
fn references_of_one_scene_with_different_options_are_cached_apart() {
    let dir = tempfile::tempdir().expect("temp dir");
    for extra in [&[][..], &["--env-color", "0.2,0.2,0.2"][..]] {
        let mut args = vec![
            "tradeoff",
            "spheres",
            "--decompose",
            "--size",
            "32x18",
            "--spp",
            "4",
            "--frames",
            "1",
            // The references are what is cached: the presets' rows are enough.
            "--only",
            "preset",
            "--gi-density",
            "2",
        ];
        args.extend_from_slice(extra);
        lumen_tradeoff(dir.path(), &args);
    }
    assert_eq!(cached(dir.path(), "-32x18-4spp-8b").len(), 2);
}

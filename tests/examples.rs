//! The examples in `game/examples/` (built by `cargo test`) run at a tiny size and
//! produce the images they claim.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_lumen"))
        .parent()
        .expect("target dir")
        .join("examples")
        .join(name)
}

fn run(name: &str, dir: &Path) -> String {
    let out = Command::new(example(name))
        .arg("48x27")
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn lit_pixels(path: &Path) -> usize {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    assert_eq!(img.dimensions(), (48, 27), "{}", path.display());
    img.pixels().filter(|p| p.0.iter().any(|&c| c > 20)).count()
}

#[test]
fn image_examples_write_their_images() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (name, file) in [
        ("sphere_grid", "sphere_grid.png"),
        ("animated_lights", "animated_lights.png"),
        ("gltf_model", "gltf_model.png"),
    ] {
        let stdout = run(name, dir.path());
        assert!(stdout.contains(file), "{name}: {stdout}");
        let lit = lit_pixels(&dir.path().join("out/examples").join(file));
        assert!(lit > 48 * 27 / 20, "{name}: {lit} lit pixels");
    }
}

#[test]
fn the_controls_example_reads_scripted_keys_and_moves_its_lamp_by_time() {
    let dir = tempfile::tempdir().expect("temp dir");
    let stdout = run("controls", dir.path());
    // 30 updates of 1/60 s with the right arrow held, at 2 m/s: 1 m.
    for line in [
        "preset  low",
        "view    albedo",
        "lamp    x +1.00 m, z +1.50 m",
    ] {
        assert!(stdout.contains(line), "'{line}' in: {stdout}");
    }
    let lit = lit_pixels(&dir.path().join("out/examples/controls.png"));
    assert!(
        lit > 48 * 27 / 2,
        "the albedo view lights most pixels: {lit}"
    );
}

#[test]
fn the_png_sequence_has_twelve_moving_frames() {
    let dir = tempfile::tempdir().expect("temp dir");
    run("png_sequence", dir.path());
    let frames: Vec<PathBuf> = (0..12)
        .map(|k| {
            dir.path()
                .join(format!("out/examples/sequence/frame_{k:04}.png"))
        })
        .collect();
    for f in &frames {
        assert!(lit_pixels(f) > 0, "{}", f.display());
    }
    let first = image::open(&frames[0]).expect("frame 0").to_rgb8();
    let last = image::open(&frames[11]).expect("frame 11").to_rgb8();
    assert_ne!(first, last, "the camera moves");
}

#[test]
fn frame_timing_reports_the_passes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let stdout = run("frame_timing", dir.path());
    assert!(
        stdout.contains("frame: median") && stdout.contains("over 30 frames"),
        "{stdout}"
    );
    assert!(stdout.contains("lighting"), "{stdout}");
}

#[test]
fn an_example_runs_in_a_window_with_its_systems() {
    let x = common::Xvfb::start();
    let dir = tempfile::tempdir().expect("temp dir");
    let out = Command::new(example("animated_lights"))
        .args(["96x64", "--window", "--frames", "3"])
        .current_dir(dir.path())
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("animated_lights runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("lumen view: "),
        "the window's adapter line: {err}"
    );
    assert!(
        !dir.path().join("out/examples/animated_lights.png").exists(),
        "a window, not an image"
    );
    let bad = Command::new(example("sphere_grid"))
        .arg("--frames")
        .output()
        .expect("sphere_grid runs");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--frames needs a number"));
}

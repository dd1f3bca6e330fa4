//! The knobs as the `lumen` command offers them: flags derived from the declarations,
//! grouped by heading and per subcommand, presets as TOML files (`lumen quality show`,
//! `--quality-file`), and the old spellings as hidden aliases with a note. A knob that a
//! plugin declares is `toy.rs`'s.

use lumen::quality::knob::Acts;
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

/// The `quality` object of `render --json` with `args`.
fn quality_json(args: &[&str], dir: &Path) -> serde_json::Value {
    let mut all = vec![
        "render", "--scene", "plane", "--size", "8x8", "--out", "q.png",
    ];
    all.extend_from_slice(args);
    all.push("--json");
    let out = lumen(&all, dir);
    assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    report["quality"].clone()
}

#[test]
fn quality_show_prints_a_file_that_loads_back_as_the_same_preset() {
    let dir = tempfile::tempdir().expect("temp dir");
    for preset in ["low", "ultra"] {
        let out = lumen(&["quality", "show", preset], dir.path());
        assert!(out.status.success(), "{}", text(&out.stderr));
        let file = dir.path().join(format!("{preset}.toml"));
        std::fs::write(&file, &out.stdout).expect("write");
        let loaded = quality_json(
            &["--quality-file", file.to_str().expect("utf-8")],
            dir.path(),
        );
        let named = quality_json(&["--quality", preset], dir.path());
        assert_eq!(loaded, named, "{preset}");
    }
    // A file that starts from a preset and overrides one knob; a flag overrides the file.
    let file = dir.path().join("mine.toml");
    std::fs::write(&file, "preset = \"medium\"\nao-slices = 7\n").expect("write");
    let q = quality_json(
        &["--quality-file", "mine.toml", "--ssr-steps", "100"],
        dir.path(),
    );
    assert_eq!(q["ao-slices"], 7);
    assert_eq!(q["ssr-steps"], 100);
    assert_eq!(q["gi-face"], 8, "medium's");
}

#[test]
fn a_bad_quality_file_names_the_file_the_line_and_the_key() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("bad.toml"),
        "ao = \"half\"\nao-slises = 3\n",
    )
    .expect("write");
    std::fs::write(dir.path().join("range.toml"), "\n\nssr-rays = 99\n").expect("write");
    for (file, line, key) in [("bad.toml", 2, "ao-slises"), ("range.toml", 3, "ssr-rays")] {
        let out = lumen(
            &[
                "render",
                "--size",
                "8x8",
                "--out",
                "x.png",
                "--quality-file",
                file,
            ],
            dir.path(),
        );
        assert!(!out.status.success());
        let err = text(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
        assert!(
            err.contains(&format!("{file}:{line}:")) && err.contains(key),
            "{err}"
        );
    }
    assert!(!dir.path().join("x.png").exists(), "nothing rendered");
}

#[test]
fn old_spellings_are_hidden_aliases_with_a_note() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = lumen(
        &[
            "render",
            "--scene",
            "plane",
            "--size",
            "8x8",
            "--out",
            "x.png",
            "--no-ssr",
            "--specular-aa",
            "--json",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(err.contains("--no-ssr is now written --ssr off"), "{err}");
    assert!(
        err.contains("--specular-aa is now written --specular-aa on"),
        "{err}"
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(report["quality"]["ssr"], false);
    assert_eq!(report["quality"]["specular-aa"], true);
    let help = text(&lumen(&["render", "--help"], dir.path()).stdout);
    assert!(!help.contains("--no-ssr"), "hidden");
}

#[test]
fn each_subcommand_offers_the_knobs_that_act_on_it_under_headings() {
    let dir = tempfile::tempdir().expect("temp dir");
    let render = text(&lumen(&["render", "--help"], dir.path()).stdout);
    let reference = text(&lumen(&["reference", "--help"], dir.path()).stdout);
    for heading in [
        "Shadows:",
        "Indirect light:",
        "Anti-aliasing:",
        "Camera:",
        "Quality:",
    ] {
        assert!(render.contains(heading), "render --help lacks {heading}");
    }
    for knob in lumen::quality::knobs::builtin().iter() {
        let flag = format!("--{} ", knob.name);
        assert_eq!(
            render.contains(&flag),
            knob.acts.meets(Acts::FRAME.and(Acts::LOAD)),
            "render {flag}"
        );
        assert_eq!(
            reference.contains(&flag),
            knob.acts.meets(Acts::TRACE.and(Acts::LOAD)),
            "reference {flag}"
        );
    }
    for rasterizer_only in ["--shadow-mask", "--light-culling", "--ssr-steps", "--aa "] {
        assert!(!reference.contains(rasterizer_only), "{rasterizer_only}");
    }
    let bad = lumen(&["render", "--ao-slices", "9"], dir.path());
    assert!(!bad.status.success());
    assert!(text(&bad.stderr).contains("1..=8"), "{}", text(&bad.stderr));
}

//! The `lumen` command end to end: every command on a tiny size, and bad input.

use crate::common;

use common::{Xvfb, assert_clean_failure};
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

fn tmp() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

#[test]
fn scenes_lists_the_built_in_scenes() {
    let out = lumen(&["scenes"], &std::env::temp_dir());
    assert!(out.status.success());
    let stdout = text(&out.stdout);
    for name in ["spheres", "plane", "extremes"] {
        assert!(
            stdout.lines().any(|l| l.starts_with(name)),
            "{name} missing: {stdout}"
        );
    }
}

#[test]
fn render_png_with_json_report() {
    let dir = tmp();
    let out = lumen(
        &[
            "render", "--scene", "spheres", "--size", "64x48", "--out", "s.png", "--json",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("one JSON object on stdout");
    for key in [
        "adapter", "backend", "size", "passes", "exposure", "ev100", "frame_ms", "stats",
    ] {
        assert!(report.get(key).is_some(), "missing {key}: {report}");
    }
    assert_eq!(report["size"], "64x48");
    // spheres' own volume (4×4×2 at `high`, three passes of six faces per probe) and probe.
    assert_eq!(
        report["probes"]["volume_probes"],
        serde_json::json!([4, 4, 2])
    );
    assert_eq!(report["probes"]["faces_captured"], 32 * 3 * 6);
    assert_eq!(report["probes"]["reflection_probes_captured"], 1);
    let ev100 = report["ev100"].as_f64().unwrap_or(f64::NAN);
    let exposure = report["exposure"].as_f64().unwrap_or(f64::NAN);
    assert!((ev100 - 9.7).abs() < 1e-4, "{ev100}");
    assert!(
        (exposure - 1.0 / (1.2 * 2f64.powf(9.7))).abs() < 1e-9,
        "{exposure}"
    );
    let passes = report["passes"].as_array().cloned().unwrap_or_default();
    let names: Vec<_> = passes.iter().filter_map(|p| p["name"].as_str()).collect();
    // The probes' captures drew the sun's atlas with the same view and casters: the frame
    // keeps it. The sun's shadow is resolved in the mask pass (its depth copy, then the
    // lookups).
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
    let planned = |name: &str| {
        report["plan"]["passes"]
            .as_array()
            .into_iter()
            .flatten()
            .find(|p| p["name"] == name)
            .cloned()
            .unwrap_or_default()
    };
    // Nothing is skinned or morphed: the deformation pass does not run.
    assert_eq!(planned("deform")["runs"], false);
    let shadow = &planned("shadow");
    assert_eq!(shadow["runs"], false);
    assert!(
        shadow["reason"]
            .as_str()
            .is_some_and(|r| r.starts_with("cached: the atlas already holds these 1 view(s)")),
        "{shadow}"
    );
    for p in &passes {
        assert!(p["cpu_ms"].as_f64().is_some_and(|v| v >= 0.0), "{p}");
        assert!(
            p["gpu_ms"].is_null() || p["gpu_ms"].as_f64().is_some_and(|v| v >= 0.0),
            "{p}"
        );
    }
    assert_eq!(report["stats"]["instances"], 50);
    let img = image::open(dir.path().join("s.png")).expect("PNG written");
    assert_eq!((img.width(), img.height()), (64, 48));
}

#[test]
fn render_exr_is_linear_exposed_radiance() {
    // With --exposure 1 the EXR holds raw luminance: the plate's centre pixel equals the
    // CPU BRDF × illuminance × n·l.
    let dir = tmp();
    let out = lumen(
        &[
            "render",
            "--scene",
            "plane",
            "--size",
            "33x33",
            "--exposure",
            "1",
            "--out",
            "p.exr",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let img =
        lumen::assets::image_io::load_rgba32f(&dir.path().join("p.exr")).expect("EXR written");
    assert_eq!((img.width(), img.height()), (33, 33));
    assert!(img.pixels().all(|p| p.0.iter().all(|c| c.is_finite())));
    let got = glam::Vec3::from_slice(&img.get_pixel(16, 16).0[..3]);
    let m = lumen_game::scenes::PLANE_MATERIAL;
    let surface = lumen::shading::brdf::Surface {
        base_color: m.base_color.truncate(),
        metallic: m.metallic,
        perceptual_roughness: m.perceptual_roughness,
        specular_level: m.specular_level,
    };
    let (n, v) = (glam::Vec3::Z, glam::Vec3::Z);
    let l = lumen_game::scenes::PLANE_LIGHT_DIRECTION.normalize();
    let want = lumen::shading::brdf::surface_brdf(n, v, l, &surface, Default::default())
        * lumen_game::scenes::PLANE_ILLUMINANCE_LUX
        * n.dot(l);
    let rel = ((got - want).abs() / want).max_element();
    assert!(rel < 0.01, "EXR {got} vs CPU {want}");
}

#[test]
fn render_extremes_is_finite() {
    let dir = tmp();
    let out = lumen(
        &[
            "render", "--scene", "extremes", "--size", "48x32", "--out", "e.exr",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let img = lumen::assets::image_io::load_rgba32f(&dir.path().join("e.exr")).expect("EXR");
    assert!(
        img.pixels()
            .all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0))
    );
}

#[test]
fn explain_prints_the_plan() {
    let dir = tmp();
    let out = lumen(
        &["render", "--size", "16x16", "--out", "x.png", "--explain"],
        dir.path(),
    );
    assert!(out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("gbuffer")
            && err.contains("spot lights")
            && err.contains("no light of this kind"),
        "{err}"
    );
    // The specular AA form's defaults, and a value given beside it, reach the plan.
    let out = lumen(
        &[
            "render",
            "--size",
            "16x16",
            "--out",
            "x.png",
            "--explain",
            "--specular-aa",
            "on",
            "--specular-aa-form",
            "2021",
            "--specular-aa-threshold",
            "0.5",
        ],
        dir.path(),
    );
    assert!(out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("(2021 form, σ² 0.159, κ 0.500)"), "{err}");
}

#[test]
fn main_job_without_a_display_writes_out_showcase_png() {
    // No subcommand and no display: the showcase, rendered headless at 1280×720 (what
    // it shows is tested in tests/gltf.rs at a smaller size).
    let dir = tmp();
    let out = lumen(&[], dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("wrote out/showcase.png") && stdout.contains("frame "),
        "{stdout}"
    );
    let img = image::open(dir.path().join("out/showcase.png")).expect("out/showcase.png");
    assert_eq!((img.width(), img.height()), (1280, 720));
}

#[test]
fn bad_input_gives_one_line_errors() {
    let dir = tmp();
    let d = dir.path();
    assert_clean_failure(
        &lumen(&["render", "--scene", "nope", "--out", "x.png"], d),
        "unknown scene 'nope'",
    );
    assert_clean_failure(&lumen(&["render", "--size", "0x10"], d), "0x10");
    assert_clean_failure(&lumen(&["render", "--size", "wide"], d), "wide");
    assert_clean_failure(&lumen(&["render", "missing.glb"], d), "missing.glb");
    assert_clean_failure(
        &lumen(&["render", "--out", "x.jpg", "--size", "8x8"], d),
        "x.jpg",
    );
    assert_clean_failure(&lumen(&["render", "--exposure", "-1"], d), "-1");
    assert_clean_failure(&lumen(&["render", "--tonemap", "filmic"], d), "filmic");
    assert_clean_failure(
        &lumen(&["render", "--specular-aa-form", "2020"], d),
        "unknown specular-aa-form '2020' (use 2019, 2021)",
    );
    assert_clean_failure(&lumen(&["frobnicate"], d), "frobnicate");
    // Unwritable output: the parent "directory" is a regular file.
    std::fs::write(d.join("file"), b"x").expect("write");
    assert_clean_failure(
        &lumen(&["render", "--size", "8x8", "--out", "file/x.png"], d),
        "file",
    );
    // Not a glTF file at all.
    std::fs::write(d.join("junk.gltf"), b"this is not json").expect("write");
    assert_clean_failure(
        &lumen(&["render", "--size", "8x8", "junk.gltf"], d),
        "junk.gltf",
    );
}

#[test]
fn no_adapter_gives_one_line_error() {
    let dir = tmp();
    let run = |env: (&str, &str)| {
        Command::new(env!("CARGO_BIN_EXE_lumen"))
            .args(["render", "--size", "8x8", "--out", "x.png"])
            .current_dir(dir.path())
            .env(env.0, env.1)
            .output()
            .expect("lumen runs")
    };
    assert_clean_failure(&run(("WGPU_BACKEND", "metal")), "no usable GPU adapter");
    assert_clean_failure(
        &run(("WGPU_ADAPTER_NAME", "no such adapter")),
        "no such adapter",
    );
    assert_clean_failure(&run(("WGPU_BACKEND", "glide")), "glide");
}

#[test]
fn gl_backend_renders() {
    let dir = tmp();
    let out = Command::new(env!("CARGO_BIN_EXE_lumen"))
        .args(["render", "--size", "32x32", "--out", "g.png", "--json"])
        .current_dir(dir.path())
        .env("WGPU_BACKEND", "gl")
        .output()
        .expect("lumen runs");
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(report["backend"], "gl");
}

/// Runs `lumen view ARGS` in `dir` on the Xvfb display with `backend`, failing after
/// 120 s; returns its exit status and stderr.
fn run_view(x: &Xvfb, dir: &Path, backend: &str, args: &[&str]) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_lumen"))
        .arg("view")
        .args(args)
        .current_dir(dir)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("WGPU_BACKEND", backend)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("lumen view runs");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while child.try_wait().ok().flatten().is_none() && std::time::Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    if child.try_wait().ok().flatten().is_none() {
        let _ = child.kill();
        panic!("{backend}: lumen view {args:?} did not finish in 120 s");
    }
    let out = child.wait_with_output().expect("output");
    (out.status.success(), text(&out.stderr))
}

fn lit_pixels(path: &Path, size: (u32, u32)) -> usize {
    let img = image::open(path).expect("screenshot").to_rgba8();
    assert_eq!((img.width(), img.height()), size);
    img.pixels().filter(|p| p.0[0] > 20).count()
}

#[test]
fn view_presents_frames_in_a_window() {
    let x = Xvfb::start();
    let dir = tmp();
    for backend in ["vulkan", "gl"] {
        let shot = format!("shot-{backend}.png");
        // `--frames 3` exits only after three frames were presented to the window (with
        // the panel drawn over them).
        let args = [
            "--scene",
            "spheres",
            "--size",
            "96x64",
            "--frames",
            "3",
            "--screenshot",
            &shot,
        ];
        let (ok, err) = run_view(&x, dir.path(), backend, &args);
        assert!(ok, "{backend}: {err}");
        assert!(
            err.contains(&format!("({backend}, ")),
            "{backend}: adapter line missing: {err}"
        );
        let lit = lit_pixels(&dir.path().join(&shot), (96, 64));
        assert!(
            lit > 96 * 64 / 10,
            "{backend}: screenshot nearly black ({lit} lit pixels)"
        );
    }
}

#[test]
fn view_plays_a_files_first_clip_and_lists_its_clips() {
    // Fox.glb (CC BY 4.0, assets/README.md) has three clips; the viewer plays the first
    // in real time. Still knobs (no progressive probes, no AO noise) so that only the
    // animation can change the picture: held at 0 s (`--time 0`), frames 2 and 40 are
    // the same; playing, they are not.
    let x = Xvfb::start();
    let dir = tmp();
    let fox = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/models/Fox.glb");
    let fox = fox.display().to_string();
    let shot = |frames: &str, name: &str, time: Option<&str>| {
        let mut args = vec![
            fox.as_str(),
            "--size",
            "96x64",
            "--gi",
            "off",
            "--reflection-probes",
            "off",
            "--ao",
            "off",
            "--frames",
            frames,
            "--screenshot",
            name,
        ];
        if let Some(t) = time {
            args.extend(["--time", t]);
        }
        let (ok, err) = run_view(&x, dir.path(), "vulkan", &args);
        assert!(ok, "{err}");
        let image = image::open(dir.path().join(name))
            .expect("screenshot")
            .to_rgba8();
        (image, err)
    };
    let changed = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 8))
            .count()
    };
    let (early, err) = shot("2", "early.png", None);
    assert!(
        err.contains("animation 'Survey' plays (clips: Survey (")
            && err.contains("Walk (")
            && err.contains("Run ("),
        "{err}"
    );
    let (late, _) = shot("40", "late.png", None);
    let (held_early, err) = shot("2", "held-early.png", Some("0"));
    assert!(
        err.contains("animation 'Survey' is held at 0.00 s"),
        "{err}"
    );
    let (held_late, _) = shot("40", "held-late.png", Some("0"));
    let (moved, still) = (changed(&early, &late), changed(&held_early, &held_late));
    println!("pixels changed between frames 2 and 40: playing {moved}, held {still}");
    assert_eq!(still, 0, "nothing moves while the clip is held");
    assert!(
        moved > 20,
        "the fox moves while its clip plays ({moved} pixels)"
    );
}

#[test]
fn view_recovers_from_a_lost_device() {
    let x = Xvfb::start();
    let dir = tmp();
    for backend in ["vulkan", "gl"] {
        let shot = format!("lost-{backend}.png");
        // The hidden test hook destroys the device after two frames.
        let args = [
            "--scene",
            "spheres",
            "--size",
            "96x64",
            "--frames",
            "5",
            "--lose-device-after",
            "2",
            "--screenshot",
            &shot,
        ];
        let (ok, err) = run_view(&x, dir.path(), backend, &args);
        assert!(ok, "{backend}: {err}");
        assert!(err.contains("the GPU device was lost"), "{backend}: {err}");
        assert!(err.contains("recreated it on"), "{backend}: {err}");
        let lit = lit_pixels(&dir.path().join(&shot), (96, 64));
        assert!(
            lit > 96 * 64 / 10,
            "{backend}: the new device renders ({lit} lit)"
        );
    }
}

#[test]
fn view_shows_a_broken_shader_or_file_and_keeps_running() {
    let x = Xvfb::start();
    let dir = tmp();
    let shaders = dir.path().join("shaders");
    std::fs::create_dir(&shaders).expect("mkdir");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders");
    for entry in std::fs::read_dir(&source).expect("shaders/") {
        let path = entry.expect("entry").path();
        std::fs::copy(&path, shaders.join(path.file_name().expect("name"))).expect("copy");
    }
    let tonemap = shaders.join("tonemap.wgsl");
    let text_before = std::fs::read_to_string(&tonemap).expect("read");
    std::fs::write(
        &tonemap,
        text_before.replacen("fn fs_main(", "fn fs_main(((", 1),
    )
    .expect("write");
    let args = [
        "--scene",
        "spheres",
        "--size",
        "96x64",
        "--frames",
        "4",
        "--shaders",
        "shaders",
        "--screenshot",
        "shot.png",
        "--open",
        "missing.glb",
    ];
    let (ok, err) = run_view(&x, dir.path(), "vulkan", &args);
    assert!(ok, "the viewer goes on: {err}");
    assert!(
        err.contains("missing.glb: No such file"),
        "a bad --open is shown: {err}"
    );
    assert!(err.contains("tonemap"), "the error names the shader: {err}");
    assert!(err.contains("previous ones are back"), "{err}");
    let lit = lit_pixels(&dir.path().join("shot.png"), (96, 64));
    assert!(
        lit > 96 * 64 / 10,
        "the previous shaders render ({lit} lit pixels)"
    );
    // A missing shader folder is a one-line error before any window opens.
    let (ok, err) = run_view(&x, dir.path(), "vulkan", &["--shaders", "nowhere"]);
    assert!(
        !ok && err.contains("shader folder nowhere does not exist"),
        "{err}"
    );
}

#[test]
fn shadow_flags() {
    let dir = tmp();
    let out = lumen(
        &[
            "render",
            "--size",
            "32x32",
            "--out",
            "x.png",
            "--shadows",
            "off",
            "--json",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let passes: Vec<_> = report["passes"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|p| p["name"].as_str())
        .collect();
    assert!(!passes.contains(&"shadow"), "{passes:?}");
    let shadow = report["plan"]["passes"]
        .as_array()
        .into_iter()
        .flatten()
        .find(|p| p["name"] == "shadow")
        .cloned()
        .unwrap_or_default();
    assert_eq!(shadow["runs"], false);
    assert!(
        shadow["reason"]
            .as_str()
            .is_some_and(|r| r.contains("shadows = off"))
    );
    // Direct light only: the probes' captures would take most of each render.
    let render_shadows = |extra: &[&str]| {
        let mut args = vec![
            "render",
            "--scene",
            "shadows",
            "--size",
            "32x32",
            "--out",
            "s.png",
            "--gi",
            "off",
            "--reflection-probes",
            "off",
            "--json",
        ];
        args.extend_from_slice(extra);
        let out = lumen(&args, dir.path());
        assert!(out.status.success(), "{extra:?}: {}", text(&out.stderr));
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
        report
    };
    for filter in ["hardware", "tent", "pcf", "pcss"] {
        render_shadows(&["--shadow-filter", filter]);
    }
    // The mask pass runs at the resolution asked for, and not at all when off.
    let mask = |setting: &str| {
        let report = render_shadows(&["--shadow-mask", setting]);
        report["plan"]["passes"]
            .as_array()
            .into_iter()
            .flatten()
            .find(|p| p["name"] == "shadow mask")
            .cloned()
            .unwrap_or_default()
    };
    assert_eq!(mask("off")["runs"], false);
    for setting in ["half", "full"] {
        let pass = mask(setting);
        assert_eq!(pass["runs"], true, "{pass}");
        assert!(
            pass["reason"]
                .as_str()
                .is_some_and(|r| r.contains(&format!("{setting} resolution"))),
            "{pass}"
        );
    }
    assert_clean_failure(
        &lumen(&["render", "--shadow-filter", "vsm"], dir.path()),
        "vsm",
    );
    assert_clean_failure(
        &lumen(&["render", "--shadow-mask", "quarter"], dir.path()),
        "quarter",
    );
}

fn hdri(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../assets/hdri")
        .join(format!("{name}.exr"))
        .display()
        .to_string()
}

#[test]
fn environment_flags() {
    let dir = tmp();
    // The furnace from the command line: a linear EXR of exactly 1.0 everywhere. AO and
    // reflections are off: this checks the BRDF alone (AO treats the lossless occluders
    // as absorbing).
    let out = lumen(
        &[
            "render",
            "--scene",
            "furnace",
            "--ao",
            "off",
            "--ssr",
            "off",
            "--exposure",
            "1",
            "--size",
            "88x32",
            "--out",
            "f.exr",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let img = lumen::assets::image_io::load_rgba32f(&dir.path().join("f.exr")).expect("EXR");
    let worst = img
        .pixels()
        .flat_map(|p| p.0[..3].to_vec())
        .map(|v| (v - 1.0).abs())
        .fold(0.0f32, f32::max);
    assert!(worst <= 0.02, "furnace EXR deviates by {worst}");

    // spheres under a real HDRI: the sky pass runs, preprocessing is reported.
    let env = hdri("studio");
    let out = lumen(
        &[
            "render", "--env", &env, "--size", "64x36", "--out", "s.png", "--json",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let passes: Vec<_> = report["passes"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|p| p["name"].as_str())
        .collect();
    assert!(passes.contains(&"sky"), "{passes:?}");
    let steps: Vec<_> = report["preprocessing"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|s| s["step"].as_str())
        .collect();
    assert!(
        steps.contains(&"ggx prefilter") && steps.contains(&"spherical harmonics"),
        "{steps:?}"
    );

    // Hidden environment, uniform colour, rotation and blur are accepted.
    for extra in [
        vec!["--env", env.as_str(), "--env-hidden"],
        vec!["--env-color", "0.2,0.3,0.4", "--env-intensity", "500"],
        vec![
            "--env",
            env.as_str(),
            "--env-rotation",
            "-90",
            "--background-blur",
            "0.5",
        ],
        vec!["--env", env.as_str(), "--energy-compensation", "off"],
    ] {
        let mut args = vec!["render", "--size", "32x18", "--out", "e.png"];
        args.extend(extra.iter().copied());
        let out = lumen(&args, dir.path());
        assert!(out.status.success(), "{extra:?}: {}", text(&out.stderr));
    }
}

#[test]
fn bad_environment_files_are_one_line_errors() {
    let dir = tmp();
    let d = dir.path();
    assert_clean_failure(
        &lumen(&["render", "--size", "8x8", "--env", "missing.exr"], d),
        "missing.exr",
    );
    std::fs::write(d.join("junk.exr"), b"definitely not an exr").expect("write");
    assert_clean_failure(
        &lumen(&["render", "--size", "8x8", "--env", "junk.exr"], d),
        "junk.exr",
    );
    let real = std::fs::read(hdri("sky")).expect("sky.exr");
    std::fs::write(d.join("cut.exr"), &real[..real.len() / 3]).expect("write");
    assert_clean_failure(
        &lumen(&["render", "--size", "8x8", "--env", "cut.exr"], d),
        "cut.exr",
    );
    assert_clean_failure(&lumen(&["render", "--env-color", "1,2"], d), "1,2");
    assert_clean_failure(&lumen(&["render", "--background-blur", "3"], d), "3");
}

fn render_json(args: &[&str]) -> serde_json::Value {
    let dir = tmp();
    let mut all = vec!["render", "--size", "48x32", "--out", "o.png", "--json"];
    all.extend_from_slice(args);
    let out = lumen(&all, dir.path());
    assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("one JSON object on stdout")
}

fn pass_names(report: &serde_json::Value) -> Vec<String> {
    report["passes"]
        .as_array()
        .cloned()
        .unwrap_or_default()
        .iter()
        .filter_map(|p| p["name"].as_str().map(String::from))
        .collect()
}

#[test]
fn physical_exposure_matches_filament() {
    // Filament's example: f/16, 1/125 s, ISO 100 → EV100 14.97.
    let r = render_json(&["--aperture", "16", "--shutter", "1/125", "--iso", "100"]);
    let ev = r["ev100"].as_f64().unwrap_or(f64::NAN);
    assert!((ev - 14.97).abs() < 0.01, "{ev}");
    let exposure = r["exposure"].as_f64().unwrap_or(f64::NAN);
    assert!(
        ((exposure * 1.2 * 2f64.powf(ev)) - 1.0).abs() < 1e-4,
        "{exposure}"
    );
    assert_eq!(r["camera_notes"].as_array().map(Vec::len), Some(0), "{r}");
    // One stop each: ISO 200 (+1 EV... brighter: EV100 − 1), 1/250 s (EV + 1), f/22.6 (+1).
    for (args, want) in [
        (
            ["--aperture", "16", "--shutter", "1/125", "--iso", "200"],
            13.97,
        ),
        (
            ["--aperture", "16", "--shutter", "1/250", "--iso", "100"],
            15.97,
        ),
        (
            ["--aperture", "22.627", "--shutter", "1/125", "--iso", "100"],
            15.97,
        ),
    ] {
        let ev = render_json(&args)["ev100"].as_f64().unwrap_or(f64::NAN);
        assert!((ev - want).abs() < 0.01, "{args:?}: {ev}");
    }
}

#[test]
fn out_of_range_camera_settings_are_clamped_and_reported() {
    let r = render_json(&["--aperture", "0.1", "--shutter", "1/125", "--iso", "100"]);
    // Clamped to f/0.5: log2(0.25 · 125) = 4.97.
    let ev = r["ev100"].as_f64().unwrap_or(f64::NAN);
    assert!((ev - 4.97).abs() < 0.01, "{ev}");
    let notes = r["camera_notes"].to_string();
    assert!(notes.contains("aperture"), "{notes}");
    let r = render_json(&["--ev100", "-10", "--exposure-compensation", "5"]);
    assert_eq!(r["ev100"].as_f64(), Some(-10.0));
    assert!(r["camera_notes"].to_string().contains("clamped"), "{r}");
}

#[test]
fn camera_flags() {
    for name in ["none", "reinhard", "aces", "agx", "pbr-neutral"] {
        let r = render_json(&["--tonemap", name]);
        assert_eq!(r["tonemapper"], name);
    }
    let with = pass_names(&render_json(&["--dof", "on", "--focus", "2"]));
    assert!(with.iter().any(|p| p == "dof blur"), "{with:?}");
    let without = pass_names(&render_json(&["--scene", "dof", "--dof", "off"]));
    assert!(!without.iter().any(|p| p.starts_with("dof")), "{without:?}");
    let r = render_json(&["--auto-exposure"]);
    assert!(pass_names(&r).iter().any(|p| p == "exposure"), "{r}");
    let auto = &r["auto_exposure"];
    let (ev, target) = (auto["ev100"].as_f64(), auto["target_ev100"].as_f64());
    assert!(
        matches!((ev, target), (Some(e), Some(t)) if (e - t).abs() < 0.01),
        "{auto}"
    );
    // The frame was exposed with the adapted EV100 (the meter moved < 0.01 since).
    let used = r["ev100"].as_f64().unwrap_or(f64::NAN);
    assert!(
        (used - ev.unwrap_or(f64::NAN)).abs() < 0.01,
        "{used} vs {auto}"
    );
    let dir = tmp();
    for (args, needle) in [
        (vec!["--tonemap", "filmic"], "filmic"),
        (vec!["--aperture=-2"], "aperture"),
        (vec!["--shutter", "1/0"], "shutter"),
        (vec!["--dof-rings", "9"], "dof-rings"),
        (vec!["--vignette", "3"], "vignette"),
        (vec!["--focus", "nan"], "focus"),
    ] {
        let mut all = vec!["render", "--size", "16x16"];
        all.extend(args);
        assert_clean_failure(&lumen(&all, dir.path()), needle);
    }
}

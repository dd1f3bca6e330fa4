//! Golden images that gate CI: small renders of every built-in scene and key feature,
//! compared with FLIP against committed images in `tests/golden/`.
//!
//! - **One set of goldens**, rendered with lavapipe (Vulkan), checked on both lavapipe and
//!   GL (llvmpipe). Each case states its thresholds: the mean FLIP and the 99th percentile
//!   of per-pixel FLIP that the render on either backend must stay under. They were set
//!   above the measured GL-against-lavapipe difference (docs/src/tests.md, "Golden
//!   images", gives the numbers), so they hold on both, and tight enough that a one-line
//!   shader change fails them.
//! - **On failure** the test writes `target/golden-failures/<case>-<backend>-actual.png`
//!   and `…-flip.png` (the FLIP error map, magma colours) and names them.
//! - **Blessing**: `LUMEN_BLESS=1 cargo test --release --test golden` renders every case
//!   on lavapipe and overwrites its golden. Do it only when a change of the picture is
//!   intended (a new feature, a fixed bug, a changed default) and say so in the commit.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Side of every golden image, in pixels.
const SIZE: &str = "128x128";

/// One golden image: the `lumen render` arguments and the FLIP thresholds it must meet.
struct Case {
    name: &'static str,
    args: &'static [&'static str],
    /// Mean FLIP at most this.
    mean: f32,
    /// 99th percentile of per-pixel FLIP at most this.
    p99: f32,
}

/// The thresholds most cases use: mean 0.005, p99 0.05 (FLIP ranges 0..1). The largest
/// GL-against-lavapipe difference measured among them is mean 0.0019, p99 0.0162
/// (`cornell`, lit by its irradiance volume).
const fn case(name: &'static str, args: &'static [&'static str]) -> Case {
    Case {
        name,
        args,
        mean: 0.005,
        p99: 0.05,
    }
}

/// The thresholds of cases lit by an environment image: mean 0.02, p99 0.15. GL's
/// prefiltered environment differs from lavapipe's at the second and third mips (measured
/// mean 0.0104, p99 0.088 on `ibl-studio`; docs/src/tests.md, "Golden images").
const fn ibl_case(name: &'static str, args: &'static [&'static str]) -> Case {
    Case {
        name,
        args,
        mean: 0.02,
        p99: 0.15,
    }
}

const CASES: &[Case] = &[
    case("spheres", &["--scene", "spheres"]),
    case("plane", &["--scene", "plane"]),
    case("shadows-tent", &["--scene", "shadows"]),
    case(
        "shadows-pcf",
        &["--scene", "shadows", "--shadow-filter", "pcf"],
    ),
    case(
        "shadows-hardware",
        &["--scene", "shadows", "--shadow-filter", "hardware"],
    ),
    case(
        "shadows-pcss",
        &["--scene", "shadows", "--shadow-filter", "pcss"],
    ),
    case(
        "furnace",
        &["--scene", "furnace", "--ao", "off", "--ssr", "off"],
    ),
    case("dof", &["--scene", "dof"]),
    case("lights", &["--scene", "lights"]),
    // The numerical guards of direct light, without the probes: next to the block's
    // 65504-clamped emissive, GL and lavapipe filter the mirror floor's probe reflection
    // apart by a mean FLIP of 0.0051 (`render_extremes_is_finite` covers them finite).
    case(
        "extremes",
        &[
            "--scene",
            "extremes",
            "--gi",
            "off",
            "--reflection-probes",
            "off",
        ],
    ),
    case("cornell", &["--scene", "cornell"]),
    case(
        "ao-cornell",
        &["--scene", "cornell", "--env-color", "0.3,0.3,0.3"],
    ),
    case(
        "debug-occlusion",
        &[
            "--scene",
            "shadows",
            "--env-color",
            "1,1,1",
            "--debug-view",
            "occlusion",
        ],
    ),
    case(
        "debug-occlusion-full",
        &[
            "--scene",
            "cornell",
            "--env-color",
            "1,1,1",
            "--debug-view",
            "occlusion",
            "--ao",
            "full",
            "--ao-denoise",
            "off",
        ],
    ),
    ibl_case(
        "ibl-studio",
        &["--scene", "spheres", "--env", "assets/hdri/studio.exr"],
    ),
    ibl_case(
        "ibl-sky-no-shadows",
        &[
            "--scene",
            "shadows",
            "--env",
            "assets/hdri/sky.exr",
            "--shadows",
            "off",
        ],
    ),
    case("tonemap-aces", &["--scene", "spheres", "--tonemap", "aces"]),
    case("tonemap-agx", &["--scene", "spheres", "--tonemap", "agx"]),
    case("quality-low", &["--scene", "shadows", "--quality", "low"]),
    case(
        "debug-albedo",
        &["--scene", "spheres", "--debug-view", "albedo"],
    ),
    case(
        "debug-normal",
        &["--scene", "spheres", "--debug-view", "normal"],
    ),
    case(
        "debug-roughness",
        &["--scene", "spheres", "--debug-view", "roughness"],
    ),
    case(
        "debug-depth",
        &["--scene", "shadows", "--debug-view", "depth"],
    ),
    case(
        "debug-shadow-atlas",
        &["--scene", "shadows", "--debug-view", "shadow-atlas"],
    ),
    case("debug-coc", &["--scene", "dof", "--debug-view", "coc"]),
    // The main job's scene: the helmet's textures, its blended lenses, the HDRI and its
    // sun, the probes and every `high` feature (GL against lavapipe: mean 0.0015, p99
    // 0.0126, within the default thresholds).
    case("showcase", &["--scene", "showcase"]),
    case("materials", &["--scene", "materials"]),
    case("aliasing", &["--scene", "aliasing"]),
    case("gltf-suzi", &["assets/models/suzi.glb"]),
    case("gltf-textures", &["GENERATED_TEXTURED_QUAD"]),
];

/// The backends every golden is checked on: `WGPU_BACKEND` values and the name used in
/// file names.
const BACKENDS: &[(&str, &str)] = &[("vulkan", "lavapipe"), ("gl", "gl")];

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn golden_path(case: &Case) -> PathBuf {
    repo()
        .join("tests/golden")
        .join(format!("{}.png", case.name))
}

/// Writes a textured glTF quad (an 8×8 checker base colour, a roughness ramp in the
/// metallic-roughness map) into `dir` and returns its path.
fn textured_quad(dir: &Path) -> PathBuf {
    let checker = image::RgbaImage::from_fn(8, 8, |x, y| {
        if (x + y) % 2 == 0 {
            image::Rgba([220, 60, 30, 255])
        } else {
            image::Rgba([240, 230, 210, 255])
        }
    });
    checker.save(dir.join("checker.png")).expect("checker png");
    let ramp = image::RgbaImage::from_fn(8, 8, |x, _| {
        image::Rgba([0, (x * 32) as u8, if x >= 4 { 255 } else { 0 }, 255])
    });
    ramp.save(dir.join("ramp.png")).expect("ramp png");
    let bin = common::quad_buffer(1.0);
    std::fs::write(dir.join("quad.bin"), &bin).expect("bin");
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "rotation": [-0.25881904, 0.0, 0.0, 0.9659258]},
            {"camera": 0, "translation": [0.0, 0.0, 3.2]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0}}],
        "images": [{"uri": "checker.png"}, {"uri": "ramp.png"}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
        "materials": [{"pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0},
            "metallicRoughnessTexture": {"index": 1}
        }}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "buffers": [{"byteLength": bin.len(), "uri": "quad.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.join("quad.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).expect("json")).expect("gltf");
    path
}

/// Renders `case` on `backend` into `out`; panics with lumen's stderr if it fails.
fn render(case: &Case, backend: &str, out: &Path, scratch: &Path) {
    let mut args: Vec<String> = vec!["render".into()];
    for a in case.args {
        args.push(if *a == "GENERATED_TEXTURED_QUAD" {
            textured_quad(scratch).display().to_string()
        } else {
            (*a).to_string()
        });
    }
    args.extend(["--size".into(), SIZE.into(), "--out".into()]);
    args.push(out.display().to_string());
    let output = Command::new(env!("CARGO_BIN_EXE_lumen"))
        .args(&args)
        .current_dir(repo())
        .env("WGPU_BACKEND", backend)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("lumen runs");
    assert!(
        output.status.success(),
        "{} on {backend}: lumen {}: {}",
        case.name,
        args.join(" "),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// FLIP of `test` against `reference` (8-bit sRGB images of one size): the mean, the
/// 99th percentile of the per-pixel values, and the error map.
fn flip(
    reference: &image::RgbImage,
    test: &image::RgbImage,
) -> (f32, f32, nv_flip::FlipImageFloat) {
    let (w, h) = reference.dimensions();
    let map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, reference.as_raw()),
        nv_flip::FlipImageRgb8::with_data(w, h, test.as_raw()),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&map).mean();
    let mut values = map.to_vec();
    values.sort_by(f32::total_cmp);
    let p99 = values[((values.len() - 1) as f64 * 0.99).round() as usize];
    (mean, p99, map)
}

fn read_rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8()
}

#[test]
fn golden_images_match_on_lavapipe_and_gl() {
    let bless = std::env::var_os("LUMEN_BLESS").is_some();
    let scratch = tempfile::tempdir().expect("temp dir");
    let failures_dir = repo().join("target/golden-failures");
    let mut failures = Vec::new();
    let mut report =
        String::from("case                 backend    mean FLIP (max)    p99 FLIP (max)\n");
    for case in CASES {
        if bless {
            let golden = golden_path(case);
            render(case, "vulkan", &golden, scratch.path());
            report.push_str(&format!("blessed {}\n", golden.display()));
            continue;
        }
        let golden = read_rgb(&golden_path(case));
        for (backend, label) in BACKENDS {
            let out = scratch.path().join(format!("{}-{label}.png", case.name));
            render(case, backend, &out, scratch.path());
            let actual = read_rgb(&out);
            assert_eq!(
                actual.dimensions(),
                golden.dimensions(),
                "{}: size differs from the golden",
                case.name
            );
            let (mean, p99, map) = flip(&golden, &actual);
            report.push_str(&format!(
                "{:<20} {:<10} {mean:.4} ({:.3})    {p99:.4} ({:.3})\n",
                case.name, label, case.mean, case.p99
            ));
            if mean > case.mean || p99 > case.p99 {
                std::fs::create_dir_all(&failures_dir).expect("failures dir");
                let stem = failures_dir.join(format!("{}-{label}", case.name));
                let actual_path = stem.with_extension("actual.png");
                let flip_path = stem.with_extension("flip.png");
                actual.save(&actual_path).expect("write actual");
                let colored = map.apply_color_lut(&nv_flip::magma_lut());
                let (w, h) = golden.dimensions();
                image::RgbImage::from_raw(w, h, colored.to_vec())
                    .expect("flip map size")
                    .save(&flip_path)
                    .expect("write flip map");
                failures.push(format!(
                    "{} on {label}: mean FLIP {mean:.4} (max {}), p99 {p99:.4} (max {}); actual {}, FLIP map {}",
                    case.name,
                    case.mean,
                    case.p99,
                    actual_path.display(),
                    flip_path.display()
                ));
            }
        }
    }
    println!("{report}");
    assert!(
        failures.is_empty(),
        "{} golden image(s) differ (LUMEN_BLESS=1 regenerates them, only for an intended change):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn every_golden_has_a_case_and_every_case_a_golden() {
    let dir = repo().join("tests/golden");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("tests/golden")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png"))
        .collect();
    files.sort();
    let mut names: Vec<String> = CASES.iter().map(|c| format!("{}.png", c.name)).collect();
    names.sort();
    assert_eq!(files, names, "tests/golden/ and CASES disagree");
}

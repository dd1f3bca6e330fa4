//! The PBR texture validator and workflow converter: one synthetic texture per rule
//! gives exactly the expected verdicts (both boundary values included), the command
//! line reports, writes heat maps and exits 3 on failure, conversions round-trip where
//! they can, and the seeds' numbers hold.

use Verdict::{Borderline as B, Invalid as X, NotApplicable as N, Valid as V};
use lumen::scene::{ColorSpace, TextureData};
use lumen::shading::color::srgb_decode;
use lumen::validate::{
    ColorInput, MaterialInput, Rule, ScalarInput, Verdict, brightness_code, validate,
};
use std::path::Path;
use std::process::Command;

/// A one-row texture of grey (or coloured) 8-bit texels.
fn row(texels: &[[u8; 3]], color_space: ColorSpace) -> TextureData {
    TextureData {
        width: texels.len() as u32,
        height: 1,
        rgba8: texels
            .iter()
            .flat_map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        color_space,
    }
}

fn grey(codes: &[u8]) -> Vec<[u8; 3]> {
    codes.iter().map(|&c| [c, c, c]).collect()
}

fn metal_rough(base: &[u8], metallic: &[u8]) -> MaterialInput {
    MaterialInput::MetalRough {
        base_color: ColorInput {
            texture: Some(row(&grey(base), ColorSpace::Srgb)),
            factor: glam::Vec3::ONE,
        },
        metallic: ScalarInput {
            texture: Some(row(&grey(metallic), ColorSpace::Linear)),
            channel: 0,
            factor: 1.0,
        },
        roughness: ScalarInput {
            texture: None,
            channel: 0,
            factor: 0.5,
        },
    }
}

fn spec_gloss(diffuse: &[u8], specular: &[u8]) -> MaterialInput {
    let color = |codes: &[u8]| ColorInput {
        texture: Some(row(&grey(codes), ColorSpace::Srgb)),
        factor: glam::Vec3::ONE,
    };
    MaterialInput::SpecGloss {
        diffuse: color(diffuse),
        specular: color(specular),
        glossiness: ScalarInput {
            texture: None,
            channel: 0,
            factor: 0.5,
        },
    }
}

/// The verdicts of `rule` along the row, read back from its heat map.
fn verdicts_of(material: &MaterialInput, rule: Rule, strict: bool) -> Vec<Verdict> {
    let report = validate(material, strict);
    let r = report
        .rules
        .iter()
        .find(|r| r.rule == rule)
        .expect("the rule is reported");
    let all = [N, V, B, X];
    let found: Vec<Verdict> = r
        .heatmap
        .pixels()
        .map(|p| {
            *all.iter()
                .find(|v| v.color() == p.0)
                .expect("a verdict colour")
        })
        .collect();
    let count = |v: Verdict| found.iter().filter(|f| **f == v).count() as u64;
    assert_eq!(r.invalid, count(X), "{} count", rule.name());
    assert_eq!(r.borderline, count(B), "{} count", rule.name());
    assert_eq!(
        r.checked,
        found.len() as u64 - count(N),
        "{} count",
        rule.name()
    );
    found
}

#[test]
fn base_color_range_of_dielectrics() {
    let base = [29, 30, 39, 40, 230, 231, 240, 241, 49, 50];
    let m = metal_rough(&base, &[0; 10]);
    assert_eq!(
        verdicts_of(&m, Rule::BaseColorRange, false),
        [X, B, B, V, V, B, B, X, V, V]
    );
    assert_eq!(
        verdicts_of(&m, Rule::BaseColorRange, true),
        [X, X, X, X, V, B, B, X, X, B]
    );
    // Bare metal is another rule's business.
    let metal = metal_rough(&[10, 10], &[234, 235]);
    assert_eq!(verdicts_of(&metal, Rule::BaseColorRange, false), [X, N]);
}

#[test]
fn metal_reflectance_of_bare_metal() {
    let m = metal_rough(
        &[179, 180, 189, 190, 255, 200],
        &[255, 255, 235, 235, 255, 234],
    );
    assert_eq!(
        verdicts_of(&m, Rule::MetalReflectance, false),
        [X, B, B, V, V, N]
    );
}

#[test]
fn partial_metal_must_lower_the_base_color() {
    let m = metal_rough(
        &[169, 170, 179, 180, 200, 200, 200],
        &[128, 128, 128, 128, 9, 10, 235],
    );
    assert_eq!(
        verdicts_of(&m, Rule::PartialMetal, false),
        [V, B, B, X, N, X, N]
    );
}

#[test]
fn dirt_marked_as_metal() {
    let m = metal_rough(&[99, 100, 60, 60], &[255, 255, 235, 234]);
    assert_eq!(verdicts_of(&m, Rule::DirtAsMetal, false), [X, V, X, N]);
}

/// The first 8-bit sRGB code whose linear value reaches `linear`.
fn first_code_at_least(linear: f32) -> u8 {
    (0..=255u8)
        .find(|c| srgb_decode(f32::from(*c) / 255.0) >= linear)
        .expect("a code")
}

#[test]
fn specular_classes_and_their_gaps() {
    let low = first_code_at_least(0.02);
    let gem_top = first_code_at_least(0.17) - 1;
    let plastic = first_code_at_least(0.04);
    let gem = first_code_at_least(0.1);
    let specular = [
        low - 1,
        low,
        plastic,
        gem,
        gem_top,
        gem_top + 1,
        179,
        180,
        190,
    ];
    let m = spec_gloss(&[128; 9], &specular);
    assert_eq!(
        verdicts_of(&m, Rule::SpecularClass, false),
        [X, B, V, V, B, X, X, B, V]
    );
}

#[test]
fn energy_is_diffuse_plus_specular_at_most_one() {
    // 255 + 0 is exactly 1; 255 + 1 is above it.
    let m = spec_gloss(&[0, 1, 128, 200], &[255, 255, 56, 56]);
    assert_eq!(verdicts_of(&m, Rule::Energy, false), [B, X, V, V]);
}

#[test]
fn black_diffuse_only_under_metal_specular() {
    let m = spec_gloss(&[29, 30, 240, 241, 0, 0], &[56, 56, 56, 56, 56, 255]);
    assert_eq!(
        verdicts_of(&m, Rule::DiffuseRange, false),
        [X, B, B, X, X, N]
    );
    assert_eq!(verdicts_of(&m, Rule::DiffuseRange, true)[..2], [X, X]);
}

#[test]
fn the_seeds_numbers_hold() {
    assert!((lumen::shading::brdf::f0_from_ior(1.5) - 0.04).abs() < 1e-7);
    assert!((lumen::shading::brdf::dielectric_f0(0.5) - 0.04).abs() < 1e-7);
    // 180 sRGB is the guide's 70 % metal floor; docs/src/formulas.md#measured-texture-ranges notes it is 0.46 linear.
    assert!((srgb_decode(180.0 / 255.0) - 0.456).abs() < 1e-3);
    assert_eq!(
        brightness_code(glam::Vec3::splat(srgb_decode(180.0 / 255.0))),
        180
    );
    let out = lumen(
        &["convert", "--ior", "1.5", "--specular-level", "0.5"],
        Path::new("."),
    );
    assert!(out.0, "{}", out.2);
    assert!(out.1.contains("IOR 1.5 → F0 0.0400"), "{}", out.1);
    assert!(
        out.1.contains("specular level 0.5 → F0 0.0400"),
        "{}",
        out.1
    );
}

/// Runs `lumen ARGS` in `dir`: success, stdout, stderr, exit code.
fn lumen(args: &[&str], dir: &Path) -> (bool, String, String, Option<i32>) {
    let out = Command::new(env!("CARGO_BIN_EXE_lumen"))
        .args(args)
        .current_dir(dir)
        .env_remove("DISPLAY")
        .output()
        .expect("lumen runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        out.status.code(),
    )
}

fn save_rgb(path: &Path, texels: &[[u8; 3]], width: u32) {
    let h = texels.len() as u32 / width;
    let image = image::RgbImage::from_fn(width, h, |x, y| {
        image::Rgb(texels[(y * width + x) as usize])
    });
    image.save(path).expect("save");
}

fn save_grey(path: &Path, codes: &[u8], width: u32) {
    let h = codes.len() as u32 / width;
    let image = image::GrayImage::from_fn(width, h, |x, y| {
        image::Luma([codes[(y * width + x) as usize]])
    });
    image.save(path).expect("save");
}

#[test]
fn the_command_reports_writes_heat_maps_json_and_exits_3_on_failure() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    save_rgb(&d.join("good.png"), &grey(&[120, 200]), 2);
    save_rgb(&d.join("bad.png"), &grey(&[10, 200]), 2);
    save_grey(&d.join("metal.png"), &[0, 255], 2);
    let (ok, stdout, stderr, _) = lumen(
        &[
            "validate",
            "--base-color",
            "good.png",
            "--metallic",
            "metal.png",
        ],
        d,
    );
    assert!(ok, "{stderr}");
    assert!(stdout.contains("PASS"), "{stdout}");
    let (ok, stdout, stderr, code) = lumen(
        &[
            "validate",
            "--base-color",
            "bad.png",
            "--metallic",
            "metal.png",
            "--heatmap",
            "hm",
            "--json",
            "report.json",
        ],
        d,
    );
    assert!(!ok && code == Some(3), "{stderr}");
    assert!(
        stdout.contains("base-color-range") && stdout.contains("FAIL"),
        "{stdout}"
    );
    assert!(stderr.contains("1 of 1 material(s) fail"), "{stderr}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("report.json")).expect("json")).expect("JSON");
    assert_eq!(json["schema"], "lumen-validate/1");
    assert_eq!(json["passes"], false);
    let rules = json["materials"][0]["rules"].as_array().expect("rules");
    let range = rules
        .iter()
        .find(|r| r["rule"] == "base-color-range")
        .expect("rule");
    assert_eq!(
        (range["checked"].as_u64(), range["invalid"].as_u64()),
        (Some(1), Some(1))
    );
    assert_eq!(range["invalid_share"], 1.0);
    let heat = image::open(d.join("hm/0-textures.png"))
        .expect("heat map")
        .to_rgb8();
    assert_eq!(heat.get_pixel(0, 0).0, Verdict::Invalid.color());
    assert_eq!(heat.get_pixel(1, 0).0, Verdict::Valid.color());
    assert!(d.join("hm/0-textures-dirt-as-metal.png").is_file());

    // Bad input: one-line errors, never a panic.
    for (args, expect) in [
        (vec!["validate"], "nothing to validate"),
        (
            vec!["validate", "--base-color", "missing.png"],
            "missing.png",
        ),
        (
            vec!["validate", "--diffuse", "good.png"],
            "needs both --diffuse and --specular",
        ),
        (vec!["validate", "nope.glb"], "nope.glb"),
        (
            vec![
                "convert",
                "--diffuse",
                "good.png",
                "--specular",
                "good.png",
                "--to",
                "spec-gloss",
            ],
            "spec/gloss already",
        ),
        (vec!["convert", "--to", "roughness"], "nothing to convert"),
        (
            vec!["convert", "--roughness", "good.png", "--to", "roughness"],
            "needs --glossiness",
        ),
    ] {
        let (ok, _, stderr, code) = lumen(&args, d);
        assert!(!ok && code == Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
    }
    let (_, _, stderr, code) = lumen(
        &["validate", "--base-color", "a.png", "--diffuse", "b.png"],
        d,
    );
    assert_eq!(code, Some(2), "mixed workflows are a usage error: {stderr}");
}

#[test]
fn gltf_materials_are_validated_each() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    let gltf = r#"{"asset": {"version": "2.0"}, "materials": [
        {"name": "plastic", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 1], "metallicFactor": 0}},
        {"name": "dirty metal", "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1], "metallicFactor": 1}},
        {"name": "gem", "extensions": {"KHR_materials_pbrSpecularGlossiness": {
            "diffuseFactor": [0.3, 0.3, 0.3, 1], "specularFactor": [0.1, 0.1, 0.1], "glossinessFactor": 0.9}}}
    ], "extensionsUsed": ["KHR_materials_pbrSpecularGlossiness"]}"#;
    std::fs::write(d.join("m.gltf"), gltf).expect("write");
    let (ok, stdout, stderr, code) = lumen(&["validate", "m.gltf", "--json", "-"], d);
    assert!(!ok && code == Some(3), "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).expect("JSON on stdout");
    let materials = json["materials"].as_array().expect("materials");
    let passes: Vec<(&str, bool)> = materials
        .iter()
        .map(|m| (m["name"].as_str().unwrap_or(""), m["passes"] == true))
        .collect();
    assert_eq!(
        passes,
        [("plastic", true), ("dirty metal", false), ("gem", true)]
    );
    assert_eq!(materials[2]["workflow"], "specular/glossiness");

    // Converting the file: each metal/rough material gets a folder, the gem is skipped.
    let (ok, stdout, stderr, _) = lumen(
        &["convert", "m.gltf", "--to", "spec-gloss", "--out", "c"],
        d,
    );
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("gem: in that workflow already; skipped"),
        "{stdout}"
    );
    let specular = image::open(d.join("c/1-dirty_metal/specular.png"))
        .expect("specular")
        .to_rgb8();
    // A metal's specular is its base colour: 0.05 linear is sRGB code 63.
    assert_eq!(specular.get_pixel(0, 0).0, [63, 63, 63]);
    assert!(d.join("c/0-plastic/diffuse.png").is_file());
}

#[test]
fn metal_rough_round_trips_through_spec_gloss_where_it_can() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    // Dielectric greys and colours, and coloured metals, which convert exactly; grey
    // and coloured partial metals, whose metallic the 8-bit specular pins down only to a
    // few codes; and a dielectric white (base above 0.96), which spec/gloss cannot hold.
    let mut base: Vec<[u8; 3]> = Vec::new();
    let mut metallic: Vec<u8> = Vec::new();
    let mut roughness: Vec<u8> = Vec::new();
    for (k, c) in [30u8, 60, 120, 180, 240].iter().enumerate() {
        base.push([*c, *c, *c]);
        metallic.push(0);
        roughness.push(40 * k as u8);
    }
    for c in [[200, 60, 30], [30, 120, 200], [90, 200, 90]] {
        base.push(c);
        metallic.push(0);
        roughness.push(128);
    }
    for c in [
        [255, 195, 86],
        [250, 208, 192],
        [196, 199, 199],
        [180, 180, 255],
    ] {
        base.push(c);
        metallic.push(255);
        roughness.push(77);
    }
    let exact = base.len();
    for (c, m) in [
        ([150u8, 150, 150], 128u8),
        ([100, 100, 100], 64),
        ([170, 170, 170], 200),
        ([230, 120, 40], 128),
    ] {
        base.push(c);
        metallic.push(m);
        roughness.push(200);
    }
    let white = base.len();
    base.push([255, 255, 255]);
    metallic.push(0);
    roughness.push(10);
    let n = base.len() as u32;
    save_rgb(&d.join("base.png"), &base, n);
    save_grey(&d.join("metallic.png"), &metallic, n);
    save_grey(&d.join("roughness.png"), &roughness, n);

    let (ok, stdout, stderr, _) = lumen(
        &[
            "convert",
            "--base-color",
            "base.png",
            "--metallic",
            "metallic.png",
            "--roughness",
            "roughness.png",
            "--to",
            "spec-gloss",
            "--out",
            "sg",
        ],
        d,
    );
    assert!(ok, "{stderr}");
    let mask = image::open(d.join("sg/not-invertible.png"))
        .expect("mask")
        .to_luma8();
    let flagged: Vec<usize> = (0..n as usize)
        .filter(|&i| mask.get_pixel(i as u32, 0).0[0] == 255)
        .collect();
    assert!(
        flagged.contains(&white),
        "the dielectric white is reported: {flagged:?}"
    );
    assert!(
        flagged.iter().all(|&i| i >= exact),
        "pure dielectrics and metals convert exactly: {flagged:?}"
    );
    assert!(
        stdout.contains(&format!(" {} texel(s)", flagged.len())),
        "the report counts what the mask shows: {stdout}"
    );

    let (ok, _, stderr, _) = lumen(
        &[
            "convert",
            "--diffuse",
            "sg/diffuse.png",
            "--specular",
            "sg/specular.png",
            "--glossiness",
            "sg/glossiness.png",
            "--to",
            "metal-rough",
            "--out",
            "mr",
        ],
        d,
    );
    assert!(ok, "{stderr}");
    let back_base = image::open(d.join("mr/base_color.png"))
        .expect("base")
        .to_rgb8();
    let back_metal = image::open(d.join("mr/metallic.png"))
        .expect("metallic")
        .to_luma8();
    let back_rough = image::open(d.join("mr/roughness.png"))
        .expect("roughness")
        .to_luma8();
    for i in (0..n as usize).filter(|i| !flagged.contains(i)) {
        let x = i as u32;
        let b = back_base.get_pixel(x, 0).0;
        for c in 0..3 {
            assert!(
                b[c].abs_diff(base[i][c]) <= 1,
                "texel {i}: base {b:?} vs {:?}",
                base[i]
            );
        }
        assert!(
            back_metal.get_pixel(x, 0).0[0].abs_diff(metallic[i]) <= 1,
            "texel {i} metallic"
        );
        assert!(
            back_rough.get_pixel(x, 0).0[0].abs_diff(roughness[i]) <= 1,
            "texel {i} roughness"
        );
    }
    // Glossiness ↔ roughness is exact.
    let (ok, _, stderr, _) = lumen(
        &[
            "convert",
            "--glossiness",
            "sg/glossiness.png",
            "--to",
            "roughness",
            "--out",
            "r",
        ],
        d,
    );
    assert!(ok, "{stderr}");
    let r = image::open(d.join("r/roughness.png"))
        .expect("roughness")
        .to_luma8();
    for (i, v) in roughness.iter().enumerate() {
        assert_eq!(r.get_pixel(i as u32, 0).0[0], *v, "texel {i}");
    }
}

#[test]
fn the_safe_color_fix_is_reported_and_makes_the_texture_pass() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    save_rgb(&d.join("base.png"), &grey(&[5, 120, 250, 60]), 4);
    save_grey(&d.join("metallic.png"), &[0, 0, 0, 255], 4);
    let (ok, stdout, stderr, _) = lumen(
        &[
            "convert",
            "--safe-color",
            "--base-color",
            "base.png",
            "--metallic",
            "metallic.png",
            "--out",
            "safe",
        ],
        d,
    );
    assert!(ok, "{stderr}");
    assert!(stdout.contains("safe colour: 3 texel(s)"), "{stdout}");
    let fixed = image::open(d.join("safe/base_color.png"))
        .expect("fixed")
        .to_rgb8();
    assert_eq!(
        fixed.get_pixel(1, 0).0,
        [120, 120, 120],
        "a valid texel is kept"
    );
    let (ok, _, stderr, _) = lumen(
        &[
            "validate",
            "--base-color",
            "safe/base_color.png",
            "--metallic",
            "safe/metallic.png",
        ],
        d,
    );
    assert!(ok, "the fixed texture passes: {stderr}");
}

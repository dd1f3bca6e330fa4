//! glTF import: files written here render the values `brdf.rs` predicts, the two PBR
//! workflows render alike, the real assets load and frame, and every broken file in
//! `tests/data/gltf/` is a one-line error naming the file (or its documented fallback).

use crate::common;

use lumen::assets::gltf::{GltfSummary, load_gltf};
use lumen::prelude::*;
use lumen::scene::{ColorSpace, MaterialMaps};
use lumen::shading::brdf::{Surface, VisibilityModel, surface_brdf_lobes};
use lumen::workflow::{MetalRough, to_spec_gloss};
use lumen::{App, FrameTarget};
use serde_json::json;
use std::path::{Path, PathBuf};

const SIZE: (u32, u32) = (64, 64);
/// Illuminance of the test files' sun (lx), shining straight at the quad.
const SUN_LUX: f32 = 1000.0;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/gltf")
        .join(name)
}

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../assets/models")
        .join(name)
}

/// A 4 × 4 m quad facing +z at z = 0 (positions and texture coordinates), a camera at
/// z = 3 looking down −z, a KHR_lights_punctual sun shining down −z, and `material`.
/// Writes `quad.gltf` and `quad.bin` into `dir` and returns the .gltf path.
fn write_quad(dir: &Path, material: serde_json::Value, extensions: &[&str]) -> PathBuf {
    write_quad_with(dir, material, extensions, json!({}), [0.0, 0.0, 0.0, 1.0])
}

/// [`write_quad`] with `extra` merged into the document's root (images, textures,
/// samplers) and the sun's node rotated by the quaternion `sun_rotation` (x, y, z, w).
fn write_quad_with(
    dir: &Path,
    material: serde_json::Value,
    extensions: &[&str],
    extra: serde_json::Value,
    sun_rotation: [f32; 4],
) -> PathBuf {
    let bin = common::quad_buffer(2.0);
    std::fs::write(dir.join("quad.bin"), &bin).expect("write bin");
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": extensions.iter().chain(["KHR_lights_punctual"].iter()).collect::<Vec<_>>(),
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": SUN_LUX, "color": [1.0, 1.0, 1.0]}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0.0, 0.0, 3.0]},
            {"rotation": sun_rotation, "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0}}],
        "materials": [material],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "buffers": [{"byteLength": bin.len(), "uri": "quad.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-2.0, -2.0, 0.0], "max": [2.0, 2.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let mut doc = doc;
    if let (Some(root), Some(more)) = (doc.as_object_mut(), extra.as_object()) {
        for (k, v) in more {
            root.insert(k.clone(), v.clone());
        }
    }
    let path = dir.join("quad.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).expect("json")).expect("write gltf");
    path
}

/// Loads `path` into a fresh app without energy compensation (so the expected value is
/// the plain BRDF), renders it, and returns the centre pixel, the exposure and the summary.
fn render_centre(path: &Path) -> (Vec3, f32, GltfSummary) {
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, path).expect("loads");
    app.world_mut()
        .resource_mut::<Quality>()
        .energy_compensation = false;
    let report = app.render_headless(SIZE).expect("frame");
    let hdr = app.read_hdr_image().expect("readback");
    let p = hdr.get_pixel(SIZE.0 / 2, SIZE.1 / 2).0;
    (Vec3::new(p[0], p[1], p[2]), report.exposure, summary)
}

/// The CPU BRDF's radiance at the centre: n = v = l = +z.
fn expected(base: Vec3, metallic: f32, roughness: f32, specular_level: f32) -> Vec3 {
    let surface = Surface {
        base_color: base,
        metallic,
        perceptual_roughness: roughness,
        specular_level,
    };
    let lobes = surface_brdf_lobes(
        Vec3::Z,
        Vec3::Z,
        Vec3::Z,
        &surface,
        VisibilityModel::default(),
    );
    (lobes.diffuse + lobes.specular) * SUN_LUX
}

fn relative_error(a: Vec3, b: Vec3) -> f32 {
    (a - b).abs().max_element() / b.max_element()
}

#[test]
fn a_written_quad_renders_the_brdf_value() {
    let dir = tempfile::tempdir().expect("temp dir");
    let base = Vec3::new(0.6, 0.3, 0.1);
    for (metallic, roughness, ior) in [(0.0f32, 0.8f32, 1.5f32), (1.0, 0.5, 1.5), (0.0, 0.6, 2.0)] {
        let material = json!({
            "pbrMetallicRoughness": {
                "baseColorFactor": [base.x, base.y, base.z, 1.0],
                "metallicFactor": metallic, "roughnessFactor": roughness
            },
            "extensions": {"KHR_materials_ior": {"ior": ior}}
        });
        let path = write_quad(dir.path(), material, &["KHR_materials_ior"]);
        let (pixel, exposure, summary) = render_centre(&path);
        assert!(summary.has_camera && summary.lights == 1 && !summary.default_lighting);
        let level = (((ior - 1.0) / (ior + 1.0)).powi(2) / 0.08).min(1.0);
        let want = expected(base, metallic, roughness, level) * exposure;
        let err = relative_error(pixel, want);
        println!(
            "metallic {metallic} roughness {roughness} ior {ior}: {pixel} vs {want} ({err:.4})"
        );
        // The G-buffer stores base colour in 8 bits and the HDR target is f16.
        assert!(err < 0.01, "{pixel} vs {want}");
    }
}

#[test]
fn spec_gloss_renders_like_its_metal_rough_twin() {
    let dir = tempfile::tempdir().expect("temp dir");
    for (base, metallic, roughness) in [
        (Vec3::new(0.5, 0.5, 0.5), 0.0, 0.7),
        (Vec3::new(0.95, 0.64, 0.54), 1.0, 0.3),
        (Vec3::splat(0.7), 0.5, 0.5),
    ] {
        let mr = json!({"pbrMetallicRoughness": {
            "baseColorFactor": [base.x, base.y, base.z, 1.0],
            "metallicFactor": metallic, "roughnessFactor": roughness
        }});
        let (a, _, _) = render_centre(&write_quad(dir.path(), mr, &[]));
        let sg = to_spec_gloss(MetalRough {
            base_color: base,
            metallic,
            roughness,
        });
        let material = json!({"extensions": {"KHR_materials_pbrSpecularGlossiness": {
            "diffuseFactor": [sg.diffuse.x, sg.diffuse.y, sg.diffuse.z, 1.0],
            "specularFactor": [sg.specular.x, sg.specular.y, sg.specular.z],
            "glossinessFactor": sg.glossiness
        }}});
        let (b, _, _) = render_centre(&write_quad(
            dir.path(),
            material,
            &["KHR_materials_pbrSpecularGlossiness"],
        ));
        let err = relative_error(b, a);
        println!("{base} metallic {metallic}: metal/rough {a}, spec/gloss {b} ({err:.4})");
        // Both go through the same 8-bit G-buffer; the conversion is exact for these.
        assert!(err < 0.01, "{a} vs {b}");
    }
}

#[test]
fn material_extensions_map_onto_the_material() {
    let dir = tempfile::tempdir().expect("temp dir");
    let material = json!({
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0]},
        "emissiveFactor": [1.0, 0.5, 0.0],
        "extensions": {
            "KHR_materials_emissive_strength": {"emissiveStrength": 40.0},
            "KHR_materials_specular": {"specularFactor": 0.5},
            "KHR_materials_ior": {"ior": 1.5}
        }
    });
    let path = write_quad(
        dir.path(),
        material,
        &[
            "KHR_materials_emissive_strength",
            "KHR_materials_specular",
            "KHR_materials_ior",
        ],
    );
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let materials: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    assert_eq!(materials.len(), 1);
    let m = materials[0];
    assert_eq!(m.emissive, Vec3::new(40.0, 20.0, 0.0));
    // F0 = 0.04 (ior 1.5) × 0.5 = 0.02 → level 0.25; glTF's default metallic is 1.
    assert!(
        (m.specular_level - 0.25).abs() < 1e-6,
        "{}",
        m.specular_level
    );
    assert_eq!(m.metallic, 1.0);
}

#[test]
fn transmission_and_volume_map_onto_the_material() {
    let dir = tempfile::tempdir().expect("temp dir");
    let material = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 0.9},
            "KHR_materials_volume": {
                "thicknessFactor": 0.25,
                "attenuationDistance": 2.0,
                "attenuationColor": [0.5, 0.75, 1.0]
            },
            "KHR_materials_ior": {"ior": 1.33},
            "KHR_materials_dispersion": {"dispersion": 0.5}
        }
    });
    let path = write_quad(
        dir.path(),
        material,
        &[
            "KHR_materials_transmission",
            "KHR_materials_volume",
            "KHR_materials_ior",
            "KHR_materials_dispersion",
        ],
    );
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let materials: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    let t = materials[0].transmission.expect("transmissive");
    assert_eq!(t.factor, 0.9);
    assert_eq!(t.ior, 1.33);
    assert_eq!(t.thickness_m, 0.25);
    assert_eq!(t.attenuation_distance_m, 2.0);
    assert_eq!(t.attenuation_color, Vec3::new(0.5, 0.75, 1.0));
    assert_eq!(t.dispersion, 0.5);
    // Without the volume extension: thin-walled, no absorption.
    let thin = json!({"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}});
    let path = write_quad(dir.path(), thin, &["KHR_materials_transmission"]);
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let m: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    assert_eq!(
        m[0].transmission,
        Some(lumen::scene::Transmission::default())
    );
}

/// The first material of a quad written with `extension`'s object `value`, and the
/// loader's warnings.
fn load_extension(
    dir: &Path,
    extension: &str,
    value: serde_json::Value,
) -> (Material, Vec<String>) {
    let material = json!({"extensions": {extension: value}});
    let path = write_quad(dir, material, &[extension]);
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let m: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    (m[0], summary.warnings)
}

/// Asserts that some warning of `warnings` contains `needle`.
fn warned(warnings: &[String], needle: &str) {
    assert!(warnings.iter().any(|w| w.contains(needle)), "{warnings:?}");
}

#[test]
fn clearcoat_maps_onto_the_material_and_warns_of_a_missing_texture() {
    let dir = tempfile::tempdir().expect("temp dir");
    let ext = "KHR_materials_clearcoat";
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({
            "clearcoatFactor": 0.8,
            "clearcoatRoughnessFactor": 0.3,
            "clearcoatNormalTexture": {"index": 0}
        }),
    );
    assert_eq!(
        m.clearcoat,
        Some(lumen::scene::Clearcoat {
            factor: 0.8,
            perceptual_roughness: 0.3
        })
    );
    warned(
        &warnings,
        "KHR_materials_clearcoat's clearcoatNormalTexture: its texture index (0) names no texture",
    );
    // A factor of 0 (the default) is no coat; a factor that is not a number is refused
    // with a warning, and the material still loads.
    let (m, _) = load_extension(dir.path(), ext, json!({"clearcoatRoughnessFactor": 0.5}));
    assert_eq!(m.clearcoat, None);
    let (m, warnings) = load_extension(dir.path(), ext, json!({"clearcoatFactor": "shiny"}));
    assert_eq!(m.clearcoat, None);
    warned(&warnings, "clearcoatFactor is not a number");
}

#[test]
fn iridescence_maps_onto_the_material_and_warns_of_a_missing_texture() {
    let dir = tempfile::tempdir().expect("temp dir");
    let ext = "KHR_materials_iridescence";
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({
            "iridescenceFactor": 0.7,
            "iridescenceThicknessMaximum": 550.0,
            "iridescenceThicknessTexture": {"index": 0}
        }),
    );
    // The index defaults to 1.3; without the texture the thickness is the maximum.
    assert_eq!(
        m.iridescence,
        Some(lumen::scene::Iridescence {
            factor: 0.7,
            ior: 1.3,
            thickness_nm: 550.0
        })
    );
    // This file has no textures: the texture info names none, and the factors apply.
    warned(
        &warnings,
        "KHR_materials_iridescence's iridescenceThicknessTexture: its texture index (0) names no texture",
    );
    // Factor 0 (the default) is no film; an index that is not a number is refused.
    let (m, _) = load_extension(dir.path(), ext, json!({"iridescenceIor": 1.5}));
    assert_eq!(m.iridescence, None);
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({"iridescenceFactor": 1.0, "iridescenceIor": "oil"}),
    );
    assert_eq!(m.iridescence, None);
    warned(&warnings, "iridescenceIor is not a number");
}

#[test]
fn diffuse_transmission_maps_onto_the_material_and_warns_of_a_missing_texture() {
    let dir = tempfile::tempdir().expect("temp dir");
    let ext = "KHR_materials_diffuse_transmission";
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({
            "diffuseTransmissionFactor": 0.6,
            "diffuseTransmissionColorFactor": [0.9, 0.5, 0.2],
            "diffuseTransmissionColorTexture": {"index": 0}
        }),
    );
    let expected = lumen::scene::DiffuseTransmission {
        factor: 0.6,
        color: Vec3::new(0.9, 0.5, 0.2),
    };
    assert_eq!(m.diffuse_transmission, Some(expected));
    warned(
        &warnings,
        "KHR_materials_diffuse_transmission's diffuseTransmissionColorTexture: its texture index (0) names no texture",
    );
    // glTF's default metallic factor is 1: a metal has no diffuse lobe to transmit.
    assert_eq!(m.translucent(), None);
    let dielectric = Material { metallic: 0.0, ..m };
    assert_eq!(dielectric.translucent(), Some(expected));
    // The colour defaults to white; factor 0 (the default) is none; a colour that is not
    // three numbers is refused.
    let (m, _) = load_extension(dir.path(), ext, json!({"diffuseTransmissionFactor": 1.0}));
    assert_eq!(m.diffuse_transmission.map(|d| d.color), Some(Vec3::ONE));
    let (m, _) = load_extension(
        dir.path(),
        ext,
        json!({"diffuseTransmissionColorFactor": [1.0, 0.0, 0.0]}),
    );
    assert_eq!(m.diffuse_transmission, None);
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({"diffuseTransmissionFactor": 1.0, "diffuseTransmissionColorFactor": [1.0, 0.5]}),
    );
    assert_eq!(m.diffuse_transmission, None);
    warned(
        &warnings,
        "diffuseTransmissionColorFactor is not three numbers",
    );
}

#[test]
fn a_tinted_specular_colour_becomes_the_level_and_the_tint() {
    // F0 = 0.04 (IOR 1.5) × factor 1 × colour (1, 0.5, 0.25): level 0.5 (the largest
    // channel) and tint (1, 0.5, 0.25), drawn without a warning.
    let dir = tempfile::tempdir().expect("temp dir");
    let ext = "KHR_materials_specular";
    let colour = json!({"specularColorFactor": [1.0, 0.5, 0.25]});
    let (m, warnings) = load_extension(dir.path(), ext, colour.clone());
    assert!(
        (m.specular_level - 0.5).abs() < 1e-6,
        "{}",
        m.specular_level
    );
    assert_eq!(m.specular_tint, Vec3::new(1.0, 0.5, 0.25));
    // glTF's default metallic factor is 1: this quad is a metal, whose F0 is its base
    // colour, so the tint is not drawn (and needs no warning).
    assert!(m.tint().is_none());
    assert!(warnings.iter().all(|w| !w.contains(ext)), "{warnings:?}");
    // A grey colour is untinted; it scales the level.
    let (m, _) = load_extension(
        dir.path(),
        ext,
        json!({"specularColorFactor": [0.5, 0.5, 0.5]}),
    );
    assert_eq!(m.specular_tint, Vec3::ONE);
    assert!(
        (m.specular_level - 0.25).abs() < 1e-6,
        "{}",
        m.specular_level
    );
    // On a blended or a transmissive material the tint is drawn (by the transparent
    // pass), without a warning; on an unlit one it is not, and a warning says so.
    let blended = json!({
        "alphaMode": "BLEND",
        "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 0.5], "metallicFactor": 0.0},
        "extensions": {ext: colour}
    });
    let transmissive = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {ext: colour, "KHR_materials_transmission": {"transmissionFactor": 1.0}}
    });
    let unlit = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {ext: colour, "KHR_materials_unlit": {}}
    });
    let cases = [
        (blended, vec![ext], false),
        (transmissive, vec![ext, "KHR_materials_transmission"], false),
        (unlit, vec![ext, "KHR_materials_unlit"], true),
    ];
    for (material, used, untinted) in cases {
        let path = write_quad(dir.path(), material, &used);
        let mut app = App::headless().expect("a GPU adapter");
        let summary = load_gltf(&mut app, &path).expect("loads");
        if untinted {
            warned(&summary.warnings, "drawn untinted");
        } else {
            assert!(
                summary.warnings.iter().all(|w| !w.contains("untinted")),
                "{:?}",
                summary.warnings
            );
        }
    }
}

#[test]
fn sheen_maps_onto_the_material_and_warns_of_missing_textures() {
    let dir = tempfile::tempdir().expect("temp dir");
    let ext = "KHR_materials_sheen";
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({
            "sheenColorFactor": [0.5, 0.25, 1.0],
            "sheenRoughnessFactor": 0.7,
            "sheenColorTexture": {"index": 0},
            "sheenRoughnessTexture": {"index": 0}
        }),
    );
    assert_eq!(
        m.sheen,
        Some(lumen::scene::Sheen {
            color: Vec3::new(0.5, 0.25, 1.0),
            perceptual_roughness: 0.7
        })
    );
    for texture in ["sheenColorTexture", "sheenRoughnessTexture"] {
        warned(
            &warnings,
            &format!("KHR_materials_sheen's {texture}: its texture index (0) names no texture"),
        );
    }
    // The default colour (black) is no sheen; a colour of two numbers is refused with a
    // warning, and the material still loads.
    let (m, _) = load_extension(dir.path(), ext, json!({"sheenRoughnessFactor": 0.5}));
    assert_eq!(m.sheen, None);
    let (m, warnings) = load_extension(dir.path(), ext, json!({"sheenColorFactor": [1.0, 1.0]}));
    assert_eq!(m.sheen, None);
    warned(
        &warnings,
        "KHR_materials_sheen's factors are not a colour of three numbers",
    );
}

#[test]
fn anisotropy_maps_onto_the_material_and_warns_of_a_missing_texture() {
    // The file requires the extension: Lumen reads it, so the file loads.
    let dir = tempfile::tempdir().expect("temp dir");
    let ext = "KHR_materials_anisotropy";
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({
            "anisotropyStrength": 0.6,
            "anisotropyRotation": 1.25,
            "anisotropyTexture": {"index": 0}
        }),
    );
    assert_eq!(
        m.anisotropy,
        Some(lumen::scene::Anisotropy {
            strength: 0.6,
            rotation_rad: 1.25
        })
    );
    warned(
        &warnings,
        "KHR_materials_anisotropy's anisotropyTexture: its texture index (0) names no texture",
    );
    // Strength 0 (the default) is isotropic; a rotation that is not a number is refused
    // with a warning, and the material still loads.
    let (m, _) = load_extension(dir.path(), ext, json!({"anisotropyRotation": 0.5}));
    assert_eq!(m.anisotropy, None);
    let (m, warnings) = load_extension(
        dir.path(),
        ext,
        json!({"anisotropyStrength": 0.5, "anisotropyRotation": [1]}),
    );
    assert_eq!(m.anisotropy, None);
    warned(&warnings, "anisotropyRotation is not a number");
}

#[test]
fn khr_materials_unlit_maps_onto_the_material() {
    let dir = tempfile::tempdir().expect("temp dir");
    let material = json!({
        "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
        "extensions": {"KHR_materials_unlit": {}}
    });
    let path = write_quad(dir.path(), material, &["KHR_materials_unlit"]);
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let m: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    assert!(m[0].unlit);
    assert_eq!(m[0].base_color, glam::Vec4::new(0.2, 0.4, 0.6, 1.0));
    // Without the extension the material is lit.
    let path = write_quad(dir.path(), json!({}), &[]);
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let m: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    assert!(!m[0].unlit);
}

#[test]
fn required_extensions_load_when_read_and_are_refused_by_name_otherwise() {
    // KHR_materials_volume is read by Lumen, not by the gltf crate: a file that requires
    // it loads. An extension nobody reads is refused, named.
    let dir = tempfile::tempdir().expect("temp dir");
    let material = json!({"extensions": {
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 0.5}
    }});
    let path = write_quad(
        dir.path(),
        material,
        &["KHR_materials_transmission", "KHR_materials_volume"],
    );
    let require = |path: &Path, names: &[&str]| {
        let mut doc: serde_json::Value =
            serde_json::from_slice(&std::fs::read(path).expect("read")).expect("json");
        doc["extensionsRequired"] = json!(names);
        let out = path.with_file_name("required.gltf");
        std::fs::write(&out, serde_json::to_vec(&doc).expect("json")).expect("write");
        out
    };
    let required = require(
        &path,
        &["KHR_materials_volume", "KHR_materials_transmission"],
    );
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &required).expect("a required extension Lumen reads loads");
    let world = app.world_mut();
    let m: Vec<Material> = world.query::<&Material>().iter(world).copied().collect();
    assert_eq!(m[0].transmission.map(|t| t.thickness_m), Some(0.5));
    let unknown = require(&path, &["EXT_nobody_reads_this"]);
    let mut app = App::headless().expect("a GPU adapter");
    let err = load_gltf(&mut app, &unknown)
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("requires the unsupported extension EXT_nobody_reads_this"),
        "{err}"
    );
}

#[test]
fn generated_tangents_follow_the_texture_directions() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = write_quad(dir.path(), json!({}), &[]);
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let handles: Vec<MeshHandle> = world.query::<&Mesh3d>().iter(world).map(|m| m.0).collect();
    let meshes = world.resource::<lumen::scene::Meshes>();
    let mesh = meshes.get(handles[0]).expect("mesh");
    // The quad's u runs along +x and its v along −y (the image's top is at +y). The
    // tangent follows u; glTF's bitangent, cross(normal, tangent) × w, points up the
    // image, towards decreasing v: +y here.
    for v in &mesh.vertices {
        let t = Vec3::from_slice(&v.tangent[..3]);
        assert!((t - Vec3::X).length() < 1e-4, "{t}");
        let bitangent = Vec3::from(v.normal).cross(t) * v.tangent[3];
        assert!((bitangent - Vec3::Y).length() < 1e-4, "{bitangent}");
    }
}

#[test]
fn bunny_and_suzi_load_and_fill_the_frame() {
    for (name, triangles) in [("bunny.glb", 5648), ("suzi.glb", 14842)] {
        let mut app = App::headless().expect("a GPU adapter");
        let summary = load_gltf(&mut app, &asset(name)).expect("loads");
        assert_eq!(summary.triangles, triangles, "{name}");
        assert!(summary.default_lighting && !summary.has_camera, "{name}");
        let bounds = summary.bounds.expect("bounds");
        assert!(bounds.min.is_finite() && bounds.max.is_finite());
        let size = (128, 128);
        app.render_headless(size).expect("frame");
        let hdr = app.read_hdr_image().expect("readback");
        let world = app.world_mut();
        let background = world
            .query::<&Environment>()
            .iter(world)
            .next()
            .map(|_| lumen::assets::gltf::DEFAULT_SKY_NITS)
            .expect("default sky");
        let ev = lumen::scene::Exposure::Ev100(lumen::assets::gltf::DEFAULT_EV100).multiplier();
        let sky = background * ev;
        // Object pixels differ from the uniform sky behind it.
        let mut count = 0usize;
        let (mut sx, mut sy) = (0.0f64, 0.0f64);
        for (x, y, p) in hdr.enumerate_pixels() {
            assert!(
                p.0.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{name} ({x}, {y})"
            );
            if (common::lum(p) - sky).abs() > 0.02 * sky {
                count += 1;
                sx += f64::from(x);
                sy += f64::from(y);
            }
        }
        let fraction = count as f64 / f64::from(size.0 * size.1);
        let (cx, cy) = (sx / count.max(1) as f64, sy / count.max(1) as f64);
        println!(
            "{name}: {:.1} % of the frame, centroid ({cx:.0}, {cy:.0})",
            100.0 * fraction
        );
        assert!((0.1..0.8).contains(&fraction), "{name}: {fraction}");
        assert!(
            (32.0..96.0).contains(&cx) && (32.0..96.0).contains(&cy),
            "{name}: ({cx}, {cy})"
        );
    }
}

#[test]
fn broken_files_are_one_line_errors_naming_the_file() {
    for (file, needle) in [
        ("not_gltf.gltf", "not a valid glTF file"),
        ("invalid_json.gltf", "not a valid glTF file"),
        ("truncated.glb", "not a valid glTF file"),
        ("missing_bin.gltf", "missing.bin"),
        ("accessor_out_of_range.gltf", "accessor 0 needs 3600 bytes"),
        (
            "view_out_of_range.gltf",
            "buffer view 0 lies outside its buffer",
        ),
        (
            "index_past_vertices.gltf",
            "index 7 points past the 3 vertices",
        ),
        ("nan_position.gltf", "non-finite position"),
        ("inf_position.gltf", "non-finite position"),
        ("does_not_exist.gltf", "does_not_exist.gltf"),
    ] {
        let mut app = App::headless().expect("a GPU adapter");
        let err = load_gltf(&mut app, &data(file))
            .expect_err(file)
            .to_string();
        assert_eq!(err.lines().count(), 1, "{file}: {err}");
        assert!(err.contains(file), "{file}: {err}");
        assert!(err.contains(needle), "{file}: {err}");
    }
    // Zero-area triangles are dropped with a warning; the good one stays.
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, &data("zero_area.gltf")).expect("loads");
    assert_eq!(summary.triangles, 1);
    assert!(summary.warnings.iter().any(|w| w.contains("2 zero-area")));
}

/// Writes an RGBA8 PNG of `w × h` texels given row by row, top first.
fn write_png(path: &Path, w: u32, h: u32, texels: &[[u8; 4]]) {
    let img = image::RgbaImage::from_fn(w, h, |x, y| image::Rgba(texels[(y * w + x) as usize]));
    img.save(path).expect("png");
}

/// Writes `halves.png` into `dir`: a 2 × 1 RGBA PNG, its left texel black, its right
/// texel white.
fn write_halves(dir: &Path) {
    write_png(
        &dir.join("halves.png"),
        2,
        1,
        &[[0, 0, 0, 255], [255, 255, 255, 255]],
    );
}

/// Images, textures and a sampler for `files` (one texture per file, in order).
fn texture_json(files: &[&str], nearest: bool) -> serde_json::Value {
    json!({
        "images": files.iter().map(|f| json!({"uri": f})).collect::<Vec<_>>(),
        "samplers": [if nearest { json!({"magFilter": 9728, "minFilter": 9728}) } else { json!({}) }],
        "textures": (0..files.len()).map(|i| json!({"source": i, "sampler": 0})).collect::<Vec<_>>()
    })
}

/// Loads and renders `path` (64², no energy compensation), with `tweak` applied to the
/// world first, and returns the HDR image.
fn render_image(path: &Path, tweak: impl FnOnce(&mut World)) -> image::Rgba32FImage {
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, path).expect("loads");
    app.world_mut()
        .resource_mut::<Quality>()
        .energy_compensation = false;
    tweak(app.world_mut());
    app.render_headless(SIZE).expect("frame");
    app.read_hdr_image().expect("readback")
}

fn centre(img: &image::Rgba32FImage) -> Vec3 {
    let p = img.get_pixel(SIZE.0 / 2, SIZE.1 / 2).0;
    Vec3::new(p[0], p[1], p[2])
}

#[test]
fn webp_and_basisu_textures_load_or_fall_back() {
    // The same 4 × 4 orange texel as PNG (core source), as WebP (EXT_texture_webp, no
    // core source), and as Basis Universal KTX2 images (KHR_texture_basisu, no core
    // source), ETC1S and Zstandard-supercompressed UASTC (tests/data/ktx2). WebP and
    // UASTC render as the PNG does; ETC1S within its codec's error. A KTX2 image that
    // cannot be transcoded falls back to the core source with a warning, and without one
    // the texture is the magenta checker.
    let dir = tempfile::tempdir().expect("temp dir");
    let texel = [230u8, 120, 30, 255];
    write_png(&dir.path().join("t.png"), 4, 4, &[texel; 16]);
    let rgba = image::RgbaImage::from_pixel(4, 4, image::Rgba(texel));
    let mut webp = Vec::new();
    image::codecs::webp::WebPEncoder::new_lossless(&mut webp)
        .encode(rgba.as_raw(), 4, 4, image::ExtendedColorType::Rgba8)
        .expect("webp");
    std::fs::write(dir.path().join("t.webp"), webp).expect("write webp");
    std::fs::write(dir.path().join("broken.ktx2"), b"\xabKTX 20\xbb\r\n\x1a\n")
        .expect("write ktx2");
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/ktx2");
    for name in ["orange_etc1s.ktx2", "orange_uastc_zstd.ktx2"] {
        std::fs::copy(fixtures.join(name), dir.path().join(name)).expect("copy fixture");
    }
    let material =
        json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}});
    let textures = |images: &[&str], texture: serde_json::Value| {
        json!({
            "images": images.iter().map(|f| json!({"uri": f})).collect::<Vec<_>>(),
            "samplers": [{}],
            "textures": [texture]
        })
    };
    let load = |extra: serde_json::Value, extensions: &[&str]| {
        let path = write_quad_with(
            dir.path(),
            material.clone(),
            extensions,
            extra,
            [0.0, 0.0, 0.0, 1.0],
        );
        let mut app = App::headless().expect("a GPU adapter");
        let summary = load_gltf(&mut app, &path).expect("loads");
        app.render_headless(SIZE).expect("frame");
        (
            centre(&app.read_hdr_image().expect("readback")),
            summary.warnings,
        )
    };
    let (png, w) = load(
        textures(&["t.png"], json!({"source": 0, "sampler": 0})),
        &[],
    );
    assert!(w.is_empty(), "{w:?}");
    let (webp, w) = load(
        textures(
            &["t.webp"],
            json!({"sampler": 0, "extensions": {"EXT_texture_webp": {"source": 0}}}),
        ),
        &["EXT_texture_webp"],
    );
    assert!(w.is_empty(), "{w:?}");
    assert!(relative_error(webp, png) < 1e-3, "webp {webp} vs png {png}");
    let basisu = |image: &str| {
        textures(
            &[image, "t.png"],
            json!({"sampler": 0, "extensions": {"KHR_texture_basisu": {"source": 0}}}),
        )
    };
    // ETC1S stores (229, 121, 31) for this texel: about 1 % in linear light.
    for (image, tolerance) in [
        ("orange_uastc_zstd.ktx2", 1e-3),
        ("orange_etc1s.ktx2", 0.02),
    ] {
        let (ktx2, w) = load(basisu(image), &["KHR_texture_basisu"]);
        assert!(w.is_empty(), "{image}: {w:?}");
        let error = relative_error(ktx2, png);
        println!(
            "{image}: {ktx2} against the PNG's {png}: {:.2} %",
            error * 100.0
        );
        assert!(error < tolerance, "{image}: {ktx2} vs png {png}");
    }
    let (fallback, w) = load(
        textures(
            &["broken.ktx2", "t.png"],
            json!({"source": 1, "sampler": 0, "extensions": {"KHR_texture_basisu": {"source": 0}}}),
        ),
        &["KHR_texture_basisu"],
    );
    assert!(
        relative_error(fallback, png) < 1e-3,
        "fallback {fallback} vs png {png}"
    );
    assert!(
        w.iter()
            .any(|w| w.contains("Basis Universal") && w.contains("fallback image 1")),
        "{w:?}"
    );
    let (checker, w) = load(
        textures(
            &["broken.ktx2"],
            json!({"sampler": 0, "extensions": {"KHR_texture_basisu": {"source": 0}}}),
        ),
        &["KHR_texture_basisu"],
    );
    assert!(
        w.iter()
            .any(|w| w.contains("Basis Universal") && w.contains("magenta")),
        "{w:?}"
    );
    assert!(relative_error(checker, png) > 0.1, "{checker} vs {png}");
}

#[test]
fn a_mid_grey_texel_reads_as_srgb_or_linear_by_slot() {
    let dir = tempfile::tempdir().expect("temp dir");
    write_png(
        &dir.path().join("grey.png"),
        4,
        4,
        &[[128, 128, 128, 255]; 16],
    );
    let textures = texture_json(&["grey.png"], false);
    let srgb = lumen::shading::color::srgb_decode(128.0 / 255.0);
    let linear = 128.0 / 255.0;
    let slot = json!({"index": 0});
    // (slot material, equivalent factor-only material, what to change in the reference)
    let cases = [
        (
            "base colour (sRGB)",
            json!({"pbrMetallicRoughness": {"baseColorTexture": slot, "metallicFactor": 0.0, "roughnessFactor": 0.6}}),
            json!({"pbrMetallicRoughness": {"baseColorFactor": [srgb, srgb, srgb, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}}),
        ),
        (
            "metallic-roughness (linear)",
            json!({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1.0], "metallicRoughnessTexture": slot}}),
            json!({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1.0], "metallicFactor": linear, "roughnessFactor": linear}}),
        ),
        (
            "emissive (sRGB)",
            json!({"emissiveTexture": slot, "emissiveFactor": [1.0, 1.0, 1.0],
                   "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 300.0}},
                   "pbrMetallicRoughness": {"metallicFactor": 0.0}}),
            json!({"emissiveFactor": [srgb, srgb, srgb],
                   "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 300.0}},
                   "pbrMetallicRoughness": {"metallicFactor": 0.0}}),
        ),
    ];
    for (name, textured, reference) in cases {
        let extensions = ["KHR_materials_emissive_strength"];
        let a = centre(&render_image(
            &write_quad_with(
                dir.path(),
                textured,
                &extensions,
                textures.clone(),
                [0.0, 0.0, 0.0, 1.0],
            ),
            |_| {},
        ));
        let b = centre(&render_image(
            &write_quad(dir.path(), reference, &extensions),
            |_| {},
        ));
        let err = relative_error(a, b);
        println!("{name}: textured {a}, factors {b} ({err:.4})");
        assert!(err < 0.01, "{name}: {a} vs {b}");
    }
    // Occlusion (linear) scales only ambient light: under a uniform sky, the texel 128
    // equals a material occlusion of 128/255.
    let sky = |world: &mut World| {
        world.spawn(Environment::uniform(Vec3::splat(2000.0)));
    };
    let occluded = json!({"occlusionTexture": slot, "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.9}});
    let plain = json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.9}});
    let a = centre(&render_image(
        &write_quad_with(
            dir.path(),
            occluded,
            &[],
            textures.clone(),
            [0.0, 0.0, 0.0, 1.0],
        ),
        sky,
    ));
    let b = centre(&render_image(
        &write_quad(dir.path(), plain.clone(), &[]),
        |world| {
            sky(world);
            for mut m in world.query::<&mut Material>().iter_mut(world) {
                m.occlusion = linear;
            }
        },
    ));
    let open = centre(&render_image(&write_quad(dir.path(), plain, &[]), sky));
    let err = relative_error(a, b);
    println!("occlusion (linear): textured {a}, factor {b}, none {open} ({err:.4})");
    assert!(err < 0.01, "occlusion: {a} vs {b}");
    assert!(
        open.x > a.x * 1.1,
        "the occlusion map darkens: {open} vs {a}"
    );
}

#[test]
fn a_normal_map_bump_lit_from_above_is_bright_on_top() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Green > 128 tilts the normal up the image (glTF: +Y up); the top texel of the bump
    // faces up, the bottom one down.
    let up = [128, 218, 180, 255];
    let down = [128, 38, 180, 255];
    write_png(&dir.path().join("bump.png"), 1, 2, &[up, down]);
    write_png(
        &dir.path().join("flat.png"),
        1,
        2,
        &[[128, 128, 255, 255]; 2],
    );
    // The sun comes from above and in front: its direction −Z turned 45° down.
    let from_above = [-0.382_683_4, 0.0, 0.0, 0.923_879_5];
    let halves = |file: &str| {
        let material = json!({"normalTexture": {"index": 0},
                              "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.8}});
        let img = render_image(
            &write_quad_with(
                dir.path(),
                material,
                &[],
                texture_json(&[file], true),
                from_above,
            ),
            |_| {},
        );
        let mean = |rows: std::ops::Range<u32>| {
            let n = rows.len() as f32 * SIZE.0 as f32;
            rows.flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
                .map(|(x, y)| common::lum(img.get_pixel(x, y)))
                .sum::<f32>()
                / n
        };
        (mean(4..28), mean(36..60))
    };
    let (top, bottom) = halves("bump.png");
    let (flat_top, flat_bottom) = halves("flat.png");
    println!("bump: top {top}, bottom {bottom}; flat: {flat_top}, {flat_bottom}");
    assert!(top > 1.5 * bottom, "top {top} bottom {bottom}");
    assert!(
        (flat_top - flat_bottom).abs() < 0.02 * flat_top,
        "{flat_top} {flat_bottom}"
    );
    assert!(top > flat_top && bottom < flat_bottom);
}

#[test]
fn image_problems_fall_back_or_downscale_with_warnings() {
    for (file, needle) in [
        ("missing_image.gltf", "magenta checker"),
        ("corrupt_image.gltf", "magenta checker"),
        ("huge_texture.gltf", "downscaled to 4096×4096"),
    ] {
        let mut app = App::headless().expect("a GPU adapter");
        let summary = load_gltf(&mut app, &data(file)).expect(file);
        assert!(
            summary.warnings.iter().any(|w| w.contains(needle)),
            "{file}: {:?}",
            summary.warnings
        );
        app.render_headless((32, 32)).expect("frame");
        let img = app.read_hdr_image().expect("readback");
        assert!(
            img.pixels().all(|p| p.0.iter().all(|c| c.is_finite())),
            "{file}"
        );
    }
    // The texture budget is a quality knob: 64 texels keeps the huge image tiny.
    let mut app = App::headless().expect("a GPU adapter");
    app.world_mut().resource_mut::<Quality>().max_texture_size = 64;
    let summary = load_gltf(&mut app, &data("huge_texture.gltf")).expect("loads");
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("downscaled to 64×64"))
    );
    // A 1×1 texture is a valid texture: the quad shows its colour (200, 100, 50).
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, &data("tiny_texture.gltf")).expect("loads");
    assert_eq!(summary.textures, 1);
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    app.render_headless((32, 32)).expect("frame");
    let img = app.read_hdr_image().expect("readback");
    let p = img.get_pixel(16, 16).0;
    // Red > green > blue as the texel, whatever the light.
    assert!(p[0] > p[1] && p[1] > p[2] && p[2] > 0.0, "{p:?}");
}

#[test]
fn texture_transforms_and_coordinate_sets_move_the_texture() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Left texel black, right texel white, sampled nearest.
    write_halves(dir.path());
    let textures = texture_json(&["halves.png"], true);
    let right_quarter = |info: serde_json::Value| {
        let material =
            json!({"pbrMetallicRoughness": {"baseColorTexture": info, "metallicFactor": 0.0}});
        let img = render_image(
            &write_quad_with(
                dir.path(),
                material,
                &["KHR_texture_transform"],
                textures.clone(),
                [0.0, 0.0, 0.0, 1.0],
            ),
            |_| {},
        );
        common::lum(img.get_pixel(SIZE.0 * 3 / 4, SIZE.1 / 2))
    };
    let plain = right_quarter(json!({"index": 0}));
    // u' = 0.5 u: the whole quad samples the left (black) texel.
    let scaled = right_quarter(
        json!({"index": 0, "extensions": {"KHR_texture_transform": {"scale": [0.5, 1.0]}}}),
    );
    // u' = u + 0.5 (repeat): the right quarter now samples the left texel too.
    let offset = right_quarter(
        json!({"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.0]}}}),
    );
    // Set 1 does not exist in this mesh: its coordinates are (0, 0), the black texel.
    let set1 = right_quarter(json!({"index": 0, "texCoord": 1}));
    println!("right quarter: plain {plain}, scaled {scaled}, offset {offset}, set 1 {set1}");
    assert!(plain > 0.05, "{plain}");
    // Black keeps only its 4 % specular reflection (1 % of the white texel here).
    for (name, v) in [("scale", scaled), ("offset", offset), ("texCoord 1", set1)] {
        assert!(v < 0.05 * plain, "{name}: {v} vs {plain}");
    }
}

/// A fresh app with `path` loaded, and the loader's summary.
fn loaded(path: &Path) -> (App, GltfSummary) {
    let mut app = App::headless().expect("a GPU adapter");
    let summary = load_gltf(&mut app, path).expect("loads");
    (app, summary)
}

/// The extension textures of the first `MaterialMaps` in `app`'s world.
fn first_extensions(app: &mut App) -> lumen::scene::ExtensionMaps {
    let world = app.world_mut();
    let maps: Vec<MaterialMaps> = world
        .query::<&MaterialMaps>()
        .iter(world)
        .cloned()
        .collect();
    maps[0].extensions
}

#[test]
fn extension_textures_are_read_where_their_texture_infos_point() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Left texel black, right texel white, sampled nearest.
    write_halves(dir.path());
    let textures = texture_json(&["halves.png"], true);
    let ext = "KHR_materials_clearcoat";
    // A black dielectric under a coat whose clearcoatTexture is the halves: coated on the
    // right only; with KHR_texture_transform's offset of 0.5 on the left only.
    let quarters = |info: serde_json::Value| {
        let material = json!({
            "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
            "extensions": {ext: {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.5, "clearcoatTexture": info}}
        });
        let path = write_quad_with(
            dir.path(),
            material,
            &[ext, "KHR_texture_transform"],
            textures.clone(),
            [0.0, 0.0, 0.0, 1.0],
        );
        let mut app = App::headless().expect("a GPU adapter");
        let summary = load_gltf(&mut app, &path).expect("loads");
        assert!(
            summary.warnings.iter().all(|w| !w.contains(ext)),
            "{:?}",
            summary.warnings
        );
        let img = render_image(&path, |_| {});
        (
            common::lum(img.get_pixel(SIZE.0 / 4, SIZE.1 / 2)),
            common::lum(img.get_pixel(SIZE.0 * 3 / 4, SIZE.1 / 2)),
        )
    };
    let (left, right) = quarters(json!({"index": 0}));
    let (shifted_left, shifted_right) = quarters(
        json!({"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.0]}}}),
    );
    println!(
        "coat texture: left {left}, right {right}; offset by 0.5: left {shifted_left}, right {shifted_right}"
    );
    assert!(right > 1.5 * left, "{left} {right}");
    assert!(
        shifted_left > 1.5 * shifted_right,
        "{shifted_left} {shifted_right}"
    );

    // Colour textures load as sRGB, data textures as linear; the film's minimum comes
    // along with its thickness texture.
    let material = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {
            "KHR_materials_sheen": {
                "sheenColorFactor": [1.0, 1.0, 1.0],
                "sheenColorTexture": {"index": 0},
                "sheenRoughnessTexture": {"index": 0, "texCoord": 1}
            },
            "KHR_materials_iridescence": {
                "iridescenceFactor": 1.0,
                "iridescenceThicknessMinimum": 250.0,
                "iridescenceThicknessTexture": {"index": 0}
            }
        }
    });
    let path = write_quad_with(
        dir.path(),
        material,
        &["KHR_materials_sheen", "KHR_materials_iridescence"],
        textures.clone(),
        [0.0, 0.0, 0.0, 1.0],
    );
    let (mut app, summary) = loaded(&path);
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    let e = first_extensions(&mut app);
    let store = app.world().resource::<lumen::scene::Textures>();
    let space = |slot: Option<lumen::scene::TextureSlot>| {
        slot.and_then(|s| store.get(s.texture))
            .map(|t| t.color_space)
    };
    assert_eq!(space(e.sheen_color), Some(ColorSpace::Srgb));
    // Read from alpha, which is linear in an sRGB texture too: the same decoded texture.
    assert_eq!(space(e.sheen_roughness), Some(ColorSpace::Srgb));
    assert_eq!(
        e.sheen_roughness.map(|s| s.texture),
        e.sheen_color.map(|s| s.texture)
    );
    assert_eq!(e.sheen_roughness.map(|s| s.uv_set), Some(1));
    assert_eq!(space(e.iridescence_thickness), Some(ColorSpace::Linear));
    assert_eq!(e.iridescence_thickness_min_nm, 250.0);
    assert_eq!(e.iridescence, None);

    // Five distinct textures for one material: the fifth is dropped with a warning naming
    // it, and its factor applies.
    let mut five = texture_json(&["halves.png"; 5], true);
    five["samplers"] = json!([{"magFilter": 9728, "minFilter": 9728}]);
    let material = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {
            "KHR_materials_clearcoat": {
                "clearcoatFactor": 1.0,
                "clearcoatTexture": {"index": 0},
                "clearcoatRoughnessTexture": {"index": 1}
            },
            "KHR_materials_sheen": {
                "sheenColorFactor": [1.0, 1.0, 1.0],
                "sheenColorTexture": {"index": 2},
                "sheenRoughnessTexture": {"index": 3}
            },
            "KHR_materials_iridescence": {
                "iridescenceFactor": 1.0,
                "iridescenceTexture": {"index": 4}
            }
        }
    });
    let path = write_quad_with(
        dir.path(),
        material,
        &[
            "KHR_materials_clearcoat",
            "KHR_materials_sheen",
            "KHR_materials_iridescence",
        ],
        five,
        [0.0, 0.0, 0.0, 1.0],
    );
    let (mut app, summary) = loaded(&path);
    warned(
        &summary.warnings,
        "more than 4 distinct extension textures; iridescenceTexture not sampled",
    );
    let e = first_extensions(&mut app);
    assert!(e.sheen_roughness.is_some());
    assert_eq!(e.iridescence, None);
}

#[test]
fn extension_textures_fall_back_to_their_factors_where_the_adapter_cannot_bind_them() {
    // OpenGL binds 16 textures per stage: the transparent and layers passes already bind
    // 15, so there the maps' layout has no extension units and the factors apply (the
    // plan says so): the quad equals the same quad without its textures, the coat's
    // normal unbent. Lavapipe binds them. The coat's texture is the black | white halves,
    // its normal map a texel tilting it.
    let dir = tempfile::tempdir().expect("temp dir");
    write_halves(dir.path());
    write_png(&dir.path().join("tilt.png"), 1, 1, &[[150, 128, 250, 255]]);
    let ext = "KHR_materials_clearcoat";
    let quad = |name: &str, textured: bool| {
        let coat = if textured {
            json!({"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.5,
                   "clearcoatTexture": {"index": 0}, "clearcoatNormalTexture": {"index": 1}})
        } else {
            json!({"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.5})
        };
        let material = json!({
            "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0},
            "extensions": {ext: coat}
        });
        let sub = dir.path().join(name);
        std::fs::create_dir_all(&sub).expect("dir");
        for png in ["halves.png", "tilt.png"] {
            std::fs::copy(dir.path().join(png), sub.join(png)).expect("copy");
        }
        write_quad_with(
            &sub,
            material,
            &[ext],
            texture_json(&["halves.png", "tilt.png"], true),
            [0.0, 0.0, 0.0, 1.0],
        )
    };
    let render = |path: &Path, backend: &str| {
        let out = path.with_extension(format!("{backend}.png"));
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_lumen"))
            .args(["render", "--size", "64x64", "--explain", "--out"])
            .arg(&out)
            .arg(path)
            .env("WGPU_BACKEND", backend)
            .output()
            .expect("lumen runs");
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        assert!(output.status.success(), "{backend}: {stderr}");
        let img = image::open(&out).expect("png").to_luma8();
        let at = |x: u32| f32::from(img.get_pixel(x, 32).0[0]);
        ((at(16), at(48)), stderr)
    };
    let (textured, plain) = (quad("textured", true), quad("plain", false));
    let note = "extension textures not sampled";
    let ((left, right), stderr) = render(&textured, "vulkan");
    let ((plain_left, plain_right), _) = render(&plain, "vulkan");
    println!(
        "vulkan: left {left}, right {right}; without the textures {plain_left}, {plain_right}"
    );
    assert!(!stderr.contains(note), "{stderr}");
    assert!(
        (left - plain_left).abs() > 10.0 && (right - plain_right).abs() > 10.0,
        "{left} {right} vs {plain_left} {plain_right}"
    );
    let ((left, right), stderr) = render(&textured, "gl");
    let ((plain_left, plain_right), _) = render(&plain, "gl");
    println!("gl: left {left}, right {right}; without the textures {plain_left}, {plain_right}");
    assert!(stderr.contains(note), "{stderr}");
    assert!(
        (left - plain_left).abs() <= 1.0 && (right - plain_right).abs() <= 1.0,
        "{left} {right} vs {plain_left} {plain_right}"
    );
}

/// The quad's geometry arrays (as `write_quad` writes them) plus a COLOR_0 accessor (3)
/// reading `colors.bin` (buffer 1), for documents that replace `meshes`.
fn geometry_with_colours(dir: &Path, colour: [f32; 4]) -> serde_json::Value {
    let bytes: Vec<u8> = (0..4)
        .flat_map(|_| colour)
        .flat_map(f32::to_le_bytes)
        .collect();
    std::fs::write(dir.join("colors.bin"), &bytes).expect("write colours");
    json!({
        "buffers": [{"byteLength": 92, "uri": "quad.bin"}, {"byteLength": 64, "uri": "colors.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12},
            {"buffer": 1, "byteOffset": 0, "byteLength": 64}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-2.0, -2.0, 0.0], "max": [2.0, 2.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC4"}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "COLOR_0": 3},
                                    "indices": 2, "material": 0}]}]
    })
}

#[test]
fn vertex_colours_alpha_masks_and_double_sided_faces() {
    let dir = tempfile::tempdir().expect("temp dir");
    let identity = [0.0, 0.0, 0.0, 1.0];
    // Vertex colours multiply the base colour: like the same colour as a factor.
    let tint = [1.0, 0.5, 0.25, 1.0];
    let dielectric =
        json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.7}});
    let coloured = centre(&render_image(
        &write_quad_with(
            dir.path(),
            dielectric.clone(),
            &[],
            geometry_with_colours(dir.path(), tint),
            identity,
        ),
        |_| {},
    ));
    let factor = centre(&render_image(
        &write_quad(
            dir.path(),
            json!({"pbrMetallicRoughness": {"baseColorFactor": tint, "metallicFactor": 0.0, "roughnessFactor": 0.7}}),
            &[],
        ),
        |_| {},
    ));
    let err = relative_error(coloured, factor);
    println!("vertex colour {coloured}, factor {factor} ({err:.4})");
    assert!(err < 0.01, "{coloured} vs {factor}");

    // MASK with a textured alpha: the transparent left half is discarded.
    write_png(
        &dir.path().join("mask.png"),
        2,
        1,
        &[[255, 255, 255, 0], [255, 255, 255, 255]],
    );
    let masked = json!({"alphaMode": "MASK", "alphaCutoff": 0.5,
                        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}});
    let img = render_image(
        &write_quad_with(
            dir.path(),
            masked,
            &[],
            texture_json(&["mask.png"], true),
            identity,
        ),
        |_| {},
    );
    let left = common::lum(img.get_pixel(SIZE.0 / 4, SIZE.1 / 2));
    let right = common::lum(img.get_pixel(SIZE.0 * 3 / 4, SIZE.1 / 2));
    println!("mask: left {left}, right {right}");
    assert!(left == 0.0 && right > 0.05, "left {left} right {right}");

    // Turned away from the camera (and the light), the quad shows its back face: culled
    // unless double-sided, and then lit with the normal flipped towards the viewer.
    let turned = json!({"nodes": [
        {"mesh": 0, "rotation": [0.0, 1.0, 0.0, 0.0]},
        {"camera": 0, "translation": [0.0, 0.0, 3.0]},
        {"extensions": {"KHR_lights_punctual": {"light": 0}}}
    ]});
    let back = |double_sided: bool| {
        let material =
            json!({"doubleSided": double_sided, "pbrMetallicRoughness": {"metallicFactor": 0.0}});
        common::lum(&image::Rgba(
            centre(&render_image(
                &write_quad_with(dir.path(), material, &[], turned.clone(), identity),
                |_| {},
            ))
            .extend(1.0)
            .to_array(),
        ))
    };
    let (single, double) = (back(false), back(true));
    println!("back face: single-sided {single}, double-sided {double}");
    assert_eq!(single, 0.0);
    assert!(double > 0.05, "{double}");
}

#[test]
fn blended_materials_are_drawn_with_their_coverage() {
    // alphaMode BLEND: the quad is drawn by the transparent pass over the black
    // background, so each pixel keeps α × the opaque quad's radiance (and coverage α).
    let dir = tempfile::tempdir().expect("temp dir");
    let identity = [0.0, 0.0, 0.0, 1.0];
    let opaque = render_image(
        &write_quad(
            dir.path(),
            json!({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1.0], "metallicFactor": 0.0}}),
            &[],
        ),
        |_| {},
    );
    let quarter = render_image(
        &write_quad(
            dir.path(),
            json!({"alphaMode": "BLEND",
                   "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 0.25], "metallicFactor": 0.0}}),
            &[],
        ),
        |_| {},
    );
    let (o, q) = (
        opaque.get_pixel(SIZE.0 / 2, SIZE.1 / 2).0,
        quarter.get_pixel(SIZE.0 / 2, SIZE.1 / 2).0,
    );
    println!("blend α 0.25: {q:?} against opaque {o:?}");
    for c in 0..3 {
        assert!(
            relative_error(Vec3::splat(q[c]), Vec3::splat(0.25 * o[c])) < 5e-3,
            "{q:?} vs {o:?}"
        );
    }
    assert!((q[3] - 0.25).abs() < 1e-3, "coverage {}", q[3]);
    // A textured alpha: the left texel (α 0) leaves the background, the right one (α 1)
    // the opaque quad.
    write_png(
        &dir.path().join("alpha.png"),
        2,
        1,
        &[[255, 255, 255, 0], [255, 255, 255, 255]],
    );
    let textured = json!({"alphaMode": "BLEND",
                          "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}});
    let img = render_image(
        &write_quad_with(
            dir.path(),
            textured,
            &[],
            texture_json(&["alpha.png"], true),
            identity,
        ),
        |_| {},
    );
    let left = img.get_pixel(SIZE.0 / 4, SIZE.1 / 2).0;
    let right = common::lum(img.get_pixel(SIZE.0 * 3 / 4, SIZE.1 / 2));
    println!("textured alpha: left {left:?}, right {right}");
    assert!(
        left == [0.0; 4] && right > 0.05,
        "left {left:?} right {right}"
    );
}

#[test]
fn flight_helmet_draws_its_lenses_blended() {
    // The CC0 FlightHelmet: its lenses material is alphaMode BLEND with a textured alpha.
    // It loads without a warning, the lenses are the frame's one blended surface, and
    // they change the pixels in front of the goggles.
    let mut app = App::headless().expect("a GPU adapter");
    let summary =
        load_gltf(&mut app, &asset("FlightHelmet/FlightHelmet.gltf")).expect("FlightHelmet loads");
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    // No probe captures: they would take most of the test's time.
    common::indirect_off(&mut app);
    let report = app.render_headless(SIZE).expect("frame");
    let lenses = report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == lumen::render::graph::PassId::Transparent)
        .map(|(_, d)| d.clone())
        .expect("the transparent pass is planned");
    assert!(
        lenses.enabled && lenses.reason.starts_with("1 blended surface"),
        "{}",
        lenses.reason
    );
    let with = app.read_hdr_image().expect("readback");
    let mut blended = app.world_mut().query::<&mut lumen::prelude::Material>();
    for mut m in blended.iter_mut(app.world_mut()) {
        if m.blend {
            m.base_color.w = 0.0;
        }
    }
    app.render_headless(SIZE).expect("frame");
    let without = app.read_hdr_image().expect("readback");
    let changed = with
        .pixels()
        .zip(without.pixels())
        .filter(|(a, b)| (common::lum(a) - common::lum(b)).abs() > 1e-3 * common::lum(b).max(1e-3))
        .count();
    println!("FlightHelmet: the lenses change {changed} pixels");
    assert!(changed > 10, "{changed}");
}

#[test]
fn spec_gloss_textures_convert_texel_by_texel() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Metal/rough: base 0.5 (linear), dielectric, roughness 0.6. Its spec/gloss twin as
    // 8-bit textures: diffuse 0.5 / 0.96 (sRGB), specular 0.04 (sRGB), gloss 0.4 (alpha).
    let enc = |v: f32| (lumen::shading::color::srgb_encode(v) * 255.0).round() as u8;
    let d = enc(0.5 / 0.96);
    let s = enc(0.04);
    let g = (0.4f32 * 255.0).round() as u8;
    write_png(&dir.path().join("diffuse.png"), 2, 2, &[[d, d, d, 255]; 4]);
    write_png(&dir.path().join("specgloss.png"), 2, 2, &[[s, s, s, g]; 4]);
    let material = json!({"extensions": {"KHR_materials_pbrSpecularGlossiness": {
        "diffuseTexture": {"index": 0}, "specularGlossinessTexture": {"index": 1}
    }}});
    let textured = centre(&render_image(
        &write_quad_with(
            dir.path(),
            material,
            &["KHR_materials_pbrSpecularGlossiness"],
            texture_json(&["diffuse.png", "specgloss.png"], false),
            [0.0, 0.0, 0.0, 1.0],
        ),
        |_| {},
    ));
    let twin = centre(&render_image(
        &write_quad(
            dir.path(),
            json!({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                                            "metallicFactor": 0.0, "roughnessFactor": 0.6}}),
            &[],
        ),
        |_| {},
    ));
    let err = relative_error(textured, twin);
    println!("spec/gloss textures {textured}, metal/rough {twin} ({err:.4})");
    // 8-bit texels on both sides of the conversion.
    assert!(err < 0.03, "{textured} vs {twin}");
}

#[test]
fn a_files_tangents_keep_their_handedness() {
    let dir = tempfile::tempdir().expect("temp dir");
    // The same quad with TANGENT (1, 0, 0, −1): MikkTSpace would give w = +1 here.
    let mut extra = geometry_with_colours(dir.path(), [1.0; 4]);
    let tangents: Vec<u8> = (0..4)
        .flat_map(|_| [1.0f32, 0.0, 0.0, -1.0])
        .flat_map(f32::to_le_bytes)
        .collect();
    std::fs::write(dir.path().join("colors.bin"), &tangents).expect("write tangents");
    extra["meshes"] = json!([{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TANGENT": 3},
                                             "indices": 2, "material": 0}]}]);
    let path = write_quad_with(dir.path(), json!({}), &[], extra, [0.0, 0.0, 0.0, 1.0]);
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, &path).expect("loads");
    let world = app.world_mut();
    let handles: Vec<MeshHandle> = world.query::<&Mesh3d>().iter(world).map(|m| m.0).collect();
    let meshes = world.resource::<lumen::scene::Meshes>();
    for v in &meshes.get(handles[0]).expect("mesh").vertices {
        assert_eq!(v.tangent, [1.0, 0.0, 0.0, -1.0]);
    }
}

/// A point light above a 1.2 m occluder over a floor, seen from the side under the
/// occluder; returns the centre pixel's luminance (the floor right below the occluder).
fn occluded_floor(light_shadows: bool) -> f32 {
    let dir = tempfile::tempdir().expect("temp dir");
    let quad = |y: f32, half: f32| -> Vec<u8> {
        [
            [-half, y, -half],
            [half, y, -half],
            [half, y, half],
            [-half, y, half],
        ]
        .iter()
        .flatten()
        .flat_map(|v: &f32| v.to_le_bytes())
        .collect()
    };
    let mut bin = quad(0.0, 3.0);
    bin.extend(quad(1.0, 0.6));
    bin.extend([0u16, 2, 1, 0, 3, 2].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.path().join("room.bin"), &bin).expect("bin");
    // The camera looks down 13.5° from (0, 0.6, 2.5) at the origin.
    let half_angle = (0.6f32 / 2.5).atan() * -0.5;
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "intensity": 100.0, "color": [1.0, 1.0, 1.0]}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0},
            {"mesh": 1},
            {"translation": [0.0, 2.0, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"camera": 0, "translation": [0.0, 0.6, 2.5],
             "rotation": [half_angle.sin(), 0.0, 0.0, half_angle.cos()]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.05, "zfar": 50.0}}],
        "materials": [{"doubleSided": true, "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0}, "indices": 2, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 1}, "indices": 2, "material": 0}]}
        ],
        "buffers": [{"byteLength": bin.len(), "uri": "room.bin"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-3.0, 0.0, -3.0], "max": [3.0, 0.0, 3.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-0.6, 1.0, -0.6], "max": [0.6, 1.0, 0.6]},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.path().join("room.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).expect("json")).expect("gltf");
    let mut app = App::headless().expect("a GPU adapter");
    let options = lumen::assets::gltf::GltfOptions {
        light_shadows,
        ..Default::default()
    };
    let summary = lumen::assets::gltf::load_gltf_with(&mut app, &path, &options).expect("loads");
    assert_eq!((summary.lights, summary.has_camera), (1, true));
    // Direct light only: the floor under the occluder also gets light bounced off the lit
    // floor and the occluder's underside (double-sided), which is not what is tested here.
    common::indirect_off(&mut app);
    app.render_headless((64, 64)).expect("frame");
    let img = app.read_hdr_image().expect("hdr");
    common::lum(img.get_pixel(32, 32))
}

#[test]
fn lights_from_files_cast_shadows_unless_turned_off() {
    let shadowed = occluded_floor(true);
    let unshadowed = occluded_floor(false);
    assert!(
        unshadowed > 0.0,
        "the floor is not lit at all: {unshadowed}"
    );
    assert!(
        shadowed < 0.01 * unshadowed,
        "the occluder casts no shadow: {shadowed} against {unshadowed} without shadows"
    );
}

#[test]
fn the_showcase_holds_the_helmet_centred_lit_and_well_exposed() {
    // The main job's scene at 160×90: the HDR image is finite, the display image is
    // neither black nor clipped, and the helmet (found as the pixels whose depth changes
    // when it is taken away) is in the middle of the frame, large, and lit.
    let size = (160u32, 90u32);
    let mut app = App::headless().expect("a GPU adapter");
    let showcase = lumen_game::scenes::find("showcase").expect("the showcase scene");
    (showcase.build)(&mut app).expect("the showcase builds");
    app.keep_target(FrameTarget::Depth);
    app.render_headless(size).expect("frame");
    let hdr = app.read_hdr_image().expect("hdr");
    assert!(
        hdr.pixels().all(|p| p.0.iter().all(|c| c.is_finite())),
        "a non-finite HDR pixel"
    );
    let display = app.read_display_image().expect("display");
    let luma = |p: &image::Rgba<u8>| {
        (0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2])) / 255.0
    };
    let n = (size.0 * size.1) as f32;
    let mean = display.pixels().map(luma).sum::<f32>() / n;
    let clipped = display.pixels().filter(|p| p.0[..3].contains(&255)).count() as f32 / n;
    println!(
        "showcase: mean display luma {mean:.3}, clipped {:.2} %",
        clipped * 100.0
    );
    assert!((0.2..0.8).contains(&mean), "mean display luma {mean}");
    assert!(
        clipped < 0.02,
        "{:.1} % of the pixels clipped",
        clipped * 100.0
    );

    let with = app.read_target(FrameTarget::Depth).expect("depth");
    let model: Vec<Entity> = app
        .world_mut()
        .query_filtered::<Entity, With<lumen_game::scenes::showcase::ShowcaseModel>>()
        .iter(app.world())
        .collect();
    assert!(!model.is_empty(), "the helmet's entities are marked");
    for e in model {
        app.world_mut().despawn(e);
    }
    common::indirect_off(&mut app);
    app.render_headless(size).expect("frame");
    let without = app.read_target(FrameTarget::Depth).expect("depth");
    let helmet: Vec<(u32, u32)> = with
        .enumerate_pixels()
        .filter(|(x, y, p)| (p.0[0] - without.get_pixel(*x, *y).0[0]).abs() > 1e-6)
        .map(|(x, y, _)| (x, y))
        .collect();
    let share = helmet.len() as f32 / n;
    let cx = helmet.iter().map(|p| p.0 as f32).sum::<f32>() / helmet.len().max(1) as f32;
    let cy = helmet.iter().map(|p| p.1 as f32).sum::<f32>() / helmet.len().max(1) as f32;
    let lit = helmet
        .iter()
        .map(|&(x, y)| luma(display.get_pixel(x, y)))
        .sum::<f32>()
        / helmet.len().max(1) as f32;
    println!(
        "showcase: helmet covers {:.1} % of the frame, centroid ({cx:.0}, {cy:.0}), mean luma {lit:.3}",
        share * 100.0
    );
    assert!((0.05..0.5).contains(&share), "helmet share {share}");
    assert!(
        (cx - 80.0).abs() < 16.0 && (cy - 45.0).abs() < 18.0,
        "helmet centroid ({cx}, {cy}) in a 160×90 frame"
    );
    // Lit from the front: 0.17 here; the sun behind it (the image unturned) gave 0.10.
    assert!((0.13..0.8).contains(&lit), "helmet mean luma {lit}");
}

/// A glTF of five nodes animated by one clip: node 0 (a 1 m quad) translation LINEAR, node 1
/// the same keys STEP, node 2 translation CUBICSPLINE, node 3 rotation LINEAR from the
/// identity to a negated quaternion (the same rotation as +1 rad about Y, on the far
/// hemisphere), node 4 scale LINEAR from (1, 1, 1) to (3, 1, 0.5) over 1 s.
fn write_animated(dir: &Path) -> PathBuf {
    let floats: Vec<f32> = [
        vec![0.0, 1.0, 3.0],
        vec![0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 4.0, 0.0],
        vec![0.0, 2.0],
        // in-tangent, value, out-tangent per key (units per second).
        vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        vec![2.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        vec![0.0, 1.0],
        {
            let q = -Quat::from_rotation_y(1.0);
            vec![0.0, 0.0, 0.0, 1.0, q.x, q.y, q.z, q.w]
        },
        // Node 0's mesh: a 1 m quad in the XY plane, facing +Z.
        vec![
            -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0,
        ],
    ]
    .concat();
    let mut bin: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    // Node 4's scale keys, after the indices (byte 228).
    bin.extend(
        [1.0f32, 1.0, 1.0, 3.0, 1.0, 0.5]
            .iter()
            .flat_map(|f| f.to_le_bytes()),
    );
    std::fs::write(dir.join("animated.bin"), &bin).expect("bin");
    // (offset in floats, count, type) of each accessor.
    let parts = [
        (0, 3, "SCALAR"),
        (3, 3, "VEC3"),
        (12, 2, "SCALAR"),
        (14, 6, "VEC3"),
        (32, 2, "SCALAR"),
        (34, 2, "VEC4"),
        (42, 4, "VEC3"),
    ];
    let width = |t: &str| match t {
        "SCALAR" => 1,
        "VEC3" => 3,
        _ => 4,
    };
    let mut views: Vec<_> = parts
        .iter()
        .map(|(o, n, t)| json!({"buffer": 0, "byteOffset": o * 4, "byteLength": n * width(t) * 4}))
        .collect();
    views.push(json!({"buffer": 0, "byteOffset": 54 * 4, "byteLength": 12}));
    views.push(json!({"buffer": 0, "byteOffset": 54 * 4 + 12, "byteLength": 24}));
    let accessors: Vec<_> = parts
        .iter()
        .enumerate()
        .map(|(i, (_, n, t))| {
            let mut a = json!({"bufferView": i, "componentType": 5126, "count": n, "type": t});
            if i == 0 || i == 2 || i == 4 {
                a["min"] = json!([0.0]);
                a["max"] = json!([if i == 0 {
                    3.0
                } else if i == 2 {
                    2.0
                } else {
                    1.0
                }]);
            }
            if i == 6 {
                a["min"] = json!([-0.5, -0.5, 0.0]);
                a["max"] = json!([0.5, 0.5, 0.0]);
            }
            a
        })
        .chain([
            json!({"bufferView": 7, "componentType": 5123, "count": 6, "type": "SCALAR"}),
            json!({"bufferView": 8, "componentType": 5126, "count": 2, "type": "VEC3"}),
        ])
        .collect();
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
        "nodes": [{"mesh": 0}, {}, {}, {}, {}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 6}, "indices": 7}]}],
        "animations": [{
            "name": "move",
            "samplers": [
                {"input": 0, "output": 1, "interpolation": "LINEAR"},
                {"input": 0, "output": 1, "interpolation": "STEP"},
                {"input": 2, "output": 3, "interpolation": "CUBICSPLINE"},
                {"input": 4, "output": 5, "interpolation": "LINEAR"},
                {"input": 4, "output": 8, "interpolation": "LINEAR"}
            ],
            "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "translation"}},
                {"sampler": 1, "target": {"node": 1, "path": "translation"}},
                {"sampler": 2, "target": {"node": 2, "path": "translation"}},
                {"sampler": 3, "target": {"node": 3, "path": "rotation"}},
                {"sampler": 4, "target": {"node": 4, "path": "scale"}}
            ]
        }],
        "buffers": [{"byteLength": bin.len(), "uri": "animated.bin"}],
        "bufferViews": views,
        "accessors": accessors
    });
    let path = dir.join("animated.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).expect("json")).expect("gltf");
    path
}

/// The four animated nodes' transforms after posing the clip at `t` seconds.
fn posed(app: &mut App, t: f32) -> Vec<Transform> {
    let world = app.world_mut();
    let mut players = world.query::<&mut AnimationPlayer>();
    let mut player = players.single_mut(world).expect("one player");
    player.seek(t);
    world.run_schedule(lumen::PostUpdate);
    animated_nodes(world)
}

/// The transforms of the nodes the clip's channels drive, channel i's target first.
fn animated_nodes(world: &mut World) -> Vec<Transform> {
    let player = world
        .query::<&AnimationPlayer>()
        .single(world)
        .expect("one player");
    let targets: Vec<Entity> = player.clips()[0]
        .channels
        .iter()
        .map(|c| c.target)
        .collect();
    targets
        .iter()
        .map(|e| *world.get::<Transform>(*e).expect("an animated node"))
        .collect()
}

#[test]
fn gltf_animation_samples_step_linear_and_cubic_spline_as_the_spec_says() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = App::new();
    let summary = load_gltf(&mut app, &write_animated(dir.path())).expect("loads");
    assert_eq!(summary.animations, vec![("move".to_string(), 3.0)]);
    let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
    // Keys at 0, 1 and 3 s: (0,0,0), (2,0,0), (2,4,0).
    for (t, linear, step) in [
        (0.0, Vec3::ZERO, Vec3::ZERO),
        (0.25, Vec3::new(0.5, 0.0, 0.0), Vec3::ZERO),
        (0.999, Vec3::new(1.998, 0.0, 0.0), Vec3::ZERO),
        (1.0, Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0)),
        (2.0, Vec3::new(2.0, 2.0, 0.0), Vec3::new(2.0, 0.0, 0.0)),
        (2.5, Vec3::new(2.0, 3.0, 0.0), Vec3::new(2.0, 0.0, 0.0)),
    ] {
        let n = posed(&mut app, t);
        assert!(
            close(n[0].translation, linear),
            "LINEAR at {t}: {}",
            n[0].translation
        );
        assert!(
            close(n[1].translation, step),
            "STEP at {t}: {}",
            n[1].translation
        );
    }
    // CUBICSPLINE, keys 0 and 2 s (Δt = 2): v0 = 0, out-tangent b0 = (1,0,0); in-tangent
    // a1 = (2,0,0), v1 = (4,0,0). At s = t/2 the Hermite form gives
    // x = Δt(s³ − 2s² + s)·1 + (−2s³ + 3s²)·4 + Δt(s³ − s²)·2:
    // s = 0.5: 0.25 + 2 − 0.5 = 1.75; s = 0.25: 0.28125 + 0.625 − 0.1875 = 0.71875.
    for (t, x) in [(0.0, 0.0), (0.5, 0.71875), (1.0, 1.75), (2.0, 4.0)] {
        let n = posed(&mut app, t);
        assert!(
            close(n[2].translation, Vec3::new(x, 0.0, 0.0)),
            "CUBICSPLINE at {t}: {}",
            n[2].translation
        );
    }
    // Rotation: halfway between the identity and −(1 rad about Y) is 0.5 rad about Y (the
    // short arc); the long arc would give π − 0.5 rad about −Y.
    let n = posed(&mut app, 0.5);
    let angle = n[3].rotation.angle_between(Quat::from_rotation_y(0.5));
    assert!(
        angle < 1e-4,
        "rotation at 0.5 s is {angle} rad from 0.5 rad about Y"
    );
    let n = posed(&mut app, 0.75);
    assert!(n[3].rotation.angle_between(Quat::from_rotation_y(0.75)) < 1e-4);
    // Scale, LINEAR per component: a quarter of the way at 0.25 s, held after the last
    // key.
    assert!(
        close(n[4].scale, Vec3::new(2.5, 1.0, 0.625)),
        "{}",
        n[4].scale
    );
    let n = posed(&mut app, 0.25);
    assert!(
        close(n[4].scale, Vec3::new(1.5, 1.0, 0.875)),
        "{}",
        n[4].scale
    );
    let n = posed(&mut app, 2.0);
    assert!(
        close(n[4].scale, Vec3::new(3.0, 1.0, 0.5)),
        "{}",
        n[4].scale
    );
}

#[test]
fn a_playing_clip_advances_with_time_and_pauses_and_loops() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = App::new();
    app.set_fixed_delta(Some(0.25));
    load_gltf(&mut app, &write_animated(dir.path())).expect("loads");
    let mut xs = Vec::new();
    for _ in 0..3 {
        app.update();
        app.world_mut().run_schedule(lumen::PostUpdate);
        xs.push(animated_nodes(app.world_mut())[0].translation.x);
    }
    // A frame shows the clip's time, then time moves on by 0.25 s: 0, 0.25, 0.5 s.
    assert_eq!(xs, vec![0.0, 0.5, 1.0]);
    let world = app.world_mut();
    let mut players = world.query::<&mut AnimationPlayer>();
    let mut player = players.single_mut(world).expect("player");
    assert_eq!(player.time_s(), 0.75);
    player.pause();
    player.seek(3.5);
    assert_eq!(
        player.time_s(),
        0.5,
        "looping wraps 3.5 s into the 3 s clip"
    );
    app.update();
    app.world_mut().run_schedule(lumen::PostUpdate);
    let world = app.world_mut();
    let player = world
        .query::<&AnimationPlayer>()
        .single(world)
        .expect("player");
    assert_eq!(player.time_s(), 0.5, "paused");
}

#[test]
fn the_fox_brings_its_three_clips_and_walk_moves_its_joints() {
    // Fox.glb (CC BY 4.0, see assets/README.md): one skinned mesh, three clips.
    let mut app = App::new();
    let summary = load_gltf(&mut app, &asset("Fox.glb")).expect("the fox loads");
    let names: Vec<&str> = summary.animations.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["Survey", "Walk", "Run"]);
    assert!(
        summary
            .animations
            .iter()
            .all(|(_, d)| *d > 0.5 && d.is_finite())
    );
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    let joints = |app: &mut App| -> Vec<Transform> {
        let world = app.world_mut();
        let mut q = world.query_filtered::<(Entity, &Transform), With<ChildOf>>();
        let mut v: Vec<_> = q.iter(world).map(|(e, t)| (e, *t)).collect();
        v.sort_by_key(|(e, _)| *e);
        v.into_iter().map(|(_, t)| t).collect()
    };
    let rest = joints(&mut app);
    let world = app.world_mut();
    let mut players = world.query::<&mut AnimationPlayer>();
    let mut player = players.single_mut(world).expect("player");
    player.play_named("Walk").expect("Walk");
    player.seek(0.5);
    app.world_mut().run_schedule(lumen::PostUpdate);
    let walked = joints(&mut app);
    let moved = rest
        .iter()
        .zip(&walked)
        .filter(|(a, b)| a.rotation.angle_between(b.rotation) > 0.01)
        .count();
    println!(
        "Fox: {:?}; Walk at 0.5 s turns {moved} of {} nodes",
        summary.animations,
        rest.len()
    );
    assert!(moved >= 5, "{moved}");
}

#[test]
fn the_time_option_poses_an_animated_file_and_holds_it() {
    use clap::Parser;
    let dir = tempfile::tempdir().expect("temp dir");
    let path = write_animated(dir.path());
    let file = path.to_str().expect("utf-8 path");
    let parse = |time: &str| {
        lumen_game::cli::Cli::try_parse_from(["lumen", "render", file, "--time", time])
    };
    assert!(parse("-1").is_err() && parse("inf").is_err());
    let Some(lumen_game::cli::Command::Render(args)) = parse("2").expect("parses").command else {
        panic!("a render command");
    };
    let mut app = App::new();
    lumen_game::setup::build_scene(&mut app, &args.scene).expect("the scene builds");
    // Node 0 at 2 s: halfway from (2,0,0) to (2,4,0), held over frames.
    for _ in 0..3 {
        app.update();
        app.world_mut().run_schedule(lumen::PostUpdate);
        let node0 = animated_nodes(app.world_mut())[0].translation;
        assert!(
            (node0 - Vec3::new(2.0, 2.0, 0.0)).length() < 1e-5,
            "{node0}"
        );
    }
}

#[test]
fn a_sequence_holds_the_frames_of_single_renders_at_their_times() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = write_animated(dir.path());
    let lumen = |args: &[&str]| {
        let mut all = vec![
            "render",
            file.to_str().expect("utf-8 path"),
            "--size",
            "48x32",
        ];
        all.extend_from_slice(args);
        common::run_lumen(dir.path(), &all);
    };
    lumen(&[
        "--frames",
        "0..3",
        "--fps",
        "30",
        "--out",
        "seq/frame-####.png",
    ]);
    lumen(&["--time", "0.1", "--out", "at.png"]);
    let read = |name: &str| {
        image::open(dir.path().join(name))
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .to_rgba8()
    };
    let frames: Vec<_> = (0..4)
        .map(|k| read(&format!("seq/frame-{k:04}.png")))
        .collect();
    assert!(
        !dir.path().join("seq/frame-0004.png").exists(),
        "four frames, no more"
    );
    // Frame 3 at 30 fps is 0.1 s: the same image as a render at --time 0.1.
    assert!(
        frames[3] == read("at.png"),
        "frame 3 differs from --time 0.1"
    );
    // The quad moves 0.2 m in 0.1 s: the frames differ.
    assert!(frames[0] != frames[3], "the sequence is animated");
}

/// The quad of [`write_quad`] with its three buffer views compressed by
/// `EXT_meshopt_compression` into `packed.bin`, their own buffer a placeholder without
/// data (`fallback`), the extension required. `corrupt` breaks the index stream's header.
fn write_meshopt_quad(dir: &Path, corrupt: bool) -> PathBuf {
    let bin = common::quad_buffer(2.0);
    let (packed, views) = common::meshopt_quad(&bin, corrupt);
    std::fs::write(dir.join("packed.bin"), &packed).expect("write packed");
    write_quad_with(
        dir,
        json!({}),
        &["EXT_meshopt_compression"],
        json!({
            "extensionsRequired": ["EXT_meshopt_compression"],
            "buffers": [
                {"byteLength": packed.len(), "uri": "packed.bin"},
                {"byteLength": bin.len(), "extensions": {"EXT_meshopt_compression": {"fallback": true}}}
            ],
            "bufferViews": views
        }),
        [0.0, 0.0, 0.0, 1.0],
    )
}

/// The vertices and indices of the one mesh `path` loads.
fn loaded_mesh(path: &Path) -> lumen::scene::MeshData {
    let mut app = App::headless().expect("a GPU adapter");
    load_gltf(&mut app, path).expect("loads");
    let world = app.world_mut();
    let handles: Vec<MeshHandle> = world.query::<&Mesh3d>().iter(world).map(|m| m.0).collect();
    let meshes = world.resource::<lumen::scene::Meshes>();
    meshes.get(handles[0]).expect("mesh").as_ref().clone()
}

#[test]
fn meshopt_compressed_views_decode_into_their_buffer() {
    // EXT_meshopt_compression: positions and texture coordinates by the attribute codec,
    // indices by the triangle codec, decoded into a placeholder buffer without data. The
    // mesh is the uncompressed quad's, vertex for vertex (the codecs are lossless; their
    // decoding of meshoptimizer's own streams is unit-tested in assets::meshopt).
    let dir = tempfile::tempdir().expect("temp dir");
    let plain = loaded_mesh(&write_quad(dir.path(), json!({}), &[]));
    let packed_dir = tempfile::tempdir().expect("temp dir");
    let packed = loaded_mesh(&write_meshopt_quad(packed_dir.path(), false));
    assert_eq!(packed.indices, plain.indices);
    assert_eq!(packed.vertices, plain.vertices);
    // A broken stream is an error naming the view and the extension, not a panic.
    let broken_dir = tempfile::tempdir().expect("temp dir");
    let path = write_meshopt_quad(broken_dir.path(), true);
    let mut app = App::headless().expect("a GPU adapter");
    let err = load_gltf(&mut app, &path).expect_err("broken").to_string();
    assert!(
        err.contains("buffer view 2: EXT_meshopt_compression: not a triangle stream"),
        "{err}"
    );
}

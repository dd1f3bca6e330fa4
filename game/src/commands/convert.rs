//! `lumen convert`: metal/roughness ↔ specular/glossiness on texture files and glTF
//! materials, glossiness ↔ roughness, the safe-colour fix, and IOR or specular level →
//! F0. Colours are converted in linear space (sRGB decoded exactly on the way in and
//! encoded on the way out); data maps are linear.

use crate::cli::{ConvertArgs, ConvertTarget};
use crate::materials::{NamedMaterial, file_stem, gltf_materials, read_texture};
use anyhow::{Context, Result, anyhow};
use glam::Vec3;
use lumen::scene::ColorSpace;
use lumen::shading::color::{srgb_decode, srgb_encode};
use lumen::validate::{MaterialInput, Texel, safe_base_color, safe_diffuse};
use lumen::workflow::{MetalRough, SpecGloss, to_metal_rough, to_spec_gloss};
use std::path::{Path, PathBuf};

/// The 8-bit sRGB code of a linear value.
pub fn srgb_code(v: f32) -> u8 {
    (srgb_encode(v) * 255.0).round() as u8
}

/// The 8-bit code of a linear data value.
pub fn linear_code(v: f32) -> u8 {
    (if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) } * 255.0).round() as u8
}

fn color_codes(c: Vec3) -> [u8; 3] {
    [srgb_code(c.x), srgb_code(c.y), srgb_code(c.z)]
}

fn decode_codes(c: [u8; 3]) -> Vec3 {
    Vec3::new(
        srgb_decode(f32::from(c[0]) / 255.0),
        srgb_decode(f32::from(c[1]) / 255.0),
        srgb_decode(f32::from(c[2]) / 255.0),
    )
}

/// Runs the command; prints what it wrote.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let mut printed = false;
    if let Some(ior) = args.ior {
        let f0 = lumen::shading::brdf::f0_from_ior(ior);
        crate::output::print(&format!("IOR {ior} → F0 {f0:.4}\n"));
        printed = true;
    }
    if let Some(level) = args.specular_level {
        let f0 = lumen::shading::brdf::dielectric_f0(level);
        crate::output::print(&format!("specular level {level} → F0 {f0:.4}\n"));
        printed = true;
    }
    let has_maps = args.file.is_some() || args.textures.any();
    if !has_maps {
        return if printed {
            Ok(())
        } else {
            Err(anyhow!(
                "nothing to convert: give a glTF file, texture files by role, --ior or --specular-level"
            ))
        };
    }
    if args.to.is_none() && !args.safe_color {
        return Err(anyhow!(
            "say what to write: --to TARGET and/or --safe-color"
        ));
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/converted"));
    match args.to {
        Some(ConvertTarget::Roughness) | Some(ConvertTarget::Glossiness) => {
            return invert_map(args, &out);
        }
        _ => {}
    }
    let materials: Vec<(NamedMaterial, PathBuf)> = match &args.file {
        Some(file) => gltf_materials(file)?
            .into_iter()
            .enumerate()
            .map(|(k, m)| {
                let dir = out.join(format!("{k}-{}", file_stem(&m.name)));
                (m, dir)
            })
            .collect(),
        None => vec![(args.textures.material()?, out.clone())],
    };
    for (m, dir) in &materials {
        let spec_gloss_in = matches!(m.input, MaterialInput::SpecGloss { .. });
        let already = args.to
            == Some(if spec_gloss_in {
                ConvertTarget::SpecGloss
            } else {
                ConvertTarget::MetalRough
            });
        // A material in the target workflow already: a safe-colour pass alone; skipped in
        // a glTF file; an error for texture files.
        let to = match (already, args.safe_color, args.file.is_some()) {
            (false, _, _) => args.to,
            (true, true, _) => None,
            (true, false, true) => {
                crate::output::print(&format!(
                    "{} · {}: in that workflow already; skipped\n",
                    m.source.display(),
                    m.name
                ));
                continue;
            }
            (true, false, false) => {
                return Err(anyhow!(
                    "{}: {} is {} already",
                    m.source.display(),
                    m.name,
                    if spec_gloss_in {
                        "spec/gloss"
                    } else {
                        "metal/rough"
                    }
                ));
            }
        };
        let text = convert(m, dir, to, args.safe_color, args.strict)?;
        crate::output::print(&text);
    }
    Ok(())
}

/// Glossiness ↔ roughness: `1 − v` texel by texel, exactly.
fn invert_map(args: &ConvertArgs, out: &Path) -> Result<()> {
    let (input, name) = match args.to {
        Some(ConvertTarget::Roughness) => (&args.textures.glossiness, "roughness.png"),
        _ => (&args.textures.roughness, "glossiness.png"),
    };
    let input = input.as_ref().ok_or_else(|| {
        anyhow!("--to roughness needs --glossiness FILE, --to glossiness needs --roughness FILE")
    })?;
    let t = read_texture(input, ColorSpace::Linear)?;
    let image = image::GrayImage::from_fn(t.width, t.height, |x, y| {
        image::Luma([255 - t.rgba8[((y * t.width + x) * 4) as usize]])
    });
    let path = out.join(name);
    save(&path, &image)?;
    crate::output::print(&format!("wrote {}\n", path.display()));
    Ok(())
}

fn save<P: image::PixelWithColorType>(
    path: &Path,
    image: &image::ImageBuffer<P, Vec<P::Subpixel>>,
) -> Result<()>
where
    [P::Subpixel]: image::EncodableLayout,
{
    lumen::assets::image_io::save(path, image, image::ImageFormat::Png)
        .with_context(|| format!("writing {}", path.display()))
}

/// What one texel becomes, as the 8-bit values written.
struct Written {
    colors: [[u8; 3]; 2],
    scalars: [u8; 2],
}

/// Converts one material into `dir` (to the other workflow, or with `to` = `None` only
/// the safe-colour fix); returns the report lines.
fn convert(
    m: &NamedMaterial,
    dir: &Path,
    to: Option<ConvertTarget>,
    safe_color: bool,
    strict: bool,
) -> Result<String> {
    let (w, h) = m.input.size();
    // `to` is metal-rough, spec-gloss (the other workflow) or none (safe colour only).
    let target_spec_gloss = match to {
        Some(t) => t == ConvertTarget::SpecGloss,
        None => matches!(m.input, MaterialInput::SpecGloss { .. }),
    };
    let names = if target_spec_gloss {
        ["diffuse.png", "specular.png", "glossiness.png", "unused"]
    } else {
        ["base_color.png", "metallic.png", "roughness.png", "unused"]
    };
    let bar = crate::progress::bar(u64::from(h), "converting", "rows");
    // Per texel: what is written, whether the safe colour changed it, whether it is lost
    // in a round trip.
    let rows: Vec<Vec<(Written, bool, bool)>> = {
        use rayon::prelude::*;
        (0..h)
            .into_par_iter()
            .map(|y| {
                let row = (0..w)
                    .map(|x| {
                        let original = m.input.texel(x, y, (w, h));
                        let texel = if safe_color {
                            safe_texel(original, strict)
                        } else {
                            original
                        };
                        let written = write_texel(texel, target_spec_gloss);
                        let lost = to.is_some() && !round_trips(texel, &written, target_spec_gloss);
                        (written, texel != original, lost)
                    })
                    .collect();
                bar.inc(1);
                row
            })
            .collect()
    };
    bar.finish_and_clear();
    let mut color_a = image::RgbImage::new(w, h);
    let mut color_b = image::RgbImage::new(w, h);
    let mut scalar_a = image::GrayImage::new(w, h);
    let mut scalar_b = image::GrayImage::new(w, h);
    let mut not_invertible = image::GrayImage::new(w, h);
    let (mut fixed, mut lossy) = (0u64, 0u64);
    for (y, row) in (0u32..).zip(&rows) {
        for (x, (written, changed, lost)) in (0u32..).zip(row) {
            color_a.put_pixel(x, y, image::Rgb(written.colors[0]));
            color_b.put_pixel(x, y, image::Rgb(written.colors[1]));
            scalar_a.put_pixel(x, y, image::Luma([written.scalars[0]]));
            scalar_b.put_pixel(x, y, image::Luma([written.scalars[1]]));
            fixed += u64::from(*changed);
            if *lost {
                lossy += 1;
                not_invertible.put_pixel(x, y, image::Luma([255]));
            }
        }
    }
    save(&dir.join(names[0]), &color_a)?;
    if target_spec_gloss {
        save(&dir.join(names[1]), &color_b)?;
        save(&dir.join(names[2]), &scalar_a)?;
    } else {
        save(&dir.join(names[1]), &scalar_a)?;
        save(&dir.join(names[2]), &scalar_b)?;
    }
    let total = u64::from(w) * u64::from(h);
    let pct = |n: u64| 100.0 * n as f64 / total as f64;
    let mut text = format!(
        "{} · {}: wrote {}/{{{}, {}, {}}} ({w}x{h})\n",
        m.source.display(),
        m.name,
        dir.display(),
        names[0],
        names[1],
        names[2]
    );
    if safe_color {
        text.push_str(&format!(
            "  safe colour: {fixed} texel(s) ({:.2} %) moved into the valid range\n",
            pct(fixed)
        ));
    }
    if to.is_some() {
        if lossy > 0 {
            let mask = dir.join("not-invertible.png");
            save(&mask, &not_invertible)?;
            text.push_str(&format!(
                "  {lossy} texel(s) ({:.2} %) do not convert back within 1/255 (white in {}): \
                 spec/gloss cannot hold a dielectric base colour above 0.96, and 8-bit maps \
                 pin a partial metal's metallic down only to a few codes\n",
                pct(lossy),
                mask.display()
            ));
        } else {
            text.push_str("  every texel converts back within 1/255\n");
        }
    }
    Ok(text)
}

/// The safe-colour fix of a texel's base or diffuse colour.
fn safe_texel(texel: Texel, strict: bool) -> Texel {
    match texel {
        Texel::MetalRough(b, m, r) => Texel::MetalRough(safe_base_color(b, m, strict), m, r),
        Texel::SpecGloss(d, s, g) => Texel::SpecGloss(safe_diffuse(d, s, strict), s, g),
    }
}

/// The written values of `texel` in the target workflow (or the source workflow, for a
/// safe-colour pass alone).
fn write_texel(texel: Texel, spec_gloss: bool) -> Written {
    match (texel, spec_gloss) {
        (Texel::MetalRough(base_color, metallic, roughness), true) => {
            let s = to_spec_gloss(MetalRough {
                base_color,
                metallic,
                roughness,
            });
            Written {
                colors: [color_codes(s.diffuse), color_codes(s.specular)],
                scalars: [linear_code(s.glossiness), 0],
            }
        }
        (Texel::MetalRough(b, m, r), false) => Written {
            colors: [color_codes(b), [0; 3]],
            scalars: [linear_code(m), linear_code(r)],
        },
        (Texel::SpecGloss(diffuse, specular, glossiness), false) => {
            let m = to_metal_rough(SpecGloss {
                diffuse,
                specular,
                glossiness,
            });
            Written {
                colors: [color_codes(m.base_color), [0; 3]],
                scalars: [linear_code(m.metallic), linear_code(m.roughness)],
            }
        }
        (Texel::SpecGloss(d, s, g), true) => Written {
            colors: [color_codes(d), color_codes(s)],
            scalars: [linear_code(g), 0],
        },
    }
}

/// Whether converting the written values back gives `texel`'s own 8-bit values within 1.
fn round_trips(texel: Texel, written: &Written, spec_gloss: bool) -> bool {
    let close = |a: [u8; 3], b: [u8; 3]| a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 1);
    match (texel, spec_gloss) {
        (Texel::MetalRough(b, m, r), true) => {
            let back = to_metal_rough(SpecGloss {
                diffuse: decode_codes(written.colors[0]),
                specular: decode_codes(written.colors[1]),
                glossiness: f32::from(written.scalars[0]) / 255.0,
            });
            close(color_codes(back.base_color), color_codes(b))
                && linear_code(back.metallic).abs_diff(linear_code(m)) <= 1
                && linear_code(back.roughness).abs_diff(linear_code(r)) <= 1
        }
        (Texel::SpecGloss(d, s, g), false) => {
            let back = to_spec_gloss(MetalRough {
                base_color: decode_codes(written.colors[0]),
                metallic: f32::from(written.scalars[0]) / 255.0,
                roughness: f32::from(written.scalars[1]) / 255.0,
            });
            close(color_codes(back.diffuse), color_codes(d))
                && close(color_codes(back.specular), color_codes(s))
                && linear_code(back.glossiness).abs_diff(linear_code(g)) <= 1
        }
        _ => true,
    }
}

//! `lumen merge`: the parts of a sharded reference (combined into one image), of a
//! sharded tradeoff (its rows joined in order) or of a sharded sequence (its frames
//! checked and listed in one manifest), checked first.

use crate::cli::MergeArgs;
use crate::sequence;
use crate::shard::{Sidecar, check_part, check_together};
use anyhow::{Context, Result, bail};
use lumen::assets::image_io::{OutputFormat, load_rgba32f, save_exr};
use lumen::reference::path::merge_parts;

/// Checks every part (whole, with its sidecar) and that they are every shard of one
/// render, merges them weighted by their path counts, writes the image and reports the
/// effective samples per pixel and the noise estimated from the spread between parts.
pub fn run(args: &MergeArgs) -> Result<()> {
    let mut checked = Vec::with_capacity(args.parts.len());
    for part in &args.parts {
        checked.push((part.clone(), check_part(part)?));
    }
    check_together(&checked)?;
    match checked[0].1.kind.as_str() {
        "tradeoff" => return merge_tradeoff(args, &mut checked),
        "sequence" => return merge_sequence(args, &checked),
        _ => {}
    }
    if OutputFormat::from_path(&args.out)? != OutputFormat::Exr {
        bail!("the merged image is a linear EXR: give --out with .exr");
    }
    let images = checked
        .iter()
        .map(|(path, _)| load_rgba32f(path).with_context(|| format!("{}", path.display())))
        .collect::<Result<Vec<_>>>()?;
    let refs: Vec<&image::Rgba32FImage> = images.iter().collect();
    let merged = merge_parts(&refs).with_context(|| {
        format!(
            "the parts differ in size ({})",
            images
                .iter()
                .map(|i| format!("{}x{}", i.width(), i.height()))
                .collect::<Vec<_>>()
                .join(", ")
        )
    })?;
    save_exr(&args.out, &merged.image)?;
    let pixels = merged.paths.len().max(1) as f64;
    let spp = merged.paths.iter().sum::<f64>() / pixels;
    let lum = |p: &image::Rgba<f32>| {
        let [r, g, b, _] = p.0;
        0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b)
    };
    let mean_luminance = merged.image.pixels().map(lum).sum::<f64>() / pixels;
    let mean_error = merged.standard_error.iter().sum::<f64>() / pixels;
    crate::output::print(&format!(
        "merged {} shards ({} samples per pixel each on average, {:.1} s in all): {:.1} effective samples per pixel\nnoise from the spread between parts: mean standard error {:.3e} of a mean luminance {:.3e} ({:.2} %)\nwrote {}\n",
        checked.len(),
        spp / checked.len() as f64,
        checked.iter().map(|(_, s)| s.seconds).sum::<f64>(),
        spp,
        mean_error,
        mean_luminance,
        if mean_luminance > 0.0 {
            100.0 * mean_error / mean_luminance
        } else {
            0.0
        },
        args.out.display()
    ));
    Ok(())
}

/// Joins the rows of tradeoff parts in shard order into one document (schema
/// lumen-tradeoff/1) at `--out`, and prints its table. Parts measured on different
/// adapters are joined with a warning: their times do not compare.
fn merge_tradeoff(args: &MergeArgs, checked: &mut [(std::path::PathBuf, Sidecar)]) -> Result<()> {
    if !args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        bail!("merged tradeoff rows are JSON: give --out with .json");
    }
    checked.sort_by_key(|(_, s)| s.index);
    let mut merged: Option<serde_json::Value> = None;
    let mut rows = Vec::new();
    for (path, _) in checked.iter() {
        let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
        let doc: serde_json::Value =
            serde_json::from_str(&text).with_context(|| format!("{}: not JSON", path.display()))?;
        rows.extend(
            doc["rows"]
                .as_array()
                .with_context(|| format!("{}: no rows", path.display()))?
                .iter()
                .cloned(),
        );
        if let Some(first) = &merged
            && first["adapter"] != doc["adapter"]
        {
            log::warn!(
                "{}: measured on {} but the first part on {}: their times do not compare",
                path.display(),
                doc["adapter"],
                first["adapter"]
            );
        }
        merged.get_or_insert(doc);
    }
    let mut doc = merged.context("no parts to merge")?;
    let expected = doc["rows_of"].as_u64().unwrap_or(rows.len() as u64);
    if rows.len() as u64 != expected {
        bail!(
            "the parts hold {} rows, the tradeoff has {expected}",
            rows.len()
        );
    }
    let title = doc["title"].as_str().unwrap_or_default().to_string();
    if let Some(map) = doc.as_object_mut() {
        for key in ["shard", "rows_of", "title"] {
            map.remove(key);
        }
    }
    doc["rows"] = serde_json::Value::Array(rows);
    let table =
        crate::commands::tradeoff::markdown(&title, &crate::commands::tradeoff::rows_of(&doc)?);
    crate::output::print(&table);
    lumen::files::write_atomic(&args.out, serde_json::to_string_pretty(&doc)?.as_bytes())?;
    crate::output::print(&format!(
        "merged {} tradeoff shards, {expected} rows\nwrote {}\n",
        checked.len(),
        args.out.display()
    ));
    Ok(())
}

/// Checks every frame each sequence manifest lists (present, with its checksum), joins
/// the manifests into the whole sequence's (every frame once, in order) at `--out`, and
/// prints what it holds.
fn merge_sequence(args: &MergeArgs, checked: &[(std::path::PathBuf, Sidecar)]) -> Result<()> {
    if !args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        bail!("a merged sequence is the manifest of its frames: give --out with .json");
    }
    let mut manifests = Vec::with_capacity(checked.len());
    for (path, _) in checked {
        let manifest = sequence::read(path)?;
        sequence::check_frames(path, &manifest)?;
        manifests.push((path.clone(), manifest));
    }
    let whole = sequence::join(&manifests)?;
    lumen::files::write_atomic(&args.out, serde_json::to_string_pretty(&whole)?.as_bytes())?;
    let [a, b] = whole.frames_of;
    crate::output::print(&format!(
        "merged {} sequence shards ({:.1} s in all): frames {a}..{b}, {} frames, each whole\nwrote {}\n",
        checked.len(),
        checked.iter().map(|(_, s)| s.seconds).sum::<f64>(),
        whole.frames.len(),
        args.out.display()
    ));
    Ok(())
}

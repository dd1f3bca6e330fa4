//! `lumen merge`: the parts of a sharded reference, checked and combined into one image.

use crate::cli::MergeArgs;
use crate::shard::{check_part, check_together};
use anyhow::{Context, Result, bail};
use lumen::assets::image_io::{OutputFormat, load_rgba32f, save_exr};
use lumen::reference::path::merge_parts;

/// Checks every part (whole, with its sidecar) and that they are every shard of one
/// render, merges them weighted by their path counts, writes the image and reports the
/// effective samples per pixel and the noise estimated from the spread between parts.
pub fn run(args: &MergeArgs) -> Result<()> {
    if OutputFormat::from_path(&args.out)? != OutputFormat::Exr {
        bail!("the merged image is a linear EXR: give --out with .exr");
    }
    let mut checked = Vec::with_capacity(args.parts.len());
    for part in &args.parts {
        checked.push((part.clone(), check_part(part)?));
    }
    check_together(&checked)?;
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
    let first = &checked[0].1;
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
    log::info!("merged parts of: {}", first.settings);
    Ok(())
}

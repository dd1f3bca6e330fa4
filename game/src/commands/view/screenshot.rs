//! Screenshots: the display image (PNG) and the exposed linear HDR image (EXR).

use crate::commands::render::save_frame;
use anyhow::Result;
use lumen::App;
use lumen::assets::image_io::OutputFormat;
use std::path::{Path, PathBuf};

/// Renders `app` headless at `size` and saves `<base>.png` (the display image) and
/// `<base>.exr` (exposed linear HDR, before tone mapping), creating folders; returns the
/// two paths. What the `P` key does.
pub fn save_screenshot(app: &mut App, size: (u32, u32), base: &Path) -> Result<[PathBuf; 2]> {
    app.render_headless(size)?;
    let paths = [base.with_extension("png"), base.with_extension("exr")];
    save_frame(app, &paths[0], OutputFormat::Png)?;
    save_frame(app, &paths[1], OutputFormat::Exr)?;
    Ok(paths)
}

/// Saves the view of `app` at `size` (the window's): as `path` (PNG or EXR by extension),
/// or as the next `out/screenshot-N.png` and `.exr`, N being `taken` + 1 (`taken` counts
/// it). Returns the log line.
pub(super) fn screenshot(
    app: &mut App,
    size: (u32, u32),
    path: Option<&Path>,
    taken: &mut u32,
) -> Result<String> {
    let written: Vec<PathBuf> = match path {
        Some(p) => {
            let format = OutputFormat::from_path(p)?;
            app.render_headless(size)?;
            save_frame(app, p, format)?;
            vec![p.to_path_buf()]
        }
        None => {
            *taken += 1;
            let base = PathBuf::from(format!("out/screenshot-{taken}"));
            save_screenshot(app, size, &base)?.to_vec()
        }
    };
    let names: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    Ok(format!("saved {}", names.join(" and ")))
}

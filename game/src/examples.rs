//! Small helpers the examples in `game/examples/` share: the size argument and where
//! images go.

use std::path::PathBuf;

/// Call first in `main`, before any thread exists: turns Mesa's `device_select` layer off
/// as the `lumen` binary does (it only reorders adapters, and prints an `XDG_RUNTIME_DIR`
/// error without a Wayland session), and returns the image size from the first
/// command-line argument (`WxH`), or `default`.
pub fn start(default: (u32, u32)) -> (u32, u32) {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY: documented to run first in main, before any other thread exists.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
    std::env::args()
        .nth(1)
        .and_then(|a| crate::cli::parse_size(&a).ok())
        .unwrap_or(default)
}

/// Saves `image` as `out/examples/<name>` (creating the folders) and prints the path.
pub fn save(image: &image::RgbaImage, name: &str) -> lumen::Result<()> {
    let path = PathBuf::from("out/examples").join(name);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| lumen::Error::io(dir, e))?;
    }
    lumen::assets::image_io::save_png(&path, image)?;
    println!("wrote {}", path.display());
    Ok(())
}

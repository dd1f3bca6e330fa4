//! Writing rendered images: PNG (display image) and OpenEXR (linear HDR).

use crate::error::{Error, Result};
use std::path::Path;

/// The image formats `lumen` writes, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// 8-bit sRGB PNG of the tone-mapped display image.
    Png,
    /// 32-bit float RGB OpenEXR of exposed linear luminance, before tone mapping.
    Exr,
}

impl OutputFormat {
    /// The format for `path`'s extension, or an error naming the extensions supported.
    pub fn from_path(path: &Path) -> Result<OutputFormat> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(OutputFormat::Png),
            Some("exr") => Ok(OutputFormat::Exr),
            other => Err(Error::InvalidArgument(format!(
                "{}: unsupported output format{} (use .png or .exr)",
                path.display(),
                other.map(|e| format!(" '.{e}'")).unwrap_or_default()
            ))),
        }
    }
}

/// Creates the parent directory of `path` if needed.
pub fn ensure_parent(path: &Path) -> Result<()> {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))
        }
        _ => Ok(()),
    }
}

fn image_error(path: &Path, e: image::ImageError) -> Error {
    match e {
        image::ImageError::IoError(io) => Error::io(path, io),
        other => Error::bad_file(path, other.to_string()),
    }
}

/// Writes an 8-bit RGBA image as PNG.
pub fn save_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    ensure_parent(path)?;
    image
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| image_error(path, e))
}

/// Writes the RGB channels of a float image as a 32-bit float OpenEXR file.
pub fn save_exr(path: &Path, image: &image::Rgba32FImage) -> Result<()> {
    ensure_parent(path)?;
    let rgb: image::Rgb32FImage = image::DynamicImage::ImageRgba32F(image.clone()).into_rgb32f();
    rgb.save_with_format(path, image::ImageFormat::OpenExr)
        .map_err(|e| image_error(path, e))
}

/// Reads an OpenEXR (or any float-capable) image as 32-bit float RGBA.
pub fn load_rgba32f(path: &Path) -> Result<image::Rgba32FImage> {
    let img = image::ImageReader::open(path)
        .map_err(|e| Error::io(path, e))?
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?
        .decode()
        .map_err(|e| image_error(path, e))?;
    Ok(img.into_rgba32f())
}

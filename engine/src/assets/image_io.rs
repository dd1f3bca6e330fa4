//! Writing rendered images: PNG (display image) and OpenEXR (linear HDR).

use crate::error::{Error, Result};
use crate::files;
use crate::limits::FileKind;
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

fn image_error(path: &Path, e: image::ImageError) -> Error {
    match e {
        image::ImageError::IoError(io) => Error::io(path, io),
        other => Error::bad_file(path, other.to_string()),
    }
}

/// Encodes `image` as `format` in memory and writes it with [`files::write_atomic`]: a
/// failed write is an error and never leaves a half-written file at `path`.
pub fn save<P: image::PixelWithColorType>(
    path: &Path,
    image: &image::ImageBuffer<P, Vec<P::Subpixel>>,
    format: image::ImageFormat,
) -> Result<()>
where
    [P::Subpixel]: image::EncodableLayout,
{
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, format)
        .map_err(|e| image_error(path, e))?;
    files::write_atomic(path, bytes.get_ref())
}

/// Writes an 8-bit RGBA image as PNG.
pub fn save_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    save(path, image, image::ImageFormat::Png)
}

/// Writes the RGB channels of a float image as a 32-bit float OpenEXR file.
pub fn save_exr(path: &Path, image: &image::Rgba32FImage) -> Result<()> {
    let rgb: image::Rgb32FImage = image::DynamicImage::ImageRgba32F(image.clone()).into_rgb32f();
    save(path, &rgb, image::ImageFormat::OpenExr)
}

/// Writes a linear 32-bit float RGBA OpenEXR file, alpha included (a reference shard's
/// part keeps its path counts there).
pub fn save_exr_rgba(path: &Path, image: &image::Rgba32FImage) -> Result<()> {
    save(path, image, image::ImageFormat::OpenExr)
}

/// Reads an OpenEXR (or any float-capable) image as 32-bit float RGBA.
pub fn load_rgba32f(path: &Path) -> Result<image::Rgba32FImage> {
    let bytes = files::read(path, FileKind::Environment)?;
    let img = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| Error::io(path, e))?
        .decode()
        .map_err(|e| image_error(path, e))?;
    Ok(img.into_rgba32f())
}

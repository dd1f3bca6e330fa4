//! Texture files: reading an image from a URI (data URI or a file next to the scene) and
//! decoding it to RGBA8 within a size budget.

use crate::limits::FileKind;
use crate::scene::{ColorSpace, TextureData};
use base64::Engine;
use std::path::Path;

/// The bytes behind a glTF URI: a base64 `data:` URI, or a percent-encoded path relative
/// to `base`, read as a file of `kind` (a regular file within its cap).
pub fn read_uri(base: &Path, uri: &str, kind: FileKind) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let payload = rest
            .split_once(";base64,")
            .map(|(_, p)| p)
            .ok_or("a data URI that is not base64")?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("bad base64 data URI: {e}"));
    }
    if uri.contains(':') {
        return Err(format!("unsupported URI scheme in {uri}"));
    }
    let path = base.join(super::gltf_buffers::percent_decoded(uri));
    super::files::read(&path, kind).map_err(|e| e.to_string())
}

/// Decodes PNG or JPEG bytes into RGBA8. A texture whose longest side exceeds `max_size`
/// is downscaled (keeping its aspect ratio) with a warning pushed to `warnings`.
pub fn decode(
    bytes: &[u8],
    color_space: ColorSpace,
    max_size: u32,
    warnings: &mut Vec<String>,
    what: &str,
) -> Result<TextureData, String> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    // The decoder's own allocation cap (512 MiB) stays; a 16384² single-channel image
    // fits it, and it is downscaled before it is expanded to RGBA.
    reader.limits(image::Limits::default());
    let mut image = reader
        .decode()
        .map_err(|e| format!("cannot decode the image: {e}"))?;
    let (w, h) = (image.width(), image.height());
    if w == 0 || h == 0 {
        return Err("the image is empty".into());
    }
    let max_size = max_size.max(1);
    if w.max(h) > max_size {
        let scale = f64::from(max_size) / f64::from(w.max(h));
        let nw = ((f64::from(w) * scale).round() as u32).clamp(1, max_size);
        let nh = ((f64::from(h) * scale).round() as u32).clamp(1, max_size);
        image = image.thumbnail_exact(nw, nh);
        warnings.push(format!(
            "{what}: {w}×{h} exceeds the texture budget of {max_size}: downscaled to {nw}×{nh}"
        ));
    }
    let rgba = image.to_rgba8();
    Ok(TextureData {
        width: rgba.width(),
        height: rgba.height(),
        rgba8: rgba.into_raw(),
        color_space,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32) -> Vec<u8> {
        let img = image::RgbaImage::from_pixel(w, h, image::Rgba([10, 20, 30, 255]));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png)
            .expect("png");
        out.into_inner()
    }

    #[test]
    fn large_images_are_downscaled_with_a_warning() {
        let mut warnings = Vec::new();
        let t =
            decode(&png(300, 150), ColorSpace::Srgb, 64, &mut warnings, "img").expect("decodes");
        assert_eq!((t.width, t.height), (64, 32));
        assert_eq!(&t.rgba8[..4], &[10, 20, 30, 255]);
        assert_eq!(warnings.len(), 1);
        let t = decode(&png(1, 1), ColorSpace::Linear, 64, &mut warnings, "img").expect("1×1");
        assert_eq!((t.width, t.height, t.rgba8.len()), (1, 1, 4));
        assert_eq!(warnings.len(), 1);
    }

    #[test]
    fn bad_bytes_and_uris_are_errors() {
        let mut warnings = Vec::new();
        assert!(decode(b"not an image", ColorSpace::Srgb, 64, &mut warnings, "x").is_err());
        assert!(decode(&png(4, 4)[..20], ColorSpace::Srgb, 64, &mut warnings, "x").is_err());
        let base = Path::new("/nonexistent");
        assert!(
            read_uri(base, "missing.png", FileKind::Texture)
                .unwrap_err()
                .contains("missing.png")
        );
        assert!(read_uri(base, "data:image/png;base64,@@@", FileKind::Texture).is_err());
        assert!(read_uri(base, "https://example.com/a.png", FileKind::Texture).is_err());
        assert_eq!(
            read_uri(base, "data:image/png;base64,AAEC", FileKind::Texture).ok(),
            Some(vec![0, 1, 2])
        );
    }
}

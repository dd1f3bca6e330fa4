//! Texture images: decoding PNG or JPEG bytes to RGBA8 within a size budget.

use crate::scene::{ColorSpace, TextureData};

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
    fn bad_bytes_are_errors() {
        let mut warnings = Vec::new();
        assert!(decode(b"not an image", ColorSpace::Srgb, 64, &mut warnings, "x").is_err());
        assert!(decode(&png(4, 4)[..20], ColorSpace::Srgb, 64, &mut warnings, "x").is_err());
    }
}

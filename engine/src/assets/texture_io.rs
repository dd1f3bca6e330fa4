//! Texture images: decoding PNG, JPEG, WebP or KTX2 bytes to RGBA8 within a size budget.
//!
//! KTX2 images are glTF's `KHR_texture_basisu`: Basis Universal data (ETC1S, or UASTC,
//! possibly Zstandard-supercompressed) in a KTX2 container. They are transcoded with the
//! pure-Rust `basisu` crate (a port of Binomial's reference transcoder, verified by its
//! authors byte for byte against it) to uncompressed RGBA8 of the base level; Lumen then
//! builds its own mip chain, as for any texture. Pure Rust keeps the build free of the
//! C++ transcoder that the `basis-universal` bindings compile.

use crate::scene::{ColorSpace, TextureData};

/// The 12 bytes every KTX2 file starts with.
const KTX2_MAGIC: [u8; 12] = [
    0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a,
];

/// Whether `bytes` are a KTX2 file (by its identifier).
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&KTX2_MAGIC)
}

/// The decoders' allocation cap: 512 MiB.
const DECODE_CAP: u64 = 512 << 20;

/// Checks the sizes a KTX2 file declares (Khronos, "KTX File Format Specification 2.0",
/// section 3: the header and the level index) before the transcoder trusts them: the
/// base level's RGBA8 size and every level's uncompressed size within the 512 MiB cap,
/// every level's bytes inside the file, at most 32 levels, one face, one layer, no depth
/// (a 2D texture, as glTF's are).
fn ktx2_within_limits(bytes: &[u8]) -> Result<(), String> {
    let u32_at = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])))
            .ok_or("the header is truncated")
    };
    let u64_at = |at: usize| {
        bytes
            .get(at..at + 8)
            .and_then(|b| b.try_into().ok())
            .map(u64::from_le_bytes)
            .ok_or("the level index is truncated")
    };
    let (w, h, depth) = (u32_at(20)?, u32_at(24)?, u32_at(28)?);
    let (layers, faces, levels) = (u32_at(32)?, u32_at(36)?, u32_at(40)?.max(1));
    if w.saturating_mul(h).saturating_mul(4) > DECODE_CAP {
        return Err(format!(
            "its {w}×{h} base level is over the 512 MiB decoding cap"
        ));
    }
    if levels > 32 || faces != 1 || depth > 1 || layers > 1 {
        return Err(format!(
            "{levels} levels, {faces} faces, depth {depth} and {layers} layers are not a 2D texture's"
        ));
    }
    for level in 0..levels as usize {
        let entry = 80 + level * 24;
        let (offset, length, uncompressed) =
            (u64_at(entry)?, u64_at(entry + 8)?, u64_at(entry + 16)?);
        if uncompressed > DECODE_CAP || offset.saturating_add(length) > bytes.len() as u64 {
            return Err(format!(
                "level {level} declares {uncompressed} bytes from {length} at {offset}: outside the file or the cap"
            ));
        }
    }
    Ok(())
}

/// The base level of a Basis Universal KTX2 texture (ETC1S or UASTC LDR) as RGBA8. A
/// malformed file, an HDR or otherwise unsupported source format, or a panic inside the
/// transcoder is an error.
pub fn transcode_ktx2(bytes: &[u8]) -> Result<image::RgbaImage, String> {
    use basisu::{DecodeFlags, SourceFormat, TargetFormat, Transcoder};
    ktx2_within_limits(bytes).map_err(|e| format!("a Basis Universal KTX2 texture, but {e}"))?;
    let transcoded = crate::error::contain_panics(|| {
        let texture = Transcoder::new(bytes)
            .map_err(|e| format!("not a Basis Universal KTX2 texture: {e:?}"))?;
        let format = texture.source_format();
        if !matches!(format, SourceFormat::Etc1s | SourceFormat::UastcLdr) {
            return Err(format!(
                "its {format:?} data is not transcoded (ETC1S and UASTC LDR are)"
            ));
        }
        let (w, h) = texture.base_dimensions();
        let pixels = texture
            .transcode(0, TargetFormat::Rgba32, DecodeFlags::NONE)
            .map_err(|e| format!("cannot transcode it: {e:?}"))?;
        image::RgbaImage::from_raw(w, h, pixels)
            .ok_or_else(|| format!("its {w}×{h} base level has the wrong size"))
    });
    transcoded.map_err(|panic| format!("the transcoder failed: {panic}"))?
}

/// Decodes PNG, JPEG, WebP or Basis Universal KTX2 bytes into RGBA8. A texture whose
/// longest side exceeds `max_size` is downscaled (keeping its aspect ratio) with a
/// warning pushed to `warnings`.
pub fn decode(
    bytes: &[u8],
    color_space: ColorSpace,
    max_size: u32,
    warnings: &mut Vec<String>,
    what: &str,
) -> Result<TextureData, String> {
    if is_ktx2(bytes) {
        let image = image::DynamicImage::ImageRgba8(transcode_ktx2(bytes)?);
        return within_budget(image, color_space, max_size, warnings, what);
    }
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    // The decoder's own allocation cap (512 MiB) stays; a 16384² single-channel image
    // fits it, and it is downscaled before it is expanded to RGBA.
    reader.limits(image::Limits::default());
    let image = reader
        .decode()
        .map_err(|e| format!("cannot decode the image: {e}"))?;
    within_budget(image, color_space, max_size, warnings, what)
}

/// `image` as RGBA8 texture data, downscaled to `max_size` with a warning if it is larger.
fn within_budget(
    mut image: image::DynamicImage,
    color_space: ColorSpace,
    max_size: u32,
    warnings: &mut Vec<String>,
    what: &str,
) -> Result<TextureData, String> {
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
    fn basis_universal_ktx2_textures_are_transcoded() {
        // tests/data/ktx2: 8 × 8 quadrants encoded by Binomial's encoder as ETC1S and as
        // Zstandard-supercompressed UASTC. UASTC keeps these flat colours exactly; ETC1S
        // within 3 of 255.
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/ktx2");
        let colours = [[230, 40, 30], [40, 200, 60], [30, 60, 220], [240, 240, 240]];
        for (file, tolerance) in [
            ("quadrants_uastc_zstd.ktx2", 0),
            ("quadrants_etc1s.ktx2", 3),
        ] {
            let bytes = std::fs::read(dir.join(file)).expect("fixture");
            assert!(is_ktx2(&bytes));
            let mut warnings = Vec::new();
            let t = decode(&bytes, ColorSpace::Srgb, 64, &mut warnings, file).expect(file);
            assert_eq!((t.width, t.height), (8, 8));
            for (y, x) in [(1, 1), (1, 6), (6, 1), (6, 6), (3, 3), (4, 4)] {
                let q = usize::from(y >= 4) * 2 + usize::from(x >= 4);
                let at = (y * 8 + x) * 4;
                for (c, want) in colours[q].iter().enumerate() {
                    let got = i32::from(t.rgba8[at + c]);
                    assert!((got - want).abs() <= tolerance, "{file} ({x}, {y}): {got}");
                }
                assert_eq!(t.rgba8[at + 3], 255);
            }
            // The budget applies: downscaled to 4 × 4 with a warning.
            let small = decode(&bytes, ColorSpace::Srgb, 4, &mut warnings, file).expect(file);
            assert_eq!((small.width, small.height, warnings.len()), (4, 4, 1));
        }
        // Truncated, corrupted and header-only files are errors, never panics.
        let good = std::fs::read(dir.join("quadrants_etc1s.ktx2")).expect("fixture");
        let mut warnings = Vec::new();
        for cut in [12, 40, 80, good.len() - 1] {
            let r = decode(&good[..cut], ColorSpace::Srgb, 64, &mut warnings, "cut");
            assert!(r.is_err(), "{cut} bytes decoded");
        }
        for k in (12..good.len()).step_by(7) {
            let mut bad = good.clone();
            bad[k] ^= 0x5a;
            let _ = decode(&bad, ColorSpace::Srgb, 64, &mut warnings, "flipped");
        }
    }

    #[test]
    fn bad_bytes_are_errors() {
        let mut warnings = Vec::new();
        assert!(decode(b"not an image", ColorSpace::Srgb, 64, &mut warnings, "x").is_err());
        assert!(decode(&png(4, 4)[..20], ColorSpace::Srgb, 64, &mut warnings, "x").is_err());
    }
}

//! The environment: light arriving from infinitely far away, from an equirectangular HDR
//! image or a uniform colour. It lights the scene (image-based lighting) and can be drawn as
//! the background.

use crate::error::{Error, Result};
use bevy_ecs::prelude::*;
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// Largest value kept in a texel: the maximum of the 16-bit float textures the environment
/// is filtered in. Larger (finite) values are clamped to it; none of the shipped HDRIs
/// reaches it (the sun of `sky.exr` peaks at 22672).
pub const MAX_TEXEL: f32 = 65504.0;

/// The most texels an environment image may have: 8192 × 4096, in any shape (a
/// 2 × 100 000 image decodes, and is downscaled to the device's limit before upload).
/// Decoding takes about 50 bytes a texel at its peak (the decoders' float RGBA, the RGB
/// copy and the sanitised texels), 1.7 GB at this limit; a 16k HDRI would need 6.7 GB,
/// so larger images are refused with the reason (downscale them first).
pub const MAX_TEXELS: u64 = 8192 * 4096;

/// What loading an HDR image had to repair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sanitized {
    /// Channels that were negative (lossy compression ringing) and became 0.
    pub negative: usize,
    /// Channels that were NaN or infinite and became 0.
    pub non_finite: usize,
    /// Channels above [`MAX_TEXEL`] that were clamped to it.
    pub clamped: usize,
}

/// A decoded equirectangular environment image: linear RGB, row 0 at the top (+Y).
#[derive(Debug)]
pub struct EquirectImage {
    /// Unique per loaded image: the renderer prefilters each id once.
    pub id: u64,
    /// Where it came from, if a file.
    pub path: Option<PathBuf>,
    /// Width in texels (longitude).
    pub width: u32,
    /// Height in texels (latitude).
    pub height: u32,
    /// Linear RGB texels, row-major, every value finite and in 0..=[`MAX_TEXEL`].
    pub texels: Vec<[f32; 3]>,
    /// What was repaired while loading.
    pub sanitized: Sanitized,
}

static NEXT_IMAGE_ID: AtomicU64 = AtomicU64::new(1);

fn sanitize(v: f32, report: &mut Sanitized) -> f32 {
    if !v.is_finite() {
        report.non_finite += 1;
        0.0
    } else if v < 0.0 {
        report.negative += 1;
        0.0
    } else if v > MAX_TEXEL {
        report.clamped += 1;
        MAX_TEXEL
    } else {
        v
    }
}

impl EquirectImage {
    /// An image from raw linear RGB texels (row-major, top row first), sanitized: negative,
    /// NaN and infinite channels become 0, values above [`MAX_TEXEL`] are clamped.
    pub fn from_texels(width: u32, height: u32, texels: Vec<[f32; 3]>) -> Result<EquirectImage> {
        if width < 2 || height < 1 || texels.len() != (width as usize) * (height as usize) {
            return Err(Error::InvalidArgument(format!(
                "an equirectangular image needs at least 2×1 texels and width × height of them; got {width}×{height} with {}",
                texels.len()
            )));
        }
        let mut sanitized = Sanitized::default();
        let texels = texels
            .into_iter()
            .map(|t| t.map(|v| sanitize(v, &mut sanitized)))
            .collect();
        Ok(EquirectImage {
            id: NEXT_IMAGE_ID.fetch_add(1, Ordering::Relaxed),
            path: None,
            width,
            height,
            texels,
            sanitized,
        })
    }

    /// Loads an OpenEXR (any compression the `exr` crate reads, DWAA/DWAB included) or
    /// Radiance `.hdr` file. Errors name the file and the problem.
    pub fn load(path: &Path) -> Result<EquirectImage> {
        let bytes = crate::files::read(path, crate::limits::FileKind::Environment)?;
        EquirectImage::decode(&bytes, path)
    }

    /// Decodes the bytes of an OpenEXR or Radiance `.hdr` file read from `path` (named in
    /// errors and warnings).
    pub fn decode(bytes: &[u8], path: &Path) -> Result<EquirectImage> {
        let format = image::guess_format(bytes)
            .map_err(|_| Error::bad_file(path, "not an OpenEXR or Radiance HDR image"))?;
        if !matches!(
            format,
            image::ImageFormat::OpenExr | image::ImageFormat::Hdr
        ) {
            return Err(Error::bad_file(
                path,
                format!("{format:?} is not an HDR format (use OpenEXR .exr or Radiance .hdr)"),
            ));
        }
        // The header's size is checked before anything is decoded: a decoder sizes its
        // buffers from it, and some allocate without a check (the `exr` crate's DWA
        // decoder asked for 25 GB for a mutated data window).
        let header = || {
            let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes));
            reader.set_format(format);
            reader
        };
        // For OpenEXR, the larger of the display window (the image crate's dimensions, the
        // size of the buffer it decodes into) and every part's data window (what the `exr`
        // crate decodes).
        let (mut w, mut h) = header()
            .into_dimensions()
            .map_err(|e| Error::bad_file(path, format!("cannot decode: {e}")))?;
        if format == image::ImageFormat::OpenExr {
            let (dw, dh) = exr_data_window(bytes)
                .map_err(|e| Error::bad_file(path, format!("cannot decode: {e}")))?;
            (w, h) = (w.max(dw), h.max(dh));
        }
        let texels = u64::from(w) * u64::from(h);
        let decoded_bytes = texels * 16;
        let budget = crate::limits::memory_budget();
        if texels > MAX_TEXELS || decoded_bytes > budget.bytes {
            return Err(Error::bad_file(
                path,
                format!(
                    "{w}×{h} is too large to decode (at most {MAX_TEXELS} texels, 8192 × 4096, in any shape; {} decoded, the memory budget is {budget}); downscale it first",
                    crate::limits::bytes_text(decoded_bytes)
                ),
            ));
        }
        if format == image::ImageFormat::OpenExr {
            check_exr_chunks(bytes)
                .map_err(|e| Error::bad_file(path, format!("cannot decode: {e}")))?;
        }
        let mut reader = header();
        let mut limits = image::Limits::default();
        limits.max_alloc = Some(budget.bytes);
        reader.limits(limits);
        let decoded = reader
            .decode()
            .map_err(|e| Error::bad_file(path, format!("cannot decode: {e}")))?
            .into_rgb32f();
        let (w, h) = decoded.dimensions();
        let texels = decoded.pixels().map(|p| p.0).collect();
        let mut img = EquirectImage::from_texels(w, h, texels)
            .map_err(|e| Error::bad_file(path, e.to_string()))?;
        img.path = Some(path.to_path_buf());
        let s = img.sanitized;
        if img.is_black() {
            log::warn!(
                "{}: the environment lights nothing: every texel is black after {} negative and {} NaN or infinite channels became 0",
                path.display(),
                s.negative,
                s.non_finite
            );
        } else if s.negative + s.non_finite + s.clamped > 0 {
            log::info!(
                "{}: set {} negative and {} non-finite channels to 0, clamped {} above {MAX_TEXEL}",
                path.display(),
                s.negative,
                s.non_finite,
                s.clamped
            );
        }
        Ok(img)
    }
}

impl EquirectImage {
    /// A box-filtered copy no wider and no taller than `max` texels (each axis on its own,
    /// so an image past a device's texture limit fits it), or `None` if it already fits.
    /// Each output texel is the mean of the source texels its footprint covers.
    pub fn downscaled_to_fit(&self, max: u32) -> Option<EquirectImage> {
        let max = max.max(2);
        if self.width <= max && self.height <= max {
            return None;
        }
        let (w, h) = (self.width.min(max), self.height.min(max));
        let span = |i: u32, out: u32, size: u32| {
            let lo = (u64::from(i) * u64::from(size) / u64::from(out)) as u32;
            let hi = ((u64::from(i) + 1) * u64::from(size) / u64::from(out)) as u32;
            lo..hi.max(lo + 1).min(size)
        };
        let mut texels = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h {
            let rows = span(y, h, self.height);
            for x in 0..w {
                let cols = span(x, w, self.width);
                let mut sum = [0.0f64; 3];
                let mut n = 0.0f64;
                for sy in rows.clone() {
                    for sx in cols.clone() {
                        let t = self.texels[(sy * self.width + sx) as usize];
                        for c in 0..3 {
                            sum[c] += f64::from(t[c]);
                        }
                        n += 1.0;
                    }
                }
                texels.push(sum.map(|v| (v / n) as f32));
            }
        }
        Some(EquirectImage {
            id: NEXT_IMAGE_ID.fetch_add(1, Ordering::Relaxed),
            path: self.path.clone(),
            width: w,
            height: h,
            texels,
            sanitized: self.sanitized,
        })
    }

    /// Whether no texel carries light (every channel 0 after sanitizing).
    pub fn is_black(&self) -> bool {
        self.texels.iter().all(|t| t.iter().all(|&v| v == 0.0))
    }
}

/// The largest data window among an OpenEXR file's parts (texels), read from its headers
/// alone. The decoders size their buffers from the data windows, which the image crate's
/// dimensions (the display window) do not bound.
fn exr_data_window(bytes: &[u8]) -> std::result::Result<(u32, u32), String> {
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| e.to_string())?;
    let side = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
    let (mut w, mut h) = (0, 0);
    for header in &meta.headers {
        w = w.max(side(header.layer_size.width()));
        h = h.max(side(header.layer_size.height()));
    }
    Ok((w, h))
}

/// Refuses an OpenEXR file with a DWA-compressed chunk whose header declares more data
/// than its block can hold. The `exr` crate's DWA decoder allocates what those counters
/// say before checking them (the fuzzer found requests of 25 GB and 512 TB, which abort the
/// process). The nine counters after each chunk's version (little-endian u64: the unknown, AC, DC and RLE
/// section sizes and the AC and DC coefficient counts) are bounded by four times the
/// header's largest uncompressed block.
fn check_exr_chunks(bytes: &[u8]) -> std::result::Result<(), String> {
    let reader = exr::block::read(std::io::Cursor::new(bytes), false).map_err(|e| e.to_string())?;
    let headers = reader.headers().to_vec();
    let is_dwa = |h: &exr::meta::header::Header| {
        matches!(
            h.compression,
            exr::compression::Compression::DWAA(_) | exr::compression::Compression::DWAB(_)
        )
    };
    if !headers.iter().any(is_dwa) {
        return Ok(());
    }
    for chunk in reader.all_chunks(false).map_err(|e| e.to_string())? {
        let chunk = chunk.map_err(|e| e.to_string())?;
        let Some(header) = headers.get(chunk.layer_index).filter(|h| is_dwa(h)) else {
            continue;
        };
        let data = match &chunk.compressed_block {
            exr::block::chunk::CompressedBlock::ScanLine(b) => &b.compressed_pixels_le,
            exr::block::chunk::CompressedBlock::Tile(t) => &t.compressed_pixels_le,
            _ => return Err("deep data is not an environment image".into()),
        };
        let limit = header.max_block_byte_size() as u64 * 4;
        let counters = data
            .chunks_exact(8)
            .take(10)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0xFF; 8])));
        for (k, value) in counters.enumerate() {
            // Counters 8 and 9 count 16-bit coefficients; the others are byte sizes.
            let bytes = if k >= 8 {
                value.saturating_mul(2)
            } else {
                value
            };
            if k > 0 && bytes > limit {
                return Err(format!(
                    "a DWA chunk declares {bytes} bytes, more than its block can hold ({limit})"
                ));
            }
        }
    }
    Ok(())
}

/// Where the environment's light comes from.
#[derive(Clone, Debug)]
pub enum EnvironmentSource {
    /// The same radiance from every direction, linear RGB (multiplied by the intensity).
    Uniform(Vec3),
    /// An equirectangular image (multiplied by the intensity).
    Image(Arc<EquirectImage>),
}

/// What the camera sees where no geometry is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// The environment itself, blurred as a surface of this perceptual roughness would
    /// reflect it (0 = sharp).
    Environment {
        /// Blur, as a perceptual roughness 0..1.
        blur: f32,
    },
    /// The camera's own background colour (`Camera::background`).
    CameraColor,
}

/// Light from infinitely far away: lights every surface (image-based lighting: diffuse from
/// spherical harmonics, specular from a GGX-prefiltered cube map and the split-sum BRDF
/// table) and, by default, is drawn as the background. Only the first entity with an
/// `Environment` counts.
#[derive(Component, Clone, Debug)]
pub struct Environment {
    /// The light.
    pub source: EnvironmentSource,
    /// Luminance in cd/m² of a texel of value 1 (image) or of the colour (1, 1, 1).
    pub intensity: f32,
    /// Rotation of the environment about +Y, radians.
    pub rotation_y_rad: f32,
    /// What the background shows.
    pub background: Background,
}

impl Environment {
    /// An image environment with the given intensity (cd/m² per unit texel value).
    pub fn image(image: Arc<EquirectImage>, intensity: f32) -> Self {
        Environment {
            source: EnvironmentSource::Image(image),
            intensity,
            rotation_y_rad: 0.0,
            background: Background::Environment { blur: 0.0 },
        }
    }

    /// A uniform environment of `radiance` cd/m² (linear RGB).
    pub fn uniform(radiance: Vec3) -> Self {
        Environment {
            source: EnvironmentSource::Uniform(radiance),
            intensity: 1.0,
            rotation_y_rad: 0.0,
            background: Background::Environment { blur: 0.0 },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitizing() {
        let img = EquirectImage::from_texels(
            2,
            1,
            vec![[-1.0, f32::NAN, 1e9], [0.5, f32::INFINITY, -0.0]],
        )
        .map(|i| (i.texels, i.sanitized));
        let (texels, s) = img.unwrap_or_default();
        assert_eq!(texels, vec![[0.0, 0.0, MAX_TEXEL], [0.5, 0.0, 0.0]]);
        assert_eq!((s.negative, s.non_finite, s.clamped), (1, 2, 1));
        assert!(EquirectImage::from_texels(1, 1, vec![[0.0; 3]]).is_err());
        assert!(EquirectImage::from_texels(4, 2, vec![[0.0; 3]; 7]).is_err());
    }

    #[test]
    fn load_errors_name_the_file() {
        let dir = std::env::temp_dir().join(format!("lumen-env-test-{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        let missing = dir.join("missing.exr");
        let e = EquirectImage::load(&missing).err().map(|e| e.to_string());
        assert!(e.is_some_and(|e| e.contains("missing.exr")));
        let junk = dir.join("junk.exr");
        let _ = std::fs::write(&junk, b"not an image at all");
        let e = EquirectImage::load(&junk).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.contains("junk.exr") && e.contains("not an OpenEXR")),
            "{e:?}"
        );
        // A truncated EXR: a real header and nothing after it.
        let real = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/hdri/sky.exr"
        ))
        .unwrap_or_default();
        let cut = dir.join("cut.exr");
        let _ = std::fs::write(&cut, &real[..real.len().min(400)]);
        let e = EquirectImage::load(&cut).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.contains("cut.exr") && e.contains("cannot decode")),
            "{e:?}"
        );
        let png = dir.join("tiny.png");
        let _ = image::RgbImage::new(2, 1).save(&png);
        let e = EquirectImage::load(&png).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.contains("not an HDR format")),
            "{e:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

//! The ground-truth renderer: a CPU path tracer of the same ECS scene the rasterizer
//! draws (`lumen reference`).
//!
//! It renders what the rasterizer's extraction produced for the same frame: the same
//! instances, factors, lights (pre-exposed, same units and attenuation), environment and
//! camera, so its linear output is directly comparable with `lumen render --out F.exr`.
//! That frame reaches it as a [`TraceInput`] of plain types, which
//! [`crate::trace_input::trace_scene`] builds: nothing here depends on the renderer.
//! It evaluates the same BRDF, with the same visibility term and, when the quality has
//! it on, the same multiple-scattering energy compensation: it is the ground truth for
//! light transport (visibility, shadows, indirect and environment light), not for the
//! microfacet model. Material maps (textures, vertex colours, normal maps, alpha masks)
//! are sampled as the G-buffer's textured variant samples them.

pub mod bsdf;
pub mod bvh;
pub mod dielectric;
pub mod integrator;
pub mod microfacet;
pub mod rng;
pub mod textures;
pub mod traced_scene;

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

pub use rng::Rng;

/// Names the path tracer's estimator in the file names of cached references
/// (`lumen tradeoff`), so that a reference traced by an earlier estimator, with other
/// noise, is traced again rather than reused: `lc` is next-event estimation with light
/// connections.
pub const ESTIMATOR: &str = "lc";
pub use traced_scene::{
    LightVisibility, TraceInput, TraceInstance, TraceLight, TraceMaterial, TraceScene,
};

/// What `render` is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceOptions {
    /// Image size in pixels.
    pub size: (u32, u32),
    /// Paths per pixel.
    pub samples_per_pixel: u32,
    /// Surface interactions per path (1 = direct light only).
    pub max_bounces: u32,
    /// Seed: the same seed gives the same image.
    pub seed: u64,
}

impl Default for ReferenceOptions {
    fn default() -> Self {
        ReferenceOptions {
            size: (256, 256),
            samples_per_pixel: 64,
            max_bounces: 8,
            seed: 0,
        }
    }
}

/// A share of a render's samples, for splitting one render across processes or
/// machines: shard `index` of `count` traces the samples `s` of every pixel with
/// `spp · index / count ≤ s < spp · (index + 1) / count` (contiguous ranges, so every
/// shard traces whole sample indices, each with its own deterministic random stream
/// `(seed, pixel, s)`). Sample passes rather than tiles: every shard costs about the same
/// whatever the image holds, and each part is a full, viewable, noisier image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This shard, `0 ≤ index < count`.
    pub index: u32,
    /// How many shards the render is split into (at least 1).
    pub count: u32,
}

impl Shard {
    /// This shard's contiguous share of `total` items (sample indices per pixel, frames
    /// of a sequence): `total · index / count .. total · (index + 1) / count`, empty when
    /// there are more shards than items and this one gets none.
    pub fn range(&self, total: u32) -> std::ops::Range<u32> {
        let count = u64::from(self.count.max(1));
        let at = |i: u64| (u64::from(total) * i / count).min(u64::from(total)) as u32;
        at(u64::from(self.index.min(self.count)))..at(u64::from(self.index.min(self.count)) + 1)
    }
}

/// What a path-traced part estimates per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Estimate {
    /// Radiance ([`render`]).
    Radiance,
    /// Ambient occlusion within this radius in metres ([`render_ambient_occlusion`]).
    Occlusion(f32),
}

/// The largest value a pixel holds per channel: the 16-bit float maximum (65504) of the
/// rasterizer's HDR target, which its lighting and sky passes clamp to.
pub const HDR_MAX: f64 = 65504.0;

/// A path-traced image and what its accumulation had to drop.
#[derive(Clone, Debug)]
pub struct Traced {
    /// Linear, pre-exposed radiance per pixel (alpha 1); every value finite.
    pub image: image::Rgba32FImage,
    /// Paths whose radiance was NaN or infinite: counted, left out of their pixel's mean.
    pub dropped_samples: u64,
}

/// Path-traces `scene`: linear, pre-exposed radiance per pixel (alpha 1), the mean of
/// `samples_per_pixel` paths with the pixel position jittered uniformly (box filter).
/// Rows run in parallel; `progress` is called with the number of rows done so far.
///
/// The accumulation is guarded: a path whose radiance is NaN or infinite is counted in
/// [`Traced::dropped_samples`] and left out of the mean, which is taken over the remaining
/// paths in `f64` so that no sum of finite values overflows; a pixel with no finite path
/// is black. Like the rasterizer's 16-bit float HDR target, a pixel holds at most
/// [`HDR_MAX`] per channel. Every pixel written is finite.
pub fn render(
    scene: &TraceScene,
    options: &ReferenceOptions,
    progress: &(dyn Fn(u32) + Sync),
) -> Traced {
    let all = 0..options.samples_per_pixel.max(1);
    along_camera_rays(scene, options, all, false, progress, &|origin, dir, rng| {
        scene.radiance(origin, dir, options.max_bounces.max(1), rng)
    })
}

/// One shard's part of a render ([`Shard`]): per pixel the mean of the finite paths of
/// the shard's samples (rgb, not clamped) and how many there were (alpha, an exact
/// integer below 2²⁴). [`merge_parts`] combines the parts of every shard into the image
/// [`render`] (or [`render_ambient_occlusion`]) gives.
pub fn render_part(
    scene: &TraceScene,
    options: &ReferenceOptions,
    shard: Shard,
    estimate: Estimate,
    progress: &(dyn Fn(u32) + Sync),
) -> Traced {
    let samples = shard.range(options.samples_per_pixel.max(1));
    along_camera_rays(
        scene,
        options,
        samples,
        true,
        progress,
        &|origin, dir, rng| match estimate {
            Estimate::Radiance => scene.radiance(origin, dir, options.max_bounces.max(1), rng),
            Estimate::Occlusion(radius_m) => {
                Vec3::splat(scene.ambient_occlusion(origin, dir, radius_m, rng))
            }
        },
    )
}

/// The merge of parts made by [`render_part`] (same size): per pixel the mean of all
/// parts' paths, `Σ_i m_i k_i / Σ_i k_i` over the parts' means `m_i` and path counts
/// `k_i` (in f64), clamped to [`HDR_MAX`] like [`render`]; alpha 1. With it, the standard
/// error of each pixel's mean luminance estimated from the spread of the parts (with the
/// `n` parts that have paths there, of weights `k_i`: `Σ k_i (L_i − L)² / (Σ k_i · (n − 1))`, square-rooted), and the
/// total paths per pixel (sums of `k_i`). `None` if the sizes differ or there is no part.
pub fn merge_parts(parts: &[&image::Rgba32FImage]) -> Option<Merged> {
    let first = parts.first()?;
    let (w, h) = first.dimensions();
    if parts.iter().any(|p| p.dimensions() != (w, h)) {
        return None;
    }
    let mut image = image::Rgba32FImage::new(w, h);
    let mut standard_error = vec![0.0f64; (w * h) as usize];
    let mut paths = vec![0.0f64; (w * h) as usize];
    for (i, (x, y, out)) in image.enumerate_pixels_mut().enumerate() {
        let mut sum = glam::DVec3::ZERO;
        let mut kept = 0.0f64;
        for p in parts {
            let [r, g, b, k] = p.get_pixel(x, y).0;
            let k = f64::from(k.max(0.0));
            sum += glam::DVec3::new(f64::from(r), f64::from(g), f64::from(b)) * k;
            kept += k;
        }
        let mean = if kept > 0.0 {
            sum / kept
        } else {
            glam::DVec3::ZERO
        };
        let c = mean.min(glam::DVec3::splat(HDR_MAX)).as_vec3();
        *out = image::Rgba([c.x, c.y, c.z, 1.0]);
        paths[i] = kept;
        let sharing = parts
            .iter()
            .filter(|p| p.get_pixel(x, y).0[3] > 0.0)
            .count();
        if sharing > 1 && kept > 0.0 {
            let lum = |v: glam::DVec3| 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
            let l = lum(mean);
            let spread: f64 = parts
                .iter()
                .map(|p| {
                    let [r, g, b, k] = p.get_pixel(x, y).0;
                    let li = lum(glam::DVec3::new(f64::from(r), f64::from(g), f64::from(b)));
                    f64::from(k.max(0.0)) * (li - l).powi(2)
                })
                .sum();
            standard_error[i] = (spread / (kept * (sharing - 1) as f64)).sqrt();
        }
    }
    Some(Merged {
        image,
        standard_error,
        paths,
    })
}

/// What [`merge_parts`] returns.
#[derive(Clone, Debug)]
pub struct Merged {
    /// The merged image (as [`render`] writes it).
    pub image: image::Rgba32FImage,
    /// Per pixel (row-major), the standard error of its mean luminance from the spread
    /// between the parts (0 with one part).
    pub standard_error: Vec<f64>,
    /// Per pixel, the finite paths behind its mean.
    pub paths: Vec<f64>,
}

/// Ray-traces the ambient occlusion of `scene` within `radius_m` metres
/// ([`TraceScene::ambient_occlusion`]): per pixel, the mean of `samples_per_pixel`
/// cosine-distributed rays from the first surface, as grey (0 fully occluded, 1 open;
/// 1 where the camera sees no surface). The ground truth of the AO pass.
pub fn render_ambient_occlusion(
    scene: &TraceScene,
    options: &ReferenceOptions,
    radius_m: f32,
    progress: &(dyn Fn(u32) + Sync),
) -> Traced {
    let all = 0..options.samples_per_pixel.max(1);
    along_camera_rays(scene, options, all, false, progress, &|origin, dir, rng| {
        Vec3::splat(scene.ambient_occlusion(origin, dir, radius_m, rng))
    })
}

/// [`accumulate`] of `sample(origin, direction, rng)` along one camera ray per sample,
/// through a uniformly jittered position in the pixel and a lens sample.
fn along_camera_rays(
    scene: &TraceScene,
    options: &ReferenceOptions,
    samples: std::ops::Range<u32>,
    part: bool,
    progress: &(dyn Fn(u32) + Sync),
    sample: &(dyn Fn(Vec3, Vec3, &mut Rng) -> Vec3 + Sync),
) -> Traced {
    let size = Vec2::new(options.size.0.max(1) as f32, options.size.1.max(1) as f32);
    accumulate(options, samples, part, progress, &|pixel, rng| {
        let jitter = rng.pair();
        let lens = rng.pair();
        let (origin, dir) = scene.camera_ray(pixel + jitter, size, lens);
        sample(origin, dir, rng)
    })
}

/// The guarded mean of the values of `sample(pixel corner, rng)` for the sample indices
/// `samples` of each pixel (see [`render`]); a `part` keeps the mean unclamped and puts
/// the count of finite paths in alpha ([`render_part`]).
fn accumulate(
    options: &ReferenceOptions,
    samples: std::ops::Range<u32>,
    part: bool,
    progress: &(dyn Fn(u32) + Sync),
    sample: &(dyn Fn(Vec2, &mut Rng) -> Vec3 + Sync),
) -> Traced {
    let (w, h) = (options.size.0.max(1), options.size.1.max(1));
    let done = AtomicU32::new(0);
    let rows: Vec<(Vec<f32>, u64)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut row = Vec::with_capacity(w as usize * 4);
            let mut dropped = 0u64;
            for x in 0..w {
                let pixel = y * w + x;
                let mut sum = glam::DVec3::ZERO;
                let mut kept = 0u32;
                for s in samples.clone() {
                    let mut rng = Rng::new(options.seed, pixel, s);
                    let l = sample(Vec2::new(x as f32, y as f32), &mut rng);
                    if l.is_finite() {
                        sum += l.as_dvec3();
                        kept += 1;
                    } else {
                        dropped += 1;
                    }
                }
                let mean = sum / f64::from(kept.max(1));
                if part {
                    let c = mean.as_vec3();
                    row.extend([c.x, c.y, c.z, kept as f32]);
                } else {
                    let c = mean.min(glam::DVec3::splat(HDR_MAX)).as_vec3();
                    row.extend([c.x, c.y, c.z, 1.0]);
                }
            }
            progress(done.fetch_add(1, Ordering::Relaxed) + 1);
            (row, dropped)
        })
        .collect();
    let dropped_samples = rows.iter().map(|(_, d)| d).sum();
    let pixels: Vec<f32> = rows.into_iter().flat_map(|(row, _)| row).collect();
    let image = image::Rgba32FImage::from_raw(w, h, pixels)
        .unwrap_or_else(|| image::Rgba32FImage::new(w, h));
    Traced {
        image,
        dropped_samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_cover_every_item_once() {
        for (total, count) in [(8, 4), (10, 3), (2, 5), (1_048_576, 7)] {
            let mut next = 0;
            for index in 0..count {
                let r = Shard { index, count }.range(total);
                assert_eq!(r.start, next, "{total} items in {count}");
                next = r.end;
            }
            assert_eq!(next, total);
        }
        assert_eq!(Shard { index: 1, count: 4 }.range(8), 2..4);
        assert!(Shard { index: 0, count: 5 }.range(2).is_empty());
    }

    #[test]
    fn parts_merge_by_their_path_counts() {
        let part =
            |v: f32, k: f32| image::Rgba32FImage::from_pixel(2, 1, image::Rgba([v, v, v, k]));
        let (a, b, none) = (part(1.0, 3.0), part(5.0, 1.0), part(7.0, 0.0));
        let merged = merge_parts(&[&a, &b, &none]).expect("same sizes");
        assert_eq!(merged.image.get_pixel(0, 0).0, [2.0, 2.0, 2.0, 1.0]);
        assert_eq!(merged.paths, [4.0, 4.0]);
        // Luminances 1 (3 paths) and 5 (1 path) about the mean 2, over two parts that
        // have paths: √((3·1² + 1·3²) / (4 · 1)) = √3; the part without paths counts
        // for nothing.
        for e in &merged.standard_error {
            assert!((e - 3f64.sqrt()).abs() < 1e-9, "standard error {e}");
        }
        let alone = merge_parts(&[&a, &none]).expect("same sizes");
        assert_eq!(alone.standard_error, [0.0, 0.0]);
        let huge = part(1e6, 1.0);
        assert_eq!(
            merge_parts(&[&huge]).expect("one").image.get_pixel(0, 0).0[0],
            65504.0
        );
        assert!(merge_parts(&[&a, &image::Rgba32FImage::new(1, 1)]).is_none());
        assert!(merge_parts(&[]).is_none());
    }
}

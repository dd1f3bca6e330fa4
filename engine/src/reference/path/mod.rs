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

pub mod bvh;
pub mod dielectric;
pub mod integrator;
pub mod microfacet;
pub mod rng;
pub mod scene;
pub mod textures;

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

pub use rng::Rng;

/// Names the path tracer's estimator in the file names of cached references
/// (`lumen tradeoff`), so that a reference traced by an earlier estimator, with other
/// noise, is traced again rather than reused: `lc` is next-event estimation with light
/// connections.
pub const ESTIMATOR: &str = "lc";
pub use scene::{
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
    along_camera_rays(scene, options, progress, &|origin, dir, rng| {
        scene.radiance(origin, dir, options.max_bounces.max(1), rng)
    })
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
    along_camera_rays(scene, options, progress, &|origin, dir, rng| {
        Vec3::splat(scene.ambient_occlusion(origin, dir, radius_m, rng))
    })
}

/// [`accumulate`] of `sample(origin, direction, rng)` along one camera ray per sample,
/// through a uniformly jittered position in the pixel and a lens sample.
fn along_camera_rays(
    scene: &TraceScene,
    options: &ReferenceOptions,
    progress: &(dyn Fn(u32) + Sync),
    sample: &(dyn Fn(Vec3, Vec3, &mut Rng) -> Vec3 + Sync),
) -> Traced {
    let size = Vec2::new(options.size.0.max(1) as f32, options.size.1.max(1) as f32);
    accumulate(options, progress, &|pixel, rng| {
        let jitter = rng.pair();
        let lens = rng.pair();
        let (origin, dir) = scene.camera_ray(pixel + jitter, size, lens);
        sample(origin, dir, rng)
    })
}

/// The guarded mean of `samples_per_pixel` values of `sample(pixel corner, rng)` per
/// pixel (see [`render`]).
fn accumulate(
    options: &ReferenceOptions,
    progress: &(dyn Fn(u32) + Sync),
    sample: &(dyn Fn(Vec2, &mut Rng) -> Vec3 + Sync),
) -> Traced {
    let (w, h) = (options.size.0.max(1), options.size.1.max(1));
    let spp = options.samples_per_pixel.max(1);
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
                for s in 0..spp {
                    let mut rng = Rng::new(options.seed, pixel, s);
                    let l = sample(Vec2::new(x as f32, y as f32), &mut rng);
                    if l.is_finite() {
                        sum += l.as_dvec3();
                        kept += 1;
                    } else {
                        dropped += 1;
                    }
                }
                let c = (sum / f64::from(kept.max(1)))
                    .min(glam::DVec3::splat(HDR_MAX))
                    .as_vec3();
                row.extend([c.x, c.y, c.z, 1.0]);
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

//! The shadow atlas, and packing square shadow views of power-of-two sizes into it.
//!
//! Sorted from largest to smallest, power-of-two squares laid out along a Z-order (Morton)
//! curve never overlap and leave no holes: the atlas side is the smallest power of two
//! whose area holds them all.
//!
//! The atlas ([`ShadowAtlas`]) is not a graph resource: it is a cache that the frame and
//! the probe captures share (each capture's sun view is the frame's, so the frame keeps
//! what a capture drew, [`super::pass`]), and the graph allocates per frame and per
//! capture. It lives beside the scene buffers: the shadow pass writes it, the passes that
//! look shadows up bind it ([`super::lookups`]).

use crate::render::device::Gpu;
use crate::render::gpu_types::GpuShadowView;
use crate::render::scene_buffers::GrowableBuffer;
use crate::render::targets::Target;
use bevy_ecs::prelude::Resource;

/// Format of the shadow atlas.
pub const ATLAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Shadow views the uniform copy holds (96 bytes each: 12 KiB).
pub const UNIFORM_SHADOW_VIEWS: u32 = 128;

/// The shadow atlas and the views it holds: what the passes that look shadows up bind.
#[derive(Resource)]
pub struct ShadowAtlas {
    /// The depth atlas (1×1 until a frame has shadows).
    pub atlas: Target,
    /// A comparison sampler (less-equal, bilinear: hardware 2×2 PCF) for the atlas.
    pub sampler: wgpu::Sampler,
    /// [`GpuShadowView`] per view.
    pub gpu_views: GrowableBuffer,
    /// The first [`UNIFORM_SHADOW_VIEWS`] views again, as a uniform buffer, read when every
    /// view fits (uniform loads are cheaper on lavapipe, as for the lights).
    pub views_uniform: wgpu::Buffer,
    /// The atlas layout of the frame that last drew it.
    pub layout: AtlasLayout,
}

impl ShadowAtlas {
    /// An empty 1×1 atlas and room for 16 views.
    pub fn new(gpu: &Gpu) -> ShadowAtlas {
        ShadowAtlas {
            atlas: atlas_target(gpu, 1),
            sampler: gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            gpu_views: GrowableBuffer::new(
                gpu,
                "shadow views",
                16 * std::mem::size_of::<GpuShadowView>() as u64,
            ),
            views_uniform: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shadow views (uniform)"),
                size: u64::from(UNIFORM_SHADOW_VIEWS) * std::mem::size_of::<GpuShadowView>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            layout: AtlasLayout {
                side: 1,
                rects: Vec::new(),
                halvings: 0,
            },
        }
    }

    /// Makes the atlas `side` texels square, unless it is; returns whether it made it anew
    /// (what it held is gone).
    pub fn fit(&mut self, gpu: &Gpu, side: u32) -> bool {
        if self.atlas.texture.width() == side {
            return false;
        }
        self.atlas = atlas_target(gpu, side);
        true
    }
}

fn atlas_target(gpu: &Gpu, side: u32) -> Target {
    Target::new(gpu, "shadow atlas", (side, side), ATLAS_FORMAT)
}

/// Where one view landed in the atlas, in texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AtlasRect {
    /// Left edge.
    pub x: u32,
    /// Top edge.
    pub y: u32,
    /// Side.
    pub size: u32,
}

/// A packing: the atlas side and one rectangle per requested view (in request order).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtlasLayout {
    /// Side of the square atlas in texels.
    pub side: u32,
    /// Rectangles, in the order of the requests.
    pub rects: Vec<AtlasRect>,
    /// How many times every request was halved to fit `max_side` (0 = as requested).
    pub halvings: u32,
}

/// Smallest side a view is shrunk to when the atlas is full.
pub const MIN_VIEW_SIZE: u32 = 64;

fn morton_decode(mut code: u64) -> (u32, u32) {
    let (mut x, mut y) = (0u32, 0u32);
    let mut bit = 0;
    while code != 0 {
        x |= ((code & 1) as u32) << bit;
        y |= (((code >> 1) & 1) as u32) << bit;
        code >>= 2;
        bit += 1;
    }
    (x, y)
}

/// Packs views of the requested sides (each rounded up to a power of two, at least
/// [`MIN_VIEW_SIZE`]) into an atlas of side at most `max_side`. If they do not fit, every
/// request is halved (down to [`MIN_VIEW_SIZE`]) until they do; if even that fails, the
/// views that do not fit get no rectangle and the function returns `None` for them.
pub fn pack(requests: &[u32], max_side: u32) -> (AtlasLayout, Vec<Option<usize>>) {
    let m = max_side.max(MIN_VIEW_SIZE);
    let max_side = if m.is_power_of_two() {
        m
    } else {
        m.next_power_of_two() / 2
    };
    let mut halvings = 0;
    loop {
        let sizes: Vec<u32> = requests
            .iter()
            .map(|&r| {
                (r.max(MIN_VIEW_SIZE).next_power_of_two() >> halvings)
                    .max(MIN_VIEW_SIZE)
                    .min(max_side)
            })
            .collect();
        let area: u64 = sizes.iter().map(|&s| u64::from(s) * u64::from(s)).sum();
        let largest = sizes.iter().copied().max().unwrap_or(MIN_VIEW_SIZE);
        let mut side = largest;
        while u64::from(side) * u64::from(side) < area && side < max_side {
            side *= 2;
        }
        let fits = u64::from(side) * u64::from(side) >= area;
        let all_minimal = sizes.iter().all(|&s| s == MIN_VIEW_SIZE);
        if fits || all_minimal {
            let mut order: Vec<usize> = (0..sizes.len()).collect();
            order.sort_by_key(|&i| std::cmp::Reverse(sizes[i]));
            let mut rects = vec![
                AtlasRect {
                    x: 0,
                    y: 0,
                    size: 0
                };
                sizes.len()
            ];
            let mut placed = vec![None; sizes.len()];
            let mut used: u64 = 0;
            for (slot, &i) in order.iter().enumerate() {
                let s = u64::from(sizes[i]);
                if used + s * s > u64::from(side) * u64::from(side) {
                    continue;
                }
                let (bx, by) = morton_decode(used / (s * s));
                rects[i] = AtlasRect {
                    x: bx * sizes[i],
                    y: by * sizes[i],
                    size: sizes[i],
                };
                placed[i] = Some(slot);
                used += s * s;
            }
            return (
                AtlasLayout {
                    side,
                    rects,
                    halvings,
                },
                placed,
            );
        }
        halvings += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn overlaps(a: &AtlasRect, b: &AtlasRect) -> bool {
        a.x < b.x + b.size && b.x < a.x + a.size && a.y < b.y + b.size && b.y < a.y + a.size
    }

    #[test]
    fn mixed_sizes_pack_without_overlap() {
        let requests = [2048, 512, 512, 512, 512, 512, 512, 1024, 1000, 300];
        let (layout, placed) = pack(&requests, 8192);
        assert_eq!(layout.halvings, 0);
        assert!(placed.iter().all(|p| p.is_some()));
        // 2048² + 6·512² + 2·1024² + 512² = 4194304 + 1572864 + 2097152 + 262144 → 4096².
        assert_eq!(layout.side, 4096);
        for (i, a) in layout.rects.iter().enumerate() {
            assert!(a.size.is_power_of_two());
            assert!(a.x + a.size <= layout.side && a.y + a.size <= layout.side);
            for b in &layout.rects[i + 1..] {
                assert!(!overlaps(a, b), "{a:?} overlaps {b:?}");
            }
        }
        assert_eq!(layout.rects[8].size, 1024);
        assert_eq!(layout.rects[9].size, 512);
    }

    #[test]
    fn too_much_is_halved_until_it_fits() {
        let requests = vec![4096; 8];
        let (layout, placed) = pack(&requests, 8192);
        assert_eq!(layout.side, 8192);
        assert_eq!(layout.halvings, 1);
        assert!(placed.iter().all(|p| p.is_some()));
        assert!(layout.rects.iter().all(|r| r.size == 2048));
    }

    #[test]
    fn empty_and_degenerate_requests() {
        let (layout, placed) = pack(&[], 4096);
        assert!(layout.rects.is_empty() && placed.is_empty());
        let (layout, _) = pack(&[0, 1, 70], 4096);
        assert!(layout.rects.iter().all(|r| r.size >= MIN_VIEW_SIZE));
        // A non-power-of-two maximum is rounded down.
        let (layout, _) = pack(&[4096], 5000);
        assert_eq!(layout.side, 4096);
    }

    #[test]
    fn views_that_cannot_fit_get_no_rect() {
        let requests = vec![64; 20];
        let (layout, placed) = pack(&requests, 256);
        assert_eq!(layout.side, 256);
        assert_eq!(placed.iter().filter(|p| p.is_some()).count(), 16);
    }
}

//! The textures and buffers a frame renders into, allocated from the plan's assignment
//! ([`crate::render::graph::resources`]): every texture or buffer slot that a running
//! pass uses gets a view of the physical resource the plan gave it. Physical resources
//! are kept from frame to frame while the plan asks for the same shapes, so bind groups
//! built from their views stay valid ([`crate::render::bindings::CachedGroup`]); a shape
//! no longer asked for is freed.

use crate::render::device::Gpu;
use crate::render::graph::Slot;
use crate::render::graph::resources::{Assignment, Shape};
use bevy_ecs::prelude::Resource;

pub use crate::render::graph::slots::{
    DEPTH_FORMAT, GBUFFER0_FORMAT, GBUFFER1_FORMAT, GBUFFER2_FORMAT,
};

/// The usages every graph texture has: render to it, sample it, copy it both ways.
const TEXTURE_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::RENDER_ATTACHMENT
    .union(wgpu::TextureUsages::TEXTURE_BINDING)
    .union(wgpu::TextureUsages::COPY_SRC)
    .union(wgpu::TextureUsages::COPY_DST);

/// One texture and its default view, for what the graph does not allocate (the display
/// image, probe faces).
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// A view of the whole texture.
    pub view: wgpu::TextureView,
}

impl Target {
    /// A 2D texture that can be rendered to, bound for sampling, copied to and read back.
    pub fn new(gpu: &Gpu, label: &str, size: (u32, u32), format: wgpu::TextureFormat) -> Target {
        let texture = create_texture(gpu, label, size, format, 1, TEXTURE_USAGE);
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Target { texture, view }
    }
}

fn create_texture(
    gpu: &Gpu,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    levels: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A physical texture or buffer on the GPU.
struct PhysicalGpu {
    shape: Shape,
    resource: Resource_,
}

/// What a physical resource is.
enum Resource_ {
    Texture {
        texture: wgpu::Texture,
        /// Views by (first level, level count), made once each.
        views: Vec<((u32, u32), wgpu::TextureView)>,
    },
    Buffer(wgpu::Buffer),
}

impl PhysicalGpu {
    fn new(gpu: &Gpu, label: &str, shape: Shape) -> PhysicalGpu {
        let resource = match shape {
            Shape::Texture(class, levels, usage) => {
                let texture = create_texture(
                    gpu,
                    label,
                    class.size,
                    class.format,
                    levels,
                    TEXTURE_USAGE | usage,
                );
                Resource_::Texture {
                    texture,
                    views: Vec::new(),
                }
            }
            Shape::Buffer(bytes, usage) => {
                Resource_::Buffer(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: bytes.next_multiple_of(16),
                    usage: usage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }))
            }
        };
        PhysicalGpu { shape, resource }
    }

    /// The view of levels `base..base + count`, made on first use.
    fn view(&mut self, base: u32, count: u32) -> Option<wgpu::TextureView> {
        let Resource_::Texture { texture, views } = &mut self.resource else {
            return None;
        };
        if let Some((_, v)) = views.iter().find(|(k, _)| *k == (base, count)) {
            return Some(v.clone());
        }
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            base_mip_level: base,
            mip_level_count: Some(count),
            ..Default::default()
        });
        views.push(((base, count), view.clone()));
        Some(view)
    }
}

/// What one slot is bound to this frame.
enum Bound {
    Texture {
        texture: wgpu::Texture,
        size: (u32, u32),
        /// Its levels, then one view per level.
        view: wgpu::TextureView,
        levels: Vec<wgpu::TextureView>,
        fresh: bool,
    },
    Buffer {
        buffer: wgpu::Buffer,
        fresh: bool,
    },
}

/// The frame's textures and buffers, by slot.
pub struct FrameTargets {
    /// The output's size in pixels.
    pub size: (u32, u32),
    /// Format of the HDR colour slot ([`crate::quality::HdrPrecision`]).
    pub hdr_format: wgpu::TextureFormat,
    slots: Vec<(Slot, Bound)>,
}

impl FrameTargets {
    fn bound(&self, slot: Slot) -> Option<&Bound> {
        self.slots.iter().find(|(s, _)| *s == slot).map(|(_, b)| b)
    }

    /// The view of `slot`'s texture (every level it has), if this frame has it.
    pub fn view(&self, slot: Slot) -> Option<&wgpu::TextureView> {
        match self.bound(slot)? {
            Bound::Texture { view, .. } => Some(view),
            Bound::Buffer { .. } => None,
        }
    }

    /// The views of several slots, if this frame has every one of them.
    pub fn views<const N: usize>(&self, slots: [Slot; N]) -> Option<[&wgpu::TextureView; N]> {
        let views: Vec<&wgpu::TextureView> =
            slots.iter().map(|s| self.view(*s)).collect::<Option<_>>()?;
        views.try_into().ok()
    }

    /// The view of one mip level of `slot`'s texture.
    pub fn level(&self, slot: Slot, level: u32) -> Option<&wgpu::TextureView> {
        match self.bound(slot)? {
            Bound::Texture { levels, .. } => levels.get(level as usize),
            Bound::Buffer { .. } => None,
        }
    }

    /// The mip levels `slot`'s texture has.
    pub fn level_count(&self, slot: Slot) -> u32 {
        match self.bound(slot) {
            Some(Bound::Texture { levels, .. }) => levels.len() as u32,
            _ => 0,
        }
    }

    /// `slot`'s texture, for copies (it may hold other slots in other levels or at other
    /// times of the frame: copy only what the slot covers).
    pub fn texture(&self, slot: Slot) -> Option<&wgpu::Texture> {
        match self.bound(slot)? {
            Bound::Texture { texture, .. } => Some(texture),
            Bound::Buffer { .. } => None,
        }
    }

    /// The size in texels of level 0 of `slot`'s texture.
    pub fn extent(&self, slot: Slot) -> Option<(u32, u32)> {
        match self.bound(slot)? {
            Bound::Texture { size, .. } => Some(*size),
            Bound::Buffer { .. } => None,
        }
    }

    /// `slot`'s buffer, if this frame has it.
    pub fn buffer(&self, slot: Slot) -> Option<&wgpu::Buffer> {
        match self.bound(slot)? {
            Bound::Buffer { buffer, .. } => Some(buffer),
            Bound::Texture { .. } => None,
        }
    }

    /// Records a copy of level 0 of `from`'s texture into `to`'s (both this frame's, of one
    /// size and format); `false` when either is missing.
    pub fn copy(&self, encoder: &mut wgpu::CommandEncoder, from: Slot, to: Slot) -> bool {
        let (Some(source), Some(destination), Some((w, h))) =
            (self.texture(from), self.texture(to), self.extent(from))
        else {
            return false;
        };
        encoder.copy_texture_to_texture(
            source.as_image_copy(),
            destination.as_image_copy(),
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        true
    }

    /// Whether `slot`'s texture or buffer was created for this frame: a history that is
    /// fresh holds nothing yet.
    pub fn fresh(&self, slot: Slot) -> bool {
        match self.bound(slot) {
            Some(Bound::Texture { fresh, .. } | Bound::Buffer { fresh, .. }) => *fresh,
            None => true,
        }
    }
}

/// The frame's textures and buffers, and the physical resources kept between frames.
/// Probe captures render through a second set, swapped in while they run
/// ([`crate::render::indirect::probe_volume`]).
#[derive(Resource, Default)]
pub struct RenderTargets {
    /// This frame's, once a frame was prepared.
    pub current: Option<FrameTargets>,
    /// Shared physical resources, in the assignment's order.
    pool: Vec<PhysicalGpu>,
    /// Histories and resources that keep the last frame's content, by slot name.
    kept: Vec<(&'static str, PhysicalGpu)>,
}

impl RenderTargets {
    /// Allocates what `assignment` asks for, for an output of `size` pixels, keeping the
    /// physical resources of the last frame whose shapes it asks for again.
    pub fn allocate(
        &mut self,
        gpu: &Gpu,
        size: (u32, u32),
        hdr_format: wgpu::TextureFormat,
        assignment: &Assignment,
    ) {
        let mut old = std::mem::take(&mut self.pool);
        let mut old_kept = std::mem::take(&mut self.kept);
        let mut fresh = vec![false; assignment.physical.len()];
        // Each physical resource: the kept one of its slot, an old one of the same shape,
        // or a new one.
        let mut placed: Vec<Option<usize>> = vec![None; assignment.physical.len()];
        let mut kept_at: Vec<Option<usize>> = vec![None; assignment.physical.len()];
        for (i, p) in assignment.physical.iter().enumerate() {
            let label = p.holds.first().copied().unwrap_or("graph resource");
            if let Some(name) = p.kept {
                let reuse = old_kept
                    .iter()
                    .position(|(n, g)| *n == name && g.shape == p.shape);
                let gpu_resource = match reuse {
                    Some(at) => old_kept.swap_remove(at).1,
                    None => {
                        fresh[i] = true;
                        PhysicalGpu::new(gpu, label, p.shape)
                    }
                };
                self.kept.push((name, gpu_resource));
                kept_at[i] = Some(self.kept.len() - 1);
            } else {
                let reuse = old.iter().position(|g| g.shape == p.shape);
                let gpu_resource = match reuse {
                    Some(at) => old.remove(at),
                    None => {
                        fresh[i] = true;
                        PhysicalGpu::new(gpu, label, p.shape)
                    }
                };
                self.pool.push(gpu_resource);
                placed[i] = Some(self.pool.len() - 1);
            }
        }
        let mut slots = Vec::with_capacity(assignment.resources.len());
        for r in &assignment.resources {
            let p = r.physical;
            let physical = match (placed[p], kept_at[p]) {
                (Some(at), _) => &mut self.pool[at],
                (None, Some(at)) => &mut self.kept[at].1,
                (None, None) => continue,
            };
            let bound = match (r.shape, &physical.resource) {
                (Shape::Texture(class, levels, _), Resource_::Texture { texture, .. }) => {
                    let texture = texture.clone();
                    let (Some(view), Some(levels)) = (
                        physical.view(0, levels),
                        (0..levels)
                            .map(|l| physical.view(l, 1))
                            .collect::<Option<Vec<_>>>(),
                    ) else {
                        continue;
                    };
                    Bound::Texture {
                        texture,
                        size: class.size,
                        view,
                        levels,
                        fresh: fresh[p],
                    }
                }
                (Shape::Buffer(..), Resource_::Buffer(buffer)) => Bound::Buffer {
                    buffer: buffer.clone(),
                    fresh: fresh[p],
                },
                _ => continue,
            };
            slots.push((r.slot, bound));
        }
        self.current = Some(FrameTargets {
            size,
            hdr_format,
            slots,
        });
    }
}

//! The textures a frame renders into (the G-buffer, depth, HDR colour, …), allocated for
//! the slots the frame graph's running passes use.

use crate::render::device::Gpu;
use crate::render::graph::{Slot, SlotKind, TargetFormat};
use bevy_ecs::prelude::Resource;

pub use crate::render::graph::slots::{
    DEPTH_FORMAT, GBUFFER0_FORMAT, GBUFFER1_FORMAT, GBUFFER2_FORMAT,
};

/// One render target and its default view.
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// A view of the whole texture.
    pub view: wgpu::TextureView,
}

impl Target {
    /// A 2D texture that can be rendered to, bound for sampling, copied to and read back.
    pub fn new(gpu: &Gpu, label: &str, size: (u32, u32), format: wgpu::TextureFormat) -> Target {
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Target { texture, view }
    }
}

/// The frame targets the graph allocated, at the output's size: one per
/// [`SlotKind::Target`] slot that a pass running this frame uses.
pub struct FrameTargets {
    /// Size in pixels.
    pub size: (u32, u32),
    /// Format of the HDR colour slot ([`crate::quality::HdrPrecision`]).
    pub hdr_format: wgpu::TextureFormat,
    /// Bumped whenever a target is created, so passes can rebuild bind groups.
    pub generation: u64,
    targets: Vec<(Slot, Target)>,
}

impl FrameTargets {
    /// The target of `slot`, if this frame has one.
    pub fn get(&self, slot: Slot) -> Option<&Target> {
        self.targets
            .iter()
            .find(|(s, _)| *s == slot)
            .map(|(_, t)| t)
    }

    /// The view of `slot`'s target, if this frame has one.
    pub fn view(&self, slot: Slot) -> Option<&wgpu::TextureView> {
        self.get(slot).map(|t| &t.view)
    }

    /// The views of several slots, if this frame has every one of them.
    pub fn views<const N: usize>(&self, slots: [Slot; N]) -> Option<[&wgpu::TextureView; N]> {
        let views: Vec<&wgpu::TextureView> =
            slots.iter().map(|s| self.view(*s)).collect::<Option<_>>()?;
        views.try_into().ok()
    }
}

/// The frame's targets, created on first use and recreated when the output size or the
/// HDR format changes. A target no pass uses this frame is kept for the next frames that
/// use it. Probe captures render through a second set, swapped in while they run
/// ([`crate::render::indirect::irradiance_volume`]).
#[derive(Resource, Default)]
pub struct RenderTargets {
    /// Current targets, if any frame was prepared.
    pub current: Option<FrameTargets>,
}

/// A generation no set of targets has had: unique across every [`RenderTargets`], so a
/// bind group built for one set is never mistaken for another's.
fn next_generation() -> u64 {
    static GENERATION: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    GENERATION.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl RenderTargets {
    /// Makes sure a target exists at `size` for each [`SlotKind::Target`] slot of `slots`,
    /// the HDR one in `hdr_format`.
    pub fn ensure(
        &mut self,
        gpu: &Gpu,
        size: (u32, u32),
        hdr_format: wgpu::TextureFormat,
        slots: impl IntoIterator<Item = Slot>,
    ) {
        if self
            .current
            .as_ref()
            .is_none_or(|t| t.size != size || t.hdr_format != hdr_format)
        {
            self.current = Some(FrameTargets {
                size,
                hdr_format,
                generation: next_generation(),
                targets: Vec::new(),
            });
        }
        let Some(current) = self.current.as_mut() else {
            return;
        };
        for slot in slots {
            let SlotKind::Target(format) = slot.kind else {
                continue;
            };
            if current.get(slot).is_some() {
                continue;
            }
            let format = match format {
                TargetFormat::Fixed(f) => f,
                TargetFormat::Hdr => hdr_format,
            };
            current.generation = next_generation();
            current
                .targets
                .push((slot, Target::new(gpu, slot.name, size, format)));
        }
    }
}

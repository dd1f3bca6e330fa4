//! The textures a frame renders into: the G-buffer, depth and the HDR target.

use crate::render::device::Gpu;
use bevy_ecs::prelude::Resource;

/// G-buffer target 0: base colour and AO. The base colour is sRGB-encoded by the shader
/// with the exact curve (`srgb_encode`) rather than by an `*Srgb` format, because
/// drivers may approximate the hardware conversion: llvmpipe's decode is off by up to
/// 2.5 % (measured at code 5; −0.13 % at code 231).
pub const GBUFFER0_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// G-buffer target 1: octahedral normal, perceptual roughness, metallic.
pub const GBUFFER1_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// G-buffer target 2: pre-exposed emissive and specular level.
pub const GBUFFER2_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Depth, reversed Z.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

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

/// Every intermediate target of a frame, at the output's size.
pub struct FrameTargets {
    /// Size in pixels.
    pub size: (u32, u32),
    /// Base colour + AO.
    pub gbuffer0: Target,
    /// Normal, roughness, metallic.
    pub gbuffer1: Target,
    /// Emissive, specular level.
    pub gbuffer2: Target,
    /// Depth.
    pub depth: Target,
    /// HDR luminance (pre-exposed) and coverage, in `hdr_format`.
    pub hdr: Target,
    /// Format of `hdr` ([`crate::quality::HdrPrecision`]).
    pub hdr_format: wgpu::TextureFormat,
    /// Bumped whenever the targets are recreated, so passes can rebuild bind groups.
    pub generation: u64,
}

/// The frame's targets, created on first use and recreated when the output size changes.
#[derive(Resource, Default)]
pub struct RenderTargets {
    /// Current targets, if any frame was prepared.
    pub current: Option<FrameTargets>,
    generation: u64,
}

impl RenderTargets {
    /// Makes sure the targets exist at `size` with an HDR target of `hdr_format`.
    pub fn ensure(&mut self, gpu: &Gpu, size: (u32, u32), hdr_format: wgpu::TextureFormat) {
        if self
            .current
            .as_ref()
            .is_some_and(|t| t.size == size && t.hdr_format == hdr_format)
        {
            return;
        }
        self.generation += 1;
        self.current = Some(FrameTargets {
            size,
            gbuffer0: Target::new(gpu, "gbuffer0 base colour + AO", size, GBUFFER0_FORMAT),
            gbuffer1: Target::new(
                gpu,
                "gbuffer1 normal + roughness + metallic",
                size,
                GBUFFER1_FORMAT,
            ),
            gbuffer2: Target::new(
                gpu,
                "gbuffer2 emissive + specular level",
                size,
                GBUFFER2_FORMAT,
            ),
            depth: Target::new(gpu, "depth", size, DEPTH_FORMAT),
            hdr: Target::new(gpu, "hdr", size, hdr_format),
            hdr_format,
            generation: self.generation,
        });
    }
}

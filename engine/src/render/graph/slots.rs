//! The frame's core slots, shared by many passes, and their formats.

use super::{Slot, SlotKind, TargetFormat, TextureDesc};

/// G-buffer target 0: base colour and AO. The base colour is sRGB-encoded by the shader
/// with the exact curve (`srgb_encode`) rather than by an `*Srgb` format, because
/// drivers may approximate the hardware conversion: llvmpipe's decode is off by up to
/// 2.5 % (measured at code 5; −0.13 % at code 231).
pub const GBUFFER0_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// G-buffer target 1: octahedral normal, perceptual roughness, metallic.
pub const GBUFFER1_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// G-buffer target 2: pre-exposed emissive and specular level.
pub const GBUFFER2_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Motion vectors: two f16 channels of pixels (0.03 px steps up to 64 px).
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;
/// Depth, reversed Z.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// G-buffer 0: base colour (sRGB-encoded) and ambient occlusion.
pub const GBUFFER_BASE_COLOR: Slot = Slot::texture(
    "gbuffer0 base colour + AO",
    TextureDesc::full(TargetFormat::Fixed(GBUFFER0_FORMAT)).exported(),
);
/// G-buffer 1: octahedral normal, perceptual roughness, metallic.
pub const GBUFFER_NORMAL: Slot = Slot::texture(
    "gbuffer1 normal + roughness + metallic",
    TextureDesc::full(TargetFormat::Fixed(GBUFFER1_FORMAT)).exported(),
);
/// G-buffer 2: pre-exposed emissive luminance, specular level.
pub const GBUFFER_EMISSIVE: Slot = Slot::texture(
    "gbuffer2 emissive + specular level",
    TextureDesc::full(TargetFormat::Fixed(GBUFFER2_FORMAT)).exported(),
);
/// Screen motion in pixels since the previous frame (rg, y down), without jitter, of
/// every surface the G-buffer drew; 0 on the background. Written only while TAA runs.
pub const MOTION: Slot = Slot::texture(
    "motion vectors",
    TextureDesc::full(TargetFormat::Fixed(MOTION_FORMAT)).exported(),
);
/// Depth, reversed Z (1 at the near plane, 0 at the far plane and background).
pub const DEPTH: Slot = Slot::texture(
    "depth",
    TextureDesc::full(TargetFormat::Fixed(DEPTH_FORMAT)).exported(),
);
/// Pre-exposed HDR luminance (rgb, cd/m² × exposure) and coverage (a).
pub const HDR: Slot = Slot::texture("hdr", TextureDesc::full(TargetFormat::Hdr).exported());
/// The display image (the window's surface or the headless output texture).
pub const DISPLAY: Slot = Slot {
    name: "display",
    kind: SlotKind::Output,
};

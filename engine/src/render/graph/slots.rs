//! The frame's core slots, shared by many passes, and their formats.

use super::{BufferDesc, Slot, SlotKind, TargetFormat, TextureDesc};
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
/// The specular level alone, for the reflection pass: the same f16 as G-buffer target 2's
/// alpha (negative marks an unlit surface).
pub const SPECULAR_LEVEL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// Motion vectors: two f16 channels of pixels (0.03 px steps up to 64 px).
pub const MOTION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;
/// Depth, reversed Z.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// G-buffer 0: base colour (sRGB-encoded) and ambient occlusion.
pub const GBUFFER_BASE_COLOR: Slot = Slot::texture(
    "gbuffer0 base colour + AO",
    TextureDesc::full(TargetFormat::Fixed(GBUFFER0_FORMAT)),
);
/// G-buffer 1: octahedral normal, perceptual roughness, metallic.
pub const GBUFFER_NORMAL: Slot = Slot::texture(
    "gbuffer1 normal + roughness + metallic",
    TextureDesc::full(TargetFormat::Fixed(GBUFFER1_FORMAT)),
);
/// G-buffer 2: pre-exposed emissive luminance, specular level.
pub const GBUFFER_EMISSIVE: Slot = Slot::texture(
    "gbuffer2 emissive + specular level",
    TextureDesc::full(TargetFormat::Fixed(GBUFFER2_FORMAT)),
);
/// The specular level of every surface the G-buffer drew (r; negative marks an unlit
/// surface), a copy of [`GBUFFER_EMISSIVE`]'s alpha written beside it while the reflection
/// pass runs. The reflection pass reads it instead of G-buffer 2, so G-buffer 2's memory is
/// free after lighting, for the reflection pass's copy of the lit frame.
pub const GBUFFER_SPECULAR_LEVEL: Slot = Slot::texture(
    "specular level",
    TextureDesc::full(TargetFormat::Fixed(SPECULAR_LEVEL_FORMAT)),
);
/// Screen motion in pixels since the previous frame (rg, y down), without jitter, of
/// every surface the G-buffer drew; 0 on the background. Written only while TAA runs.
pub const MOTION: Slot = Slot::texture(
    "motion vectors",
    TextureDesc::full(TargetFormat::Fixed(MOTION_FORMAT)),
);
/// Depth, reversed Z (1 at the near plane, 0 at the far plane and background).
pub const DEPTH: Slot = Slot::texture(
    "depth",
    TextureDesc::full(TargetFormat::Fixed(DEPTH_FORMAT)),
);
/// Pre-exposed HDR luminance (rgb, cd/m² × exposure) and coverage (a).
pub const HDR: Slot = Slot::texture("hdr", TextureDesc::full(TargetFormat::Hdr));
/// The display image (the window's surface or the headless output texture).
pub const DISPLAY: Slot = Slot {
    name: "display",
    kind: SlotKind::Output,
};

/// Format of the resolved AO: visibility 0..1 in 8 bits (steps of 1/255, below the noise
/// of any slice count).
pub const AO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

/// The resolved ambient occlusion at full resolution: the fraction (0..1) of
/// cosine-weighted indirect light that reaches each pixel.
pub const AMBIENT_OCCLUSION: Slot =
    Slot::target("ambient occlusion", TargetFormat::Fixed(AO_FORMAT));

/// The per-tile light lists: `TILE_STRIDE` words per 16×16-pixel tile (16 bytes while
/// culling does not run, for the passes that bind it without reading it).
pub const LIGHT_TILES: Slot = Slot::buffer(
    "light tiles",
    BufferDesc {
        usage: wgpu::BufferUsages::STORAGE,
        history: false,
    },
);

/// The shadow atlas: every shadow view's depth (the [`ShadowAtlas`](crate::render::shadow::atlas::ShadowAtlas) resource, which the
/// frame and the probe captures share).
pub const SHADOW_ATLAS: Slot = Slot::owned("shadow atlas");

/// The deformed vertex buffers: a pair per deformed entity, kept while the entity is
/// deformed ([`DeformedVertices`](crate::render::geometry::deform_pass::DeformedVertices)). Not a graph resource: their number follows the
/// scene's entities, not the frame's passes; the slot orders the passes that draw them
/// after the pass that writes them.
pub const DEFORMED_VERTICES: Slot = Slot::owned("deformed vertices");

/// The textures the application reads after the frame ([`crate::App::read_target`]): each
/// keeps a physical texture of its own, never shared, so it still holds the frame's
/// content then. HDR by default (image output and the tradeoff read it); the G-buffer,
/// depth and motion only once [`crate::App::keep_target`] asks for them, so that
/// otherwise their memory serves later passes.
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct KeptSlots(pub Vec<Slot>);

impl Default for KeptSlots {
    fn default() -> Self {
        KeptSlots(vec![HDR])
    }
}

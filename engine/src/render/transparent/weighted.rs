//! The transparent pass's order-independent mode (`--transparency weighted`): weighted
//! blended OIT ([`crate::shading::transparency`]). Its two targets, the accumulation and the
//! revealage, exist only in frames that use the mode; the resolve
//! (`shaders/transparent_resolve.wgsl`) composites them over the HDR target with "over".

use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::fullscreen_step::FullscreenStep;
use crate::render::graph::{Slot, TargetFormat};
use crate::render::pipeline_cache::Fullscreen;

/// Σ wᵢLᵢαᵢ (rgb) and Σ wᵢαᵢ (a): half floats, as McGuire & Bavoil use.
pub const ACCUM_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Π(1 − αᵢ).
pub const REVEAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

/// The accumulation target (cleared to 0 each frame the mode runs).
pub const OIT_ACCUM: Slot = Slot::target("oit accumulation", TargetFormat::Fixed(ACCUM_FORMAT));
/// The revealage target (cleared to 1).
pub const OIT_REVEAL: Slot = Slot::target("oit revealage", TargetFormat::Fixed(REVEAL_FORMAT));

/// The resolve's inputs.
pub const RESOLVE_BINDINGS: BindGroupSpec =
    BindGroupSpec::fragment("transparent resolve", declared::TRANSPARENT_RESOLVE_0);

/// Premultiplied "over": `dst ← src + dst · (1 − α_src)`, for colour and coverage.
pub const OVER: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
};

/// The accumulation's colour targets: the sum (additive) and the product of `1 − α`
/// (the revealage is multiplied by one minus what the fragment writes).
pub fn accumulate_targets() -> [Option<wgpu::ColorTargetState>; 2] {
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let reveal = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::OneMinusSrc,
        operation: wgpu::BlendOperation::Add,
    };
    [
        Some(wgpu::ColorTargetState {
            format: ACCUM_FORMAT,
            blend: Some(wgpu::BlendState {
                color: add,
                alpha: add,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        }),
        Some(wgpu::ColorTargetState {
            format: REVEAL_FORMAT,
            blend: Some(wgpu::BlendState {
                color: reveal,
                alpha: reveal,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        }),
    ]
}

/// The resolve: its pipeline per HDR format, blending with [`OVER`], and its bind group.
pub fn resolve_step(gpu: &Gpu) -> FullscreenStep {
    FullscreenStep::new(
        gpu,
        Fullscreen::new("transparent resolve", "transparent_resolve.wgsl").blending(OVER),
        &RESOLVE_BINDINGS,
    )
}

//! The output of a pass that shades one texel per `scale` × `scale` pixels (the top-left
//! pixel of each block) and only where that pixel holds geometry: the shadow mask and the
//! half-resolution irradiance volume. Its first step copies each texel's pixel depth into
//! a depth target of the output's size ([`MaskDepth::Mark`]); its second shades the
//! output, depth-tested against that copy ([`MaskDepth::Test`]), so that a software
//! rasterizer, which runs both sides of a branch, spends nothing on the background. Both
//! textures are graph resources of the pass ([`scaled`]).

use crate::render::graph::{Extent, Sizing, TargetFormat, TextureDesc};
use crate::render::pipelines::{FullscreenDraw, draw_fullscreen_pass};
use crate::render::targets::DEPTH_FORMAT;
use crate::render::timing::GpuTimer;

#[cfg(doc)]
use crate::render::pipelines::MaskDepth;

/// The description of a scaled output of `format`, or of its depth copy: sized by the
/// pass's decision ([`sizing`]).
pub const fn scaled(format: wgpu::TextureFormat) -> TextureDesc {
    TextureDesc::full(TargetFormat::Fixed(format)).at(None)
}

/// The description of the depth copy of a scaled output.
pub const DEPTH_COPY: TextureDesc = scaled(DEPTH_FORMAT);

/// The sizing of a scaled output and its depth copy: `scale` pixels per texel when the pass
/// runs, else one texel (the readers bind it without reading it).
pub fn sizing(runs: bool, scale: u32) -> Sizing {
    Sizing::Texture(
        if runs {
            Extent::Divided(scale.max(1))
        } else {
            Extent::Fixed(1, 1)
        },
        None,
    )
}

/// Records both steps into `output` with the depth copy `depth`: `names` are the steps'
/// (labels and timer scopes), `pipelines` the depth copy's and the shading's, `groups`
/// bind groups 0, 1, … of both. The output is cleared to `background`, which pixels
/// without geometry keep.
#[allow(clippy::too_many_arguments)]
pub fn record(
    encoder: &mut wgpu::CommandEncoder,
    timer: &mut GpuTimer,
    names: [&'static str; 2],
    output: &wgpu::TextureView,
    depth: &wgpu::TextureView,
    pipelines: [&wgpu::RenderPipeline; 2],
    groups: &[&wgpu::BindGroup],
    background: wgpu::Color,
) {
    let draws = [
        FullscreenDraw {
            name: names[0],
            targets: &[],
            load: wgpu::LoadOp::Clear(background),
            depth: Some((depth, wgpu::LoadOp::Clear(0.0))),
            pipeline: pipelines[0],
            groups,
        },
        FullscreenDraw {
            name: names[1],
            targets: &[output],
            load: wgpu::LoadOp::Clear(background),
            depth: Some((depth, wgpu::LoadOp::Load)),
            pipeline: pipelines[1],
            groups,
        },
    ];
    for draw in &draws {
        draw_fullscreen_pass(encoder, timer, draw);
    }
}

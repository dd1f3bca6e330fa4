//! The output of a pass that shades one texel per `scale` × `scale` pixels (the top-left
//! pixel of each block) and only where that pixel holds geometry: the shadow mask and the
//! half-resolution irradiance volume. Its first step copies each texel's pixel depth into
//! a depth target at the output's size ([`MaskDepth::Mark`]); its second shades the
//! output, depth-tested against that copy ([`MaskDepth::Test`]), so that a software
//! rasterizer, which runs both sides of a branch, spends nothing on the background.

use crate::render::device::Gpu;
use crate::render::pipelines::{FullscreenDraw, draw_fullscreen_pass};
use crate::render::targets::{DEPTH_FORMAT, Target};
use crate::render::timing::GpuTimer;

#[cfg(doc)]
use crate::render::pipelines::MaskDepth;

/// A scaled output and the depth copy its shading step is tested against.
pub struct ScaledOutput {
    /// The two steps' names: the depth copy's, then the output's (labels and timer
    /// scopes).
    names: [&'static str; 2],
    format: wgpu::TextureFormat,
    /// The output: 1 × 1 texel until the first [`ScaledOutput::fit`], so that a pass that
    /// reads it always has one to bind.
    output: Target,
    /// The depth copy, with its size.
    depth: Option<((u32, u32), Target)>,
    /// Bumped whenever the output is made anew, so readers rebuild their bind groups.
    pub generation: u64,
}

impl ScaledOutput {
    /// A 1 × 1 output of `format`; `names` are the depth copy's and the output's.
    pub fn new(gpu: &Gpu, names: [&'static str; 2], format: wgpu::TextureFormat) -> Self {
        ScaledOutput {
            names,
            format,
            output: Target::new(gpu, names[1], (1, 1), format),
            depth: None,
            generation: 0,
        }
    }

    /// Makes the output and its depth copy ⌈width/scale⌉ × ⌈height/scale⌉ for a frame of
    /// `size` pixels, unless they already are.
    pub fn fit(&mut self, gpu: &Gpu, size: (u32, u32), scale: u32) {
        let scaled = (size.0.div_ceil(scale), size.1.div_ceil(scale));
        if self.depth.as_ref().is_some_and(|(s, _)| *s == scaled) {
            return;
        }
        self.depth = Some((
            scaled,
            Target::new(gpu, self.names[0], scaled, DEPTH_FORMAT),
        ));
        self.output = Target::new(gpu, self.names[1], scaled, self.format);
        self.generation += 1;
    }

    /// The output's view.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.output.view
    }

    /// Records both steps: `pipelines` are the depth copy's and the shading's, `groups`
    /// bind groups 0, 1, … of both. The output is cleared to `background`, which pixels
    /// without geometry keep. Nothing is recorded before the first
    /// [`ScaledOutput::fit`].
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut GpuTimer,
        pipelines: [&wgpu::RenderPipeline; 2],
        groups: &[&wgpu::BindGroup],
        background: wgpu::Color,
    ) {
        let Some((_, depth)) = self.depth.as_ref() else {
            return;
        };
        let draws = [
            FullscreenDraw {
                name: self.names[0],
                targets: &[],
                load: wgpu::LoadOp::Clear(background),
                depth: Some((&depth.view, wgpu::LoadOp::Clear(0.0))),
                pipeline: pipelines[0],
                groups,
            },
            FullscreenDraw {
                name: self.names[1],
                targets: &[&self.output.view],
                load: wgpu::LoadOp::Clear(background),
                depth: Some((&depth.view, wgpu::LoadOp::Load)),
                pipeline: pipelines[1],
                groups,
            },
        ];
        for draw in &draws {
            draw_fullscreen_pass(encoder, timer, draw);
        }
    }
}

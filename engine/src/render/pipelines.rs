//! Small builders shared by the passes: shader modules from composed WGSL, and the
//! full-screen pipeline and pass (bind groups: [`crate::render::bindings`]).

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use crate::render::shaders::Composed;
use crate::render::targets::DEPTH_FORMAT;
use crate::render::timing::GpuTimer;

/// A pipeline drawing `vertex_entry` with no vertex buffers (three vertices cover the
/// target for `vs_fullscreen`) into colour targets of `formats`, no blending, and the
/// given depth test (none for most passes).
pub fn fullscreen_pipeline(
    gpu: &Gpu,
    label: &str,
    layout: Option<&wgpu::PipelineLayout>,
    module: &wgpu::ShaderModule,
    entries: (&str, &str),
    formats: &[wgpu::TextureFormat],
    depth_stencil: Option<wgpu::DepthStencilState>,
) -> Result<wgpu::RenderPipeline> {
    let targets: Vec<Option<wgpu::ColorTargetState>> =
        formats.iter().map(|f| Some((*f).into())).collect();
    fullscreen_target_pipeline(gpu, label, layout, module, entries, &targets, depth_stencil)
}

/// [`fullscreen_pipeline`] into colour targets given whole (with their blend states).
pub fn fullscreen_target_pipeline(
    gpu: &Gpu,
    label: &str,
    layout: Option<&wgpu::PipelineLayout>,
    module: &wgpu::ShaderModule,
    (vertex_entry, fragment_entry): (&str, &str),
    targets: &[Option<wgpu::ColorTargetState>],
    depth_stencil: Option<wgpu::DepthStencilState>,
) -> Result<wgpu::RenderPipeline> {
    gpu.checked(&format!("{label} pipeline"), |device| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout,
            vertex: wgpu::VertexState {
                module,
                entry_point: Some(vertex_entry),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fragment_entry),
                compilation_options: Default::default(),
                targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    })
}

/// A pipeline layout of `groups`, bind groups 0, 1, … in order.
pub fn pipeline_layout(
    gpu: &Gpu,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let bind_group_layouts: Vec<Option<&wgpu::BindGroupLayout>> =
        groups.iter().map(|g| Some(*g)).collect();
    gpu.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &bind_group_layouts,
            immediate_size: 0,
        })
}

/// The compute pipeline of `entry` in `module`, with `layout` (`None`: derived from the
/// shader).
pub fn compute_pipeline(
    gpu: &Gpu,
    label: &str,
    layout: Option<&wgpu::PipelineLayout>,
    module: &wgpu::ShaderModule,
    entry: &str,
) -> Result<wgpu::ComputePipeline> {
    gpu.checked(&format!("{label} pipeline"), |device| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout,
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    })
}

/// Records one timed full-screen pass, labelled `name` (a pass's name, or one of its
/// steps): `pipeline` with `bind_group` over all of `targets`.
pub fn draw_fullscreen(
    encoder: &mut wgpu::CommandEncoder,
    timer: &mut GpuTimer,
    name: &'static str,
    targets: &[&wgpu::TextureView],
    pipeline: &wgpu::RenderPipeline,
    bind_group: &wgpu::BindGroup,
) {
    draw_fullscreen_with(
        encoder,
        timer,
        name,
        targets,
        pipeline,
        bind_group,
        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
    );
}

/// [`draw_fullscreen`] with the targets' load operation given: `LoadOp::Load` keeps what
/// the targets hold where the shader discards.
pub fn draw_fullscreen_with(
    encoder: &mut wgpu::CommandEncoder,
    timer: &mut GpuTimer,
    name: &'static str,
    targets: &[&wgpu::TextureView],
    pipeline: &wgpu::RenderPipeline,
    bind_group: &wgpu::BindGroup,
    load: wgpu::LoadOp<wgpu::Color>,
) {
    draw_fullscreen_pass(
        encoder,
        timer,
        &FullscreenDraw {
            name,
            targets,
            load,
            depth: None,
            pipeline,
            groups: &[bind_group],
        },
    );
}

/// What a full-screen step does with a depth mask held in a target of the frame's depth
/// format ([`DEPTH_FORMAT`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaskDepth {
    /// Writes the mask: depth 1 (`frag_depth`) where the next step has work; the target
    /// is cleared to 0.
    Mark,
    /// Is tested against it: the full-screen triangle lies at depth 0, so `Less` passes
    /// only where the mask holds more than 0, and the rasterizer shades no other pixel
    /// (which a branch or a `discard` would not spare on llvmpipe).
    Test,
}

/// The depth state of a full-screen step that marks or is tested against a depth mask.
pub fn mask_depth_state(step: MaskDepth) -> wgpu::DepthStencilState {
    let (write, compare) = match step {
        MaskDepth::Mark => (true, wgpu::CompareFunction::Always),
        MaskDepth::Test => (false, wgpu::CompareFunction::Less),
    };
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// One full-screen draw in a timed pass of its own, in full.
pub struct FullscreenDraw<'a> {
    /// The pass's name (or one of its steps), its label and timer scope.
    pub name: &'static str,
    /// The colour targets, each loaded with `load` and stored.
    pub targets: &'a [&'a wgpu::TextureView],
    /// How the colour targets are loaded.
    pub load: wgpu::LoadOp<wgpu::Color>,
    /// A depth attachment and how it is loaded (stored either way), if any.
    pub depth: Option<(&'a wgpu::TextureView, wgpu::LoadOp<f32>)>,
    /// The pipeline.
    pub pipeline: &'a wgpu::RenderPipeline,
    /// Bind groups 0, 1, … in order.
    pub groups: &'a [&'a wgpu::BindGroup],
}

/// A colour attachment loaded with `load` and stored.
pub fn color_attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    }
}

/// A depth attachment (no stencil) loaded with `load` and stored.
pub fn depth_attachment(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<f32>,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// Records `draw`: the full-screen triangle in a timed render pass of its own.
pub fn draw_fullscreen_pass(
    encoder: &mut wgpu::CommandEncoder,
    timer: &mut GpuTimer,
    draw: &FullscreenDraw,
) {
    let scope = timer.begin_step(draw.name);
    {
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = draw
            .targets
            .iter()
            .map(|view| Some(color_attachment(view, draw.load)))
            .collect();
        let depth_stencil_attachment = draw.depth.map(|(view, load)| depth_attachment(view, load));
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(draw.name),
            color_attachments: &attachments,
            depth_stencil_attachment,
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(draw.pipeline);
        for (i, group) in draw.groups.iter().enumerate() {
            rp.set_bind_group(i as u32, *group, &[]);
        }
        rp.draw(0..3, 0..1);
    }
    timer.end_pass(scope);
}

/// Compiles composed WGSL into a shader module. A compile error becomes [`Error::Gpu`]
/// that starts with the module and line where naga finds it, then the compiler's message.
pub fn create_module(gpu: &Gpu, label: &str, composed: &Composed) -> Result<wgpu::ShaderModule> {
    gpu.checked(&format!("shader '{label}'"), |device| {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(composed.source.as_str().into()),
        })
    })
    .map_err(|e| match composed.first_error() {
        Some(at) => Error::Gpu(format!("{at}\n{e}")),
        None => e,
    })
}

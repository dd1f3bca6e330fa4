//! What the forward passes share: the transparent pass and the layers pass draw meshes
//! through the material maps' bind group, lit by the deferred pass's code, with the same
//! bind group layout (their view group, the lighting pass's groups 1 to 3, the maps as
//! group 4), the same kind of pipelines ([`ForwardPipelines`]) and the same draw loop
//! ([`draw_batches`]).

use crate::error::Result;
use crate::render::bindings::BindGroupSpec;
use crate::render::device::Gpu;
use crate::render::extract::{Batch, ExtractedFrame};
use crate::render::geometry::deform_pass::DeformedVertices;
use crate::render::geometry::gpu_material_maps::GpuMaterialMaps;
use crate::render::indirect::light_groups::LightGroups;
use crate::render::pipeline_cache::{PipelineCache, ShaderVariant};
use crate::render::pipelines::{create_module, pipeline_layout};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;

/// The bind group index of the material maps in a forward pass.
pub const MAPS_GROUP: u32 = 4;

/// How a forward pass draws into a target of some format: its fragment entry point, its
/// colour targets and its depth test.
pub struct ForwardShape {
    /// The fragment entry point.
    pub entry: &'static str,
    /// The colour targets, with their blend states.
    pub targets: Vec<Option<wgpu::ColorTargetState>>,
    /// The depth test against the opaque depth.
    pub depth: wgpu::DepthStencilState,
}

/// A forward pass's layouts and pipelines: one shader module per variant `V`, compiled on
/// first use, and one pipeline per (variant, double-sided, HDR format).
pub struct ForwardPipelines<V> {
    label: &'static str,
    /// Group 0's layout: the pass's own view group.
    pub view_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    modules: PipelineCache<V, wgpu::ShaderModule>,
    pipelines: PipelineCache<(V, bool, wgpu::TextureFormat)>,
}

impl<V: ShaderVariant + Copy> ForwardPipelines<V> {
    /// The layouts: `view` as group 0, the light groups 1 to 3 (`lighting`) and
    /// the material maps' (`maps`) as group [`MAPS_GROUP`].
    pub fn new(
        gpu: &Gpu,
        label: &'static str,
        view: &BindGroupSpec,
        lighting: &[wgpu::BindGroupLayout; 3],
        maps: &wgpu::BindGroupLayout,
    ) -> ForwardPipelines<V> {
        let view_layout = view.layout(gpu);
        let [l1, l2, l3] = lighting;
        let layout = pipeline_layout(gpu, label, &[&view_layout, l1, l2, l3, maps]);
        ForwardPipelines {
            label,
            view_layout,
            layout,
            modules: PipelineCache::default(),
            pipelines: PipelineCache::default(),
        }
    }

    /// The pipeline of `variant` for a batch that is `double_sided`, into `format`.
    pub fn get(
        &self,
        variant: V,
        double_sided: bool,
        format: wgpu::TextureFormat,
    ) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.get(&(variant, double_sided, format))
    }

    /// Compiles what `batches` need for `variant` into `format`: the module from the WGSL
    /// file `file` with the variant's defs (once per variant), and a pipeline of
    /// `shape(format)` for each sidedness.
    pub fn ensure<'b>(
        &mut self,
        gpu: &Gpu,
        (variant, format): (V, wgpu::TextureFormat),
        batches: impl Iterator<Item = &'b Batch>,
        file: &str,
        shape: &dyn Fn(wgpu::TextureFormat) -> ForwardShape,
    ) -> Result<()> {
        let ForwardPipelines {
            label,
            layout,
            modules,
            pipelines,
            ..
        } = self;
        for batch in batches {
            let key = (variant, batch.double_sided, format);
            if pipelines.get(&key).is_some() {
                continue;
            }
            let module = modules.ensure(&variant, |defs| {
                create_module(gpu, label, &gpu.shaders.compose(file, defs)?)
            })?;
            pipelines.ensure_with(&key, || {
                let ForwardShape {
                    entry,
                    targets,
                    depth,
                } = shape(format);
                mesh_pipeline(
                    gpu,
                    label,
                    layout,
                    (module, entry),
                    batch.double_sided,
                    &targets,
                    depth,
                )
            })?;
        }
        Ok(())
    }
}

/// A pipeline drawing meshes (the vertex and instance buffers of
/// [`crate::render::geometry::mesh_vertex::buffers`], triangle lists, counter-clockwise fronts) with
/// `vs_main` and the fragment entry of `module`, back faces culled unless `double_sided`,
/// into `targets`, with the depth test `depth_stencil`.
fn mesh_pipeline(
    gpu: &Gpu,
    label: &str,
    layout: &wgpu::PipelineLayout,
    (module, fragment_entry): (&wgpu::ShaderModule, &str),
    double_sided: bool,
    targets: &[Option<wgpu::ColorTargetState>],
    depth_stencil: wgpu::DepthStencilState,
) -> Result<wgpu::RenderPipeline> {
    gpu.checked(&format!("{label} pipeline"), |device| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &crate::render::geometry::mesh_vertex::buffers(),
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                front_face: wgpu::FrontFace::Ccw,
                cull_mode: (!double_sided).then_some(wgpu::Face::Back),
                ..Default::default()
            },
            depth_stencil: Some(depth_stencil),
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

/// What a forward pass prepares from, besides its own resource.
#[derive(SystemParam)]
pub struct PrepareInputs<'w> {
    /// The batches.
    pub frame: Res<'w, ExtractedFrame>,
    /// Meshes, instances and the view.
    pub buffers: Res<'w, SceneBuffers>,
    /// The frame's targets.
    pub targets: Res<'w, RenderTargets>,
}

/// What a forward pass draws with, besides its own resource.
#[derive(SystemParam)]
pub struct ForwardInputs<'w> {
    /// Groups 1 to 3, which a forward pass binds as the lighting pass does.
    pub lighting: Res<'w, LightGroups>,
    /// The material maps' bind groups.
    pub maps: Res<'w, GpuMaterialMaps>,
    /// Meshes, instances and the view.
    pub buffers: Res<'w, SceneBuffers>,
    /// The batches.
    pub frame: Res<'w, ExtractedFrame>,
    /// The frame's targets.
    pub targets: Res<'w, RenderTargets>,
    /// The deformed vertices of skinned and morphed instances.
    pub deform: Res<'w, DeformedVertices>,
}

/// Binds `view_group` as group 0, the lighting pass's `shared` groups as 1 to 3 and the
/// instances, then draws each of `batches` (its instances in view) with its maps at
/// group `maps_group` and the pipeline `pipeline` gives it; a batch without a mesh, maps
/// or pipeline is left out.
pub fn draw_batches<'b, 'p>(
    rp: &mut wgpu::RenderPass<'_>,
    inputs: &ForwardInputs,
    (view_group, shared): (&wgpu::BindGroup, [&wgpu::BindGroup; 3]),
    maps_group: u32,
    batches: impl Iterator<Item = &'b Batch>,
    pipeline: impl Fn(&Batch) -> Option<&'p wgpu::RenderPipeline>,
) {
    rp.set_bind_group(0, view_group, &[]);
    for (i, group) in shared.into_iter().enumerate() {
        rp.set_bind_group(i as u32 + 1, group, &[]);
    }
    rp.set_vertex_buffer(1, inputs.buffers.instances.buffer.slice(..));
    for batch in batches {
        let (Some(mesh), Some(group), Some(pipeline)) = (
            inputs.buffers.meshes.get(&batch.mesh),
            batch.maps.and_then(|m| inputs.maps.group(m)),
            pipeline(batch),
        ) else {
            continue;
        };
        let Some(vertices) = inputs
            .deform
            .draw_vertices(&inputs.frame, mesh, batch.deformed)
        else {
            continue;
        };
        rp.set_pipeline(pipeline);
        rp.set_bind_group(maps_group, group, &[]);
        rp.set_vertex_buffer(0, vertices.slice(..));
        rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        rp.draw_indexed(
            0..mesh.index_count,
            0,
            batch.first_instance..batch.first_instance + batch.visible,
        );
    }
}

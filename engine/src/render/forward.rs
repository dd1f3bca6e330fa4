//! What the forward passes share: the transparent pass and the clearcoat pass draw meshes
//! through the material maps' bind group, lit by the deferred pass's code, with the same
//! pipelines shape and the same draw loop.

use crate::error::Result;
use crate::render::deform::DeformPass;
use crate::render::device::Gpu;
use crate::render::extract::{Batch, ExtractedFrame};
use crate::render::lighting::LightingPass;
use crate::render::material_maps::GpuMaterialMaps;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;

/// A pipeline drawing meshes (the vertex and instance buffers of
/// [`crate::render::mesh_vertex::buffers`], triangle lists, counter-clockwise fronts) with
/// `vs_main` and the fragment entry of `module`, back faces culled unless `double_sided`,
/// into `targets`, with the depth test `depth_stencil`: the forward passes' pipelines.
pub fn mesh_pipeline(
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
                buffers: &crate::render::mesh_vertex::buffers(),
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

/// What a forward pass draws with, besides its own resource.
#[derive(SystemParam)]
pub struct ForwardInputs<'w> {
    /// The lighting pass, whose groups 1 to 3 a forward pass binds as they are.
    pub lighting: Res<'w, LightingPass>,
    /// The material maps' bind groups.
    pub maps: Res<'w, GpuMaterialMaps>,
    /// Meshes, instances and the view.
    pub buffers: Res<'w, SceneBuffers>,
    /// The batches.
    pub frame: Res<'w, ExtractedFrame>,
    /// The frame's targets.
    pub targets: Res<'w, RenderTargets>,
    /// The deformed vertices of skinned and morphed instances.
    pub deform: Res<'w, DeformPass>,
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

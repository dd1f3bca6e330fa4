//! The vertex buffers of the passes that draw meshes with their materials (the G-buffer
//! and the transparent pass): the mesh's vertices and the instances as per-instance
//! attributes, as `shaders/mesh_vertex.wgsl` declares them (`VertexInput`,
//! `InstanceInput`). Vertex fetch is cheaper than a storage-buffer read per vertex on
//! lavapipe.

use crate::render::gpu_types::GpuInstance;
use crate::scene::Vertex;

/// `VertexInput`: position, normal, uv, tangent, uv1, colour.
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4,
    14 => Float32x2, 15 => Float32x4
];

/// `InstanceInput`: the world matrix, the normal matrix's three columns, base colour,
/// emissive and occlusion, and the material parameters.
const INSTANCE_ATTRIBUTES: [wgpu::VertexAttribute; 10] = wgpu::vertex_attr_array![
    4 => Float32x4, 5 => Float32x4, 6 => Float32x4, 7 => Float32x4,
    8 => Float32x4, 9 => Float32x4, 10 => Float32x4,
    11 => Float32x4, 12 => Float32x4, 13 => Float32x4
];

/// Buffer 0, the mesh's [`Vertex`]es, and buffer 1, the frame's [`GpuInstance`]s.
pub fn buffers() -> [Option<wgpu::VertexBufferLayout<'static>>; 2] {
    [
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VERTEX_ATTRIBUTES,
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<GpuInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &INSTANCE_ATTRIBUTES,
        }),
    ]
}

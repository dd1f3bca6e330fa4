//! The scene's GPU buffers: view uniform, instance and light storage, and one vertex +
//! index buffer per mesh (uploaded once, when first drawn).

use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::gpu_types::{GpuInstance, GpuLight, GpuView};
use crate::scene::{MeshHandle, Meshes};
use bevy_ecs::prelude::*;
use std::collections::HashMap;

/// A mesh on the GPU.
pub struct GpuMesh {
    /// Interleaved [`crate::scene::Vertex`] data.
    pub vertices: wgpu::Buffer,
    /// `u32` indices.
    pub indices: wgpu::Buffer,
    /// Number of indices.
    pub index_count: u32,
}

/// A storage buffer (also usable as a vertex buffer) that grows (by doubling) to fit its
/// contents.
pub struct GrowableBuffer {
    /// The buffer.
    pub buffer: wgpu::Buffer,
    label: &'static str,
}

impl GrowableBuffer {
    /// An empty buffer of at least `size` bytes (and at least 256).
    pub fn new(gpu: &Gpu, label: &'static str, size: u64) -> Self {
        GrowableBuffer {
            buffer: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(256),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::VERTEX
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            label,
        }
    }

    /// Writes `data`, growing the buffer first if needed; returns whether it was recreated.
    pub fn write(&mut self, gpu: &Gpu, data: &[u8]) -> bool {
        let mut recreated = false;
        if data.len() as u64 > self.buffer.size() {
            *self = GrowableBuffer::new(gpu, self.label, (data.len() as u64).next_power_of_two());
            recreated = true;
        }
        if !data.is_empty() {
            gpu.queue.write_buffer(&self.buffer, 0, data);
        }
        recreated
    }
}

/// The scene's buffers on the GPU.
#[derive(Resource)]
pub struct SceneBuffers {
    /// [`GpuView`] uniform.
    pub view: wgpu::Buffer,
    /// [`GpuInstance`] array.
    pub instances: GrowableBuffer,
    /// [`GpuLight`] array.
    pub lights: GrowableBuffer,
    /// The first [`SceneBuffers::uniform_light_capacity`] lights again, as a uniform
    /// buffer: on lavapipe a uniform load in the lighting loop costs a third of a storage
    /// load (measured: 4 point lights at 1280×720, 23 ms against 57 ms).
    pub lights_uniform: wgpu::Buffer,
    /// How many lights the uniform copy holds: 512, or fewer where the adapter's uniform
    /// binding limit is smaller.
    pub uniform_light_capacity: u32,
    /// Uploaded meshes.
    pub meshes: HashMap<MeshHandle, GpuMesh>,
    /// Bumped whenever a bound buffer is recreated, so passes rebuild their bind groups.
    pub generation: u64,
}

impl SceneBuffers {
    /// Empty buffers.
    pub fn new(gpu: &Gpu) -> Self {
        SceneBuffers {
            view: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("view"),
                size: std::mem::size_of::<GpuView>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            instances: GrowableBuffer::new(
                gpu,
                "instances",
                64 * std::mem::size_of::<GpuInstance>() as u64,
            ),
            lights: GrowableBuffer::new(gpu, "lights", 16 * std::mem::size_of::<GpuLight>() as u64),
            lights_uniform: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lights (uniform)"),
                size: u64::from(uniform_light_capacity(gpu).max(1)) * LIGHT_SIZE,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            uniform_light_capacity: uniform_light_capacity(gpu),
            meshes: HashMap::new(),
            generation: 0,
        }
    }
}

const LIGHT_SIZE: u64 = std::mem::size_of::<GpuLight>() as u64;

/// Lights that fit the uniform copy on this device (at most 512).
fn uniform_light_capacity(gpu: &Gpu) -> u32 {
    let limit = gpu.device.limits().max_uniform_buffer_binding_size;
    (limit / LIGHT_SIZE).min(512) as u32
}

fn upload_mesh(gpu: &Gpu, meshes: &Meshes, handle: MeshHandle) -> Option<GpuMesh> {
    use wgpu::util::DeviceExt;
    let mesh = meshes.get(handle)?;
    if mesh.indices.is_empty() {
        return None;
    }
    Some(GpuMesh {
        vertices: gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh vertices"),
                contents: bytemuck::cast_slice(&mesh.vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
        indices: gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh indices"),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
        index_count: mesh.indices.len() as u32,
    })
}

/// Uploads this frame's view, instances and lights, and any mesh not yet on the GPU.
pub fn prepare_scene_buffers(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    meshes: Res<Meshes>,
    mut buffers: ResMut<SceneBuffers>,
) {
    let buffers = &mut *buffers;
    gpu.queue
        .write_buffer(&buffers.view, 0, bytemuck::bytes_of(&frame.view));
    let grew_instances = buffers
        .instances
        .write(&gpu, bytemuck::cast_slice(&frame.instances));
    let grew_lights = buffers
        .lights
        .write(&gpu, bytemuck::cast_slice(&frame.lights));
    let in_uniform = frame
        .lights
        .len()
        .min(buffers.uniform_light_capacity as usize);
    if in_uniform > 0 {
        gpu.queue.write_buffer(
            &buffers.lights_uniform,
            0,
            bytemuck::cast_slice(&frame.lights[..in_uniform]),
        );
    }
    if grew_instances || grew_lights {
        buffers.generation += 1;
    }
    for batch in &frame.batches {
        if !buffers.meshes.contains_key(&batch.mesh)
            && let Some(gpu_mesh) = upload_mesh(&gpu, &meshes, batch.mesh)
        {
            buffers.meshes.insert(batch.mesh, gpu_mesh);
        }
    }
}

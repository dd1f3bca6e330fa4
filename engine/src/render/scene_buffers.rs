//! The scene's GPU buffers: view uniform, instance and light storage, and one vertex +
//! index buffer per mesh (uploaded once, when first drawn).

use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::gpu_types::{GpuInstance, GpuLight, GpuPunctualLight, GpuView};
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
    usage: wgpu::BufferUsages,
}

impl GrowableBuffer {
    /// An empty buffer of at least `size` bytes (and at least 256).
    pub fn new(gpu: &Gpu, label: &'static str, size: u64) -> Self {
        Self::with_usage(
            gpu,
            label,
            size,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
        )
    }

    /// An empty buffer of at least `size` bytes (and at least 256) for `usage` (and
    /// copies into it).
    pub fn with_usage(
        gpu: &Gpu,
        label: &'static str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        GrowableBuffer {
            buffer: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(256),
                usage,
                mapped_at_creation: false,
            }),
            label,
            usage,
        }
    }

    /// Writes `data`, growing the buffer first if needed (a grown buffer is a new one:
    /// bind groups that bound the old one are made again, [`crate::render::bindings::CachedGroup`]).
    pub fn write(&mut self, gpu: &Gpu, data: &[u8]) {
        if data.len() as u64 > self.buffer.size() {
            *self = GrowableBuffer::with_usage(
                gpu,
                self.label,
                (data.len() as u64).next_power_of_two(),
                self.usage,
            );
        }
        if !data.is_empty() {
            gpu.queue.write_buffer(&self.buffer, 0, data);
        }
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
    /// The first [`SceneBuffers::uniform_light_capacity`] lights again, in their compact
    /// [`GpuPunctualLight`] form, as a uniform buffer: on lavapipe a uniform load in the
    /// lighting loop costs a third of a storage load (measured: 4 point lights at
    /// 1280×720, 23 ms against 57 ms). The light loops and the culling pass read it.
    pub lights_uniform: wgpu::Buffer,
    /// How many lights the uniform copy holds: 1365 (64 KiB), or fewer where the
    /// adapter's uniform binding limit is smaller.
    pub uniform_light_capacity: u32,
    /// The shadowed lights again, whole and packed (directional, then point, then spot),
    /// as a uniform buffer: the shadowed loops read it when every shadowed light fits
    /// (measured on `spheres`: lighting 77 ms reading the storage buffer, 58 ms reading
    /// this).
    pub shadowed_lights_uniform: wgpu::Buffer,
    /// How many shadowed lights that copy holds ([`SHADOWED_LIGHT_CAPACITY`], or fewer
    /// where the uniform binding limit is smaller).
    pub shadowed_light_capacity: u32,
    /// Uploaded meshes.
    pub meshes: HashMap<MeshHandle, GpuMesh>,
}

impl SceneBuffers {
    /// Empty buffers.
    pub fn new(gpu: &Gpu) -> Self {
        SceneBuffers {
            view: gpu.uniform_buffer("view", std::mem::size_of::<GpuView>() as u64),
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
            shadowed_lights_uniform: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shadowed lights (uniform)"),
                size: u64::from(shadowed_light_capacity(gpu).max(1)) * FULL_LIGHT_SIZE,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            shadowed_light_capacity: shadowed_light_capacity(gpu),
            meshes: HashMap::new(),
        }
    }
}

const LIGHT_SIZE: u64 = std::mem::size_of::<GpuPunctualLight>() as u64;

const FULL_LIGHT_SIZE: u64 = std::mem::size_of::<GpuLight>() as u64;

/// Most shadowed lights the uniform copy holds: more than the shadow atlas has room for
/// at any useful resolution.
pub const SHADOWED_LIGHT_CAPACITY: u32 = 128;

impl SceneBuffers {
    /// Whether every light of `frame` fits the uniform copies, so that the passes read
    /// lights from them rather than from the storage buffer.
    pub fn lights_fit_uniform(&self, frame: &ExtractedFrame) -> bool {
        frame.light_counts.total() <= self.uniform_light_capacity
            && frame.shadowed_counts.iter().sum::<u32>() <= self.shadowed_light_capacity
    }
}

fn shadowed_light_capacity(gpu: &Gpu) -> u32 {
    let limit = gpu.device.limits().max_uniform_buffer_binding_size;
    (limit / FULL_LIGHT_SIZE).min(u64::from(SHADOWED_LIGHT_CAPACITY)) as u32
}

/// The shadowed lights of `lights`, packed: each kind's shadowed lights come first
/// within the kind (directional, point, spot), so they are three ranges.
pub fn shadowed_lights(lights: &[GpuLight], counts: [u32; 3], shadowed: [u32; 3]) -> Vec<GpuLight> {
    let mut start = 0usize;
    let mut out = Vec::new();
    for (count, shadowed) in counts.into_iter().zip(shadowed) {
        let end = (start + shadowed as usize).min(lights.len());
        out.extend_from_slice(&lights[start.min(end)..end]);
        start += count as usize;
    }
    out
}

/// Lights that fit the uniform copy on this device (at most 64 KiB of them).
fn uniform_light_capacity(gpu: &Gpu) -> u32 {
    let limit = gpu
        .device
        .limits()
        .max_uniform_buffer_binding_size
        .min(65_536);
    (limit / LIGHT_SIZE) as u32
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
                // A deformable mesh's vertices are also the deformation pass's input.
                usage: if meshes.deformation(handle).is_some() {
                    wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE
                } else {
                    wgpu::BufferUsages::VERTEX
                },
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
    buffers
        .instances
        .write(&gpu, bytemuck::cast_slice(&frame.instances));
    buffers
        .lights
        .write(&gpu, bytemuck::cast_slice(&frame.lights));
    let in_uniform = frame
        .lights
        .len()
        .min(buffers.uniform_light_capacity as usize);
    if in_uniform > 0 {
        let compact: Vec<GpuPunctualLight> = frame.lights[..in_uniform]
            .iter()
            .map(GpuPunctualLight::from)
            .collect();
        gpu.queue
            .write_buffer(&buffers.lights_uniform, 0, bytemuck::cast_slice(&compact));
    }
    let counts = frame.view.light_counts;
    let shadowed = shadowed_lights(
        &frame.lights,
        [counts[0], counts[1], counts[2]],
        frame.shadowed_counts,
    );
    let in_uniform = shadowed.len().min(buffers.shadowed_light_capacity as usize);
    if in_uniform > 0 {
        gpu.queue.write_buffer(
            &buffers.shadowed_lights_uniform,
            0,
            bytemuck::cast_slice(&shadowed[..in_uniform]),
        );
    }
    for batch in &frame.batches {
        if !buffers.meshes.contains_key(&batch.mesh)
            && let Some(gpu_mesh) = upload_mesh(&gpu, &meshes, batch.mesh)
        {
            buffers.meshes.insert(batch.mesh, gpu_mesh);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(tag: f32) -> GpuLight {
        GpuLight {
            position: [tag, 0.0, 0.0, 1.0],
            ..GpuLight::default()
        }
    }

    #[test]
    fn shadowed_lights_are_packed_by_kind() {
        // 2 directional (1 shadowed), 3 point (2 shadowed), 2 spot (1 shadowed).
        let lights: Vec<GpuLight> = (0..7).map(|k| light(k as f32)).collect();
        let packed = shadowed_lights(&lights, [2, 3, 2], [1, 2, 1]);
        let tags: Vec<f32> = packed.iter().map(|l| l.position[0]).collect();
        assert_eq!(tags, [0.0, 2.0, 3.0, 5.0]);
        // Counts past the end of the list never index out of range.
        assert_eq!(shadowed_lights(&lights[..3], [2, 3, 2], [2, 3, 2]).len(), 3);
        assert!(shadowed_lights(&[], [0, 0, 0], [0, 0, 0]).is_empty());
    }

    #[test]
    fn the_punctual_form_keeps_what_the_loops_read() {
        let full = GpuLight {
            position: [1.0, 2.0, 3.0, 1.0],
            direction: [0.0, -1.0, 0.0, 0.0],
            color_inv_range2: [4.0, 5.0, 6.0, 0.25],
            spot: [7.0, 8.0, 0.0, 0.0],
            ..GpuLight::default()
        };
        let compact = GpuPunctualLight::from(&full);
        assert_eq!(compact.position_inv_range2, [1.0, 2.0, 3.0, 0.25]);
        assert_eq!(compact.color_spot_scale, [4.0, 5.0, 6.0, 7.0]);
        assert_eq!(compact.direction_spot_offset, [0.0, -1.0, 0.0, 8.0]);
        assert_eq!(std::mem::size_of::<GpuPunctualLight>(), 48);
    }
}

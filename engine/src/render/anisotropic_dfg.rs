//! The anisotropic lobe's split-sum table on the GPU ([`crate::anisotropy::dfg_table`],
//! read by `shaders/anisotropic_dfg.wgsl`): a storage buffer held by each pass that lights
//! an anisotropic lobe from its material (the layers pass's relit base and the
//! transparent pass's blended surfaces), bound as binding 2 of its view group. The table
//! is computed (once per process) and written the first time a frame draws an
//! anisotropic surface; until then the buffer holds zeros that no shader reads.

use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use std::sync::atomic::{AtomicBool, Ordering};

/// The table's buffer and whether it holds the table.
pub struct AnisotropicDfgBuffer {
    /// (A, B) pairs in [`crate::anisotropy::dfg_table`]'s layout.
    pub buffer: wgpu::Buffer,
    written: AtomicBool,
}

impl AnisotropicDfgBuffer {
    /// The buffer, sized for the table and not yet written.
    pub fn new(gpu: &Gpu) -> Self {
        let entries: usize = crate::anisotropy::DFG_TABLE_DIMS.iter().product();
        AnisotropicDfgBuffer {
            buffer: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("anisotropic split-sum table"),
                size: (entries * std::mem::size_of::<glam::Vec2>()) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            written: AtomicBool::new(false),
        }
    }

    /// Writes the table once, for a frame that draws an anisotropic surface (opaque or
    /// blended).
    pub fn write_for(&self, gpu: &Gpu, frame: &ExtractedFrame) {
        if !self.written.load(Ordering::Relaxed)
            && frame.material_maps.iter().any(|m| m.anisotropy.is_some())
        {
            gpu.queue.write_buffer(
                &self.buffer,
                0,
                bytemuck::cast_slice(crate::anisotropy::dfg_table()),
            );
            self.written.store(true, Ordering::Relaxed);
        }
    }
}

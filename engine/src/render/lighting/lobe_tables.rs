//! The lobe tables on the GPU, held by each pass that lights a lobe from its material (the
//! layers pass over opaque surfaces, the transparent pass over blended ones):
//! - the anisotropic lobe's split-sum table ([`crate::shading::anisotropy::dfg_table`], read by
//!   `shaders/anisotropic_dfg.wgsl`), a storage buffer, binding 2 of the pass's view group;
//! - the sheen lobe's directional albedo ([`crate::shading::sheen::albedo_table`], read by
//!   `shaders/sheen_table.wgsl`), a uniform buffer.
//!
//! Each table is computed (once per process) and written the first time a frame draws a
//! surface that reads it; until then its buffer holds zeros that no shader reads.

use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;

/// The tables' buffers and whether each holds its table.
pub struct LobeTables {
    /// (A, B) pairs in [`crate::shading::anisotropy::dfg_table`]'s layout.
    pub anisotropic_dfg: wgpu::Buffer,
    /// E_sheen(n·v, r) in [`crate::shading::sheen::albedo_table`]'s layout, packed in vec4s.
    pub sheen_albedo: wgpu::Buffer,
    anisotropic_written: bool,
    sheen_written: bool,
}

impl LobeTables {
    /// The buffers, sized for the tables and not yet written.
    pub fn new(gpu: &Gpu) -> Self {
        let entries: usize = crate::shading::anisotropy::DFG_TABLE_DIMS.iter().product();
        let sheen =
            crate::shading::sheen::ALBEDO_TABLE_SIZE * crate::shading::sheen::ALBEDO_TABLE_SIZE;
        let buffer = |label, size, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        LobeTables {
            anisotropic_dfg: buffer(
                "anisotropic split-sum table",
                (entries * std::mem::size_of::<glam::Vec2>()) as u64,
                wgpu::BufferUsages::STORAGE,
            ),
            sheen_albedo: buffer(
                "sheen albedo table",
                (sheen * std::mem::size_of::<f32>()) as u64,
                wgpu::BufferUsages::UNIFORM,
            ),
            anisotropic_written: false,
            sheen_written: false,
        }
    }

    /// Writes each table once, for a frame that draws a surface reading it (opaque or
    /// blended): an anisotropic one, one with a sheen.
    pub fn write_for(&mut self, gpu: &Gpu, frame: &ExtractedFrame) {
        if !self.anisotropic_written && frame.material_maps.iter().any(|m| m.anisotropy.is_some()) {
            gpu.queue.write_buffer(
                &self.anisotropic_dfg,
                0,
                bytemuck::cast_slice(crate::shading::anisotropy::dfg_table()),
            );
            self.anisotropic_written = true;
        }
        if !self.sheen_written && frame.material_maps.iter().any(|m| m.sheen.is_some()) {
            gpu.queue.write_buffer(
                &self.sheen_albedo,
                0,
                bytemuck::cast_slice(crate::shading::sheen::albedo_table()),
            );
            self.sheen_written = true;
        }
    }
}

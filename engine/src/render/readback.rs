//! Copying a texture back to the CPU.

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use half::f16;

/// Reads a whole 2D texture of a 4-channel format back, rows unpadded: `bytes_per_pixel`
/// is 4 (`Rgba8*`, `Bgra8*`), 8 (`Rgba16Float`) or 16 (`Rgba32Float`).
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture, bytes_per_pixel: u32) -> Result<Vec<u8>> {
    let (width, height) = (texture.width(), texture.height());
    let unpadded = width * bytes_per_pixel;
    let padded =
        unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback"),
        });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        texture.size(),
    );
    let index = gpu.queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    gpu.device
        .poll(wgpu::PollType::Wait {
            submission_index: Some(index),
            timeout: None,
        })
        .map_err(|e| Error::Gpu(format!("waiting for a readback: {e}")))?;
    rx.recv()
        .map_err(|e| Error::Gpu(format!("readback never completed: {e}")))?
        .map_err(|e| Error::Gpu(format!("cannot map the readback buffer: {e}")))?;
    let mut out = Vec::with_capacity((unpadded * height) as usize);
    {
        let data = slice
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("cannot read the readback buffer: {e}")))?;
        for row in data.chunks(padded as usize) {
            out.extend_from_slice(&row[..unpadded as usize]);
        }
    }
    buffer.unmap();
    Ok(out)
}

/// Converts `Rgba16Float` texel bytes to f32.
pub fn f16_bytes_to_f32(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(2)
        .map(|b| f16::from_le_bytes([b[0], b[1]]).to_f32())
        .collect()
}

//! Copying a texture back to the CPU.

use crate::error::{Error, Result};
use crate::render::device::Gpu;
use half::f16;

/// Reads a whole 2D texture back, rows unpadded; `bytes_per_pixel` is the format's texel
/// size (4 for `Rgba8*` and `Depth32Float`, 8 for `Rgba16Float`, 16 for `Rgba32Float`).
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture, bytes_per_pixel: u32) -> Result<Vec<u8>> {
    read_texture_level(gpu, texture, 0, 0, bytes_per_pixel)
}

/// Reads one mip level of one array layer (a cube face) of a texture back, rows unpadded.
pub fn read_texture_level(
    gpu: &Gpu,
    texture: &wgpu::Texture,
    mip: u32,
    layer: u32,
    bytes_per_pixel: u32,
) -> Result<Vec<u8>> {
    if mip >= texture.mip_level_count() || layer >= texture.depth_or_array_layers() {
        return Err(Error::InvalidArgument(format!(
            "mip {mip} / layer {layer} is outside the texture ({} mips, {} layers)",
            texture.mip_level_count(),
            texture.depth_or_array_layers()
        )));
    }
    let (width, height) = (
        (texture.width() >> mip).max(1),
        (texture.height() >> mip).max(1),
    );
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
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: mip,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    let data = submit_and_map(gpu, encoder, &buffer)?;
    let mut out = Vec::with_capacity((unpadded * height) as usize);
    for row in data.chunks(padded as usize) {
        out.extend_from_slice(&row[..unpadded as usize]);
    }
    Ok(out)
}

/// The contents of `buffer` (which must allow `COPY_SRC`) after the work submitted so far
/// and `encoder`'s.
pub fn read_buffer(
    gpu: &Gpu,
    mut encoder: wgpu::CommandEncoder,
    buffer: &wgpu::Buffer,
) -> Result<Vec<u8>> {
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    submit_and_map(gpu, encoder, &staging)
}

/// Submits `encoder`, waits for it, and returns the mapped contents of `staging`.
fn submit_and_map(
    gpu: &Gpu,
    encoder: wgpu::CommandEncoder,
    staging: &wgpu::Buffer,
) -> Result<Vec<u8>> {
    let index = gpu.queue.submit([encoder.finish()]);
    let slice = staging.slice(..);
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
    let out = slice
        .get_mapped_range()
        .map_err(|e| Error::Gpu(format!("cannot read the readback buffer: {e}")))?
        .to_vec();
    staging.unmap();
    Ok(out)
}

/// Converts `Rgba16Float` texel bytes to f32.
pub fn f16_bytes_to_f32(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(2)
        .map(|b| f16::from_le_bytes([b[0], b[1]]).to_f32())
        .collect()
}

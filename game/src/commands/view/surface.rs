//! The window's GPU and surface: a device that can present to the window, the surface
//! format and configuration, and the black frame shown when the scene cannot render.

use anyhow::{Result, anyhow};
use lumen::render::device::{Gpu, GpuRequest};
use lumen::wgpu;
use std::sync::Arc;
use winit::window::Window;

fn pick_format(caps: &wgpu::SurfaceCapabilities) -> Option<wgpu::TextureFormat> {
    // A non-sRGB 8-bit format lets the tone mapping pass apply the exact sRGB curve.
    let preferred = [
        wgpu::TextureFormat::Bgra8Unorm,
        wgpu::TextureFormat::Rgba8Unorm,
    ];
    preferred
        .iter()
        .find(|f| caps.formats.contains(f))
        .copied()
        .or_else(|| caps.formats.first().copied())
}

/// A GPU that can present to `window`, its surface, and the surface configured at the
/// window's size.
pub(super) fn window_gpu(
    window: &Arc<Window>,
    display: &winit::event_loop::OwnedDisplayHandle,
    present_mode: wgpu::PresentMode,
) -> Result<(Gpu, wgpu::Surface<'static>, wgpu::SurfaceConfiguration)> {
    let surface_window = window.clone();
    let display = display.clone();
    let (gpu, surface) = Gpu::new(
        &GpuRequest::from_env()?,
        Some(&move |instance: &wgpu::Instance| {
            instance
                .create_surface(surface_window.clone())
                .map_err(|e| e.to_string())
        }),
        Some(&move || Box::new(display.clone())),
    )?;
    let surface = surface.ok_or_else(|| anyhow!("no window surface"))?;
    let caps = surface.get_capabilities(&gpu.adapter);
    let format =
        pick_format(&caps).ok_or_else(|| anyhow!("the window surface supports no format"))?;
    let size = window.inner_size();
    let config = wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        width: size.width,
        height: size.height,
        present_mode,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps
            .alpha_modes
            .first()
            .copied()
            .unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
        color_space: wgpu::SurfaceColorSpace::Auto,
    };
    configure(&gpu, &surface, &config)?;
    Ok((gpu, surface, config))
}

/// Configures `surface` (not while minimised); a refusal is an error, since presenting
/// from an unconfigured surface would panic in wgpu.
pub(super) fn configure(
    gpu: &Gpu,
    surface: &wgpu::Surface<'static>,
    config: &wgpu::SurfaceConfiguration,
) -> Result<()> {
    if config.width > 0 && config.height > 0 {
        gpu.checked("configuring the window surface", |device| {
            surface.configure(device, config)
        })?;
    }
    Ok(())
}

/// Clears `view` to black: the frame under the panel when the scene could not render.
pub(super) fn clear(gpu: &Gpu, view: &wgpu::TextureView) {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("clear"),
        });
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    gpu.queue.submit([encoder.finish()]);
}

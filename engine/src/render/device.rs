//! Adapter and device choice.
//!
//! Order: Vulkan first, then OpenGL (GL via EGL works on a bare Debian machine with
//! llvmpipe; Vulkan needs `mesa-vulkan-drivers` for lavapipe). `WGPU_BACKEND`
//! (comma-separated: `vulkan`, `gl`, …) restricts the backends tried, and
//! `WGPU_ADAPTER_NAME` picks the first adapter whose name contains it (case-insensitive).
//! Among the remaining adapters a discrete GPU beats an integrated one, which beats a
//! virtual one, which beats a CPU rasterizer.

use crate::error::{Error, Result};
use bevy_ecs::prelude::Resource;
use std::sync::Arc;

/// What the user sees of the chosen adapter.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// `vulkan`, `gl`, …
    pub backend: String,
    /// `discrete`, `integrated`, `virtual`, `cpu` or `other`.
    pub device_type: String,
    /// Driver name and version as the driver reports them.
    pub driver: String,
}

/// The GPU device the renderer draws with.
#[derive(Resource, Clone)]
pub struct Gpu {
    /// The adapter the device was created on.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Description of the adapter.
    pub summary: AdapterSummary,
    /// Whether GPU timestamp queries are available (per-pass GPU times).
    pub timestamps: bool,
    /// The WGSL sources the passes compile (built in, or reloaded from disk).
    pub shaders: crate::render::shaders::ShaderLibrary,
    /// Set by the device-lost callback: why the device was lost.
    lost: Arc<std::sync::Mutex<Option<String>>>,
}

/// Creates a presentation surface on an instance (used to pick an adapter that can
/// present to a window).
pub type SurfaceFactory<'a> =
    dyn Fn(&wgpu::Instance) -> std::result::Result<wgpu::Surface<'static>, String> + 'a;

/// Creates the display handle an instance needs to present with OpenGL (winit's
/// `OwnedDisplayHandle`).
pub type DisplayFactory<'a> = dyn Fn() -> Box<dyn wgpu::wgt::WgpuHasDisplayHandle> + 'a;

fn backend_name(backend: wgpu::Backend) -> &'static str {
    match backend {
        wgpu::Backend::Vulkan => "vulkan",
        wgpu::Backend::Gl => "gl",
        wgpu::Backend::Metal => "metal",
        wgpu::Backend::Dx12 => "dx12",
        wgpu::Backend::BrowserWebGpu => "webgpu",
        _ => "other",
    }
}

/// `vulkan+gl`-style names of a set of backends.
fn backends_label(backends: wgpu::Backends) -> String {
    backends
        .iter()
        .map(|b| match b {
            wgpu::Backends::VULKAN => "vulkan",
            wgpu::Backends::GL => "gl",
            wgpu::Backends::METAL => "metal",
            wgpu::Backends::DX12 => "dx12",
            wgpu::Backends::BROWSER_WEBGPU => "webgpu",
            _ => "other",
        })
        .collect::<Vec<_>>()
        .join("+")
}

fn device_type_rank(t: wgpu::DeviceType) -> (u8, &'static str) {
    match t {
        wgpu::DeviceType::DiscreteGpu => (0, "discrete"),
        wgpu::DeviceType::IntegratedGpu => (1, "integrated"),
        wgpu::DeviceType::VirtualGpu => (2, "virtual"),
        wgpu::DeviceType::Cpu => (3, "cpu"),
        wgpu::DeviceType::Other => (4, "other"),
    }
}

/// Parses `WGPU_BACKEND` into the list of backend sets to try, in order.
pub fn backends_to_try(env: Option<&str>) -> Result<Vec<wgpu::Backends>> {
    let Some(value) = env.map(str::trim).filter(|v| !v.is_empty()) else {
        return Ok(vec![wgpu::Backends::VULKAN, wgpu::Backends::GL]);
    };
    let mut list = Vec::new();
    for item in value.split(',').map(|s| s.trim().to_ascii_lowercase()) {
        let b = match item.as_str() {
            "vulkan" | "vk" => wgpu::Backends::VULKAN,
            "gl" | "gles" | "opengl" | "egl" => wgpu::Backends::GL,
            "metal" | "mtl" => wgpu::Backends::METAL,
            "dx12" | "d3d12" => wgpu::Backends::DX12,
            _ => {
                return Err(Error::InvalidArgument(format!(
                    "WGPU_BACKEND={value}: unknown backend '{item}' (use vulkan or gl)"
                )));
            }
        };
        list.push(b);
    }
    Ok(list)
}

/// Which adapters may be chosen.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GpuRequest {
    /// Backend sets to try, in order.
    pub backends: Vec<wgpu::Backends>,
    /// Only adapters whose name contains this (case-insensitive).
    pub adapter_name: Option<String>,
}

impl Default for GpuRequest {
    /// Vulkan, then GL; any adapter name.
    fn default() -> Self {
        GpuRequest {
            backends: vec![wgpu::Backends::VULKAN, wgpu::Backends::GL],
            adapter_name: None,
        }
    }
}

impl GpuRequest {
    /// The default request, overridden by `WGPU_BACKEND` and `WGPU_ADAPTER_NAME`.
    pub fn from_env() -> Result<GpuRequest> {
        let backend_env = std::env::var("WGPU_BACKEND").ok();
        Ok(GpuRequest {
            backends: backends_to_try(backend_env.as_deref())?,
            adapter_name: std::env::var("WGPU_ADAPTER_NAME")
                .ok()
                .map(|s| s.trim().to_string())
                .filter(|s| !s.is_empty()),
        })
    }

    /// Only the given backends (e.g. `wgpu::Backends::GL`), in order.
    pub fn backends(backends: &[wgpu::Backends]) -> GpuRequest {
        GpuRequest {
            backends: backends.to_vec(),
            adapter_name: None,
        }
    }
}

/// One Vulkan instance for the whole process. NVIDIA's Vulkan driver (580.159.04,
/// measured on an H100) stops listing its GPU after 29 instances have been created in one
/// process, even when every earlier one was dropped; reusing the instance, 80 devices in a
/// row were created without trouble. GL instances are not shared: devices of one EGL
/// display used from several threads at once fail with `BadAccess` (measured on
/// llvmpipe), so each GL app keeps its own.
fn shared_vulkan_instance(desc: wgpu::InstanceDescriptor) -> wgpu::Instance {
    static INSTANCE: std::sync::Mutex<Option<wgpu::Instance>> = std::sync::Mutex::new(None);
    let mut shared = INSTANCE.lock().unwrap_or_else(|e| e.into_inner());
    shared
        .get_or_insert_with(|| wgpu::Instance::new(desc))
        .clone()
}

impl Gpu {
    /// Picks an adapter for headless rendering (Vulkan, then GL, overridden by the
    /// environment) and creates the device.
    pub fn new_headless() -> Result<Gpu> {
        Ok(Gpu::new(&GpuRequest::from_env()?, None, None)?.0)
    }

    /// Picks an adapter as `request` says and creates the device; with a `surface` factory,
    /// only adapters that can present to that surface qualify, and the surface is returned
    /// too.
    pub fn new(
        request: &GpuRequest,
        surface: Option<&SurfaceFactory<'_>>,
        display: Option<&DisplayFactory<'_>>,
    ) -> Result<(Gpu, Option<wgpu::Surface<'static>>)> {
        let name_filter = request.adapter_name.as_ref().map(|s| s.to_lowercase());
        let mut tried = Vec::new();
        for &backends in &request.backends {
            let mut desc = match display {
                Some(make) => wgpu::InstanceDescriptor::new_with_display_handle(make()),
                None => wgpu::InstanceDescriptor::new_without_display_handle(),
            };
            desc.backends = backends;
            // Lumen issues no indirect draws or dispatches, so wgpu's indirect-call validation
            // (on by default) only costs a compute pipeline at device creation, which
            // NVIDIA's OpenGL driver rejects ("selected version doesn't support
            // COMPUTE_SHADER"), failing the device. WGPU_VALIDATION_INDIRECT_CALL=1 restores it.
            desc.flags = (wgpu::InstanceFlags::from_build_config()
                - wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL)
                .with_env();
            let instance = if display.is_none() && backends == wgpu::Backends::VULKAN {
                shared_vulkan_instance(desc)
            } else {
                wgpu::Instance::new(desc)
            };
            let surface = match surface {
                Some(make) => match make(&instance) {
                    Ok(s) => Some(s),
                    Err(e) => {
                        tried.push(format!(
                            "{backends:?}: cannot create a window surface ({e})"
                        ));
                        continue;
                    }
                },
                None => None,
            };
            let adapters = pollster::block_on(instance.enumerate_adapters(backends));
            let mut candidates: Vec<wgpu::Adapter> = adapters
                .into_iter()
                .filter(|a| {
                    let info = a.get_info();
                    name_filter
                        .as_ref()
                        .is_none_or(|f| info.name.to_lowercase().contains(f))
                })
                .filter(|a| surface.as_ref().is_none_or(|s| a.is_surface_supported(s)))
                .collect();
            candidates.sort_by_key(|a| device_type_rank(a.get_info().device_type).0);
            if candidates.is_empty() {
                tried.push(format!(
                    "{}: no adapter{}{}",
                    backends_label(backends),
                    name_filter
                        .as_ref()
                        .map(|f| format!(" whose name contains '{f}'"))
                        .unwrap_or_default(),
                    if surface.is_some() {
                        " that can present to the window"
                    } else {
                        ""
                    }
                ));
                continue;
            }
            for adapter in candidates {
                let name = adapter.get_info().name;
                match Gpu::from_adapter(adapter) {
                    Ok(gpu) => return Ok((gpu, surface)),
                    Err(e) => tried.push(format!("{}: {name}: {e}", backends_label(backends))),
                }
            }
        }
        let hint = if *request == GpuRequest::default() {
            " (install mesa-vulkan-drivers for lavapipe, or Mesa's EGL for llvmpipe)"
        } else {
            ""
        };
        Err(Error::NoAdapter(format!("{}{hint}", tried.join("; "))))
    }

    /// Creates the device on a chosen adapter and checks that it can run Lumen's shaders.
    pub fn from_adapter(adapter: wgpu::Adapter) -> Result<Gpu> {
        let info = adapter.get_info();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = wgpu::Features::empty();
        if timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        // Blending into an f32 HDR target (the transparent pass with `HdrPrecision::Full`).
        required_features |= adapter.features() & wgpu::Features::FLOAT32_BLENDABLE;
        let desc = wgpu::DeviceDescriptor {
            label: Some("lumen"),
            required_features,
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc))
            .map_err(|e| Error::Gpu(format!("cannot create a device on {}: {e}", info.name)))?;
        device.on_uncaptured_error(Arc::new(|e| {
            log::error!("uncaught GPU error: {e}");
        }));
        let lost = Arc::new(std::sync::Mutex::new(None));
        let lost_flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            log::error!("GPU device lost ({reason:?}): {message}");
            if let Ok(mut l) = lost_flag.lock() {
                *l = Some(format!("{reason:?}: {message}"));
            }
        });
        let driver = [info.driver.as_str(), info.driver_info.as_str()]
            .iter()
            .filter(|s| !s.is_empty())
            .copied()
            .collect::<Vec<_>>()
            .join(" ");
        let gpu = Gpu {
            summary: AdapterSummary {
                name: info.name.clone(),
                backend: backend_name(info.backend).to_string(),
                device_type: device_type_rank(info.device_type).1.to_string(),
                driver,
            },
            adapter,
            device,
            queue,
            timestamps,
            shaders: Default::default(),
            lost,
        };
        gpu.check_shader_support()?;
        Ok(gpu)
    }

    /// Compiles a minimal pipeline that reads storage buffers in a vertex and a fragment
    /// shader, as the G-buffer and lighting passes do. Some adapters advertise storage
    /// buffers but cannot compile them: NVIDIA's OpenGL driver gives wgpu a GL 3.3 context,
    /// whose GLSL 330 has none.
    fn check_shader_support(&self) -> Result<()> {
        const PROBE: &str = "
            @group(0) @binding(0) var<storage, read> data: array<vec4<f32>>;
            @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
                return data[i];
            }
            @fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
                return data[u32(p.x) % arrayLength(&data)];
            }";
        self.checked("capability probe", |device| {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("capability probe"),
                source: wgpu::ShaderSource::Wgsl(PROBE.into()),
            });
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("capability probe"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::TextureFormat::Rgba8Unorm.into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
        .map(|_| ())
        .map_err(|e| {
            let first = e
                .to_string()
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or_default()
                .trim()
                .to_string();
            Error::Gpu(format!(
                "cannot compile storage buffers in vertex and fragment shaders ({first})"
            ))
        })
    }

    /// Largest 2D texture side the device accepts.
    pub fn max_texture_size(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }

    /// Why the device was lost, if it was: nothing more can be rendered on it. wgpu
    /// reports a loss while it maintains the device, so after a failure call
    /// [`Gpu::poll_lost`].
    pub fn lost(&self) -> Option<String> {
        self.lost.lock().ok().and_then(|l| l.clone())
    }

    /// Lets wgpu maintain the device (a non-blocking poll, which reports a loss), then
    /// [`Gpu::lost`].
    pub fn poll_lost(&self) -> Option<String> {
        // A poll of a lost device fails; the loss itself is what this asks about.
        let _ = self.device.poll(wgpu::PollType::Poll);
        self.lost()
    }

    /// Runs `f` inside error scopes for every kind of GPU error (validation, internal —
    /// e.g. a shader the backend cannot translate — and out-of-memory) and turns a
    /// captured error into [`Error::Gpu`] naming `what`.
    pub fn checked<T>(&self, what: &str, f: impl FnOnce(&wgpu::Device) -> T) -> Result<T> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let internal = self.device.push_error_scope(wgpu::ErrorFilter::Internal);
        let value = f(&self.device);
        let errors = [
            pollster::block_on(internal.pop()),
            pollster::block_on(validation.pop()),
            pollster::block_on(oom.pop()),
        ];
        match errors.into_iter().flatten().next() {
            None => Ok(value),
            Some(e) => Err(Error::Gpu(format!("{what}: {e}"))),
        }
    }

    /// A uniform buffer of `size` bytes that the CPU writes (`COPY_DST`), zeroed.
    pub fn uniform_buffer(&self, label: &str, size: u64) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// A sampler filtering with `filter` in every direction, clamped to the edge.
    pub fn sampler(&self, label: &str, filter: wgpu::FilterMode) -> wgpu::Sampler {
        self.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some(label),
            mag_filter: filter,
            min_filter: filter,
            ..Default::default()
        })
    }

    /// A sampler filtering linearly between texels and between mip levels, clamped to the
    /// edge.
    pub fn mipmapped_sampler(&self, label: &str) -> wgpu::Sampler {
        self.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some(label),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backend_env_parsing() {
        assert_eq!(
            backends_to_try(None).ok(),
            Some(vec![wgpu::Backends::VULKAN, wgpu::Backends::GL])
        );
        assert_eq!(
            backends_to_try(Some("GL")).ok(),
            Some(vec![wgpu::Backends::GL])
        );
        assert_eq!(
            backends_to_try(Some("vulkan, gl")).ok(),
            Some(vec![wgpu::Backends::VULKAN, wgpu::Backends::GL])
        );
        let err = backends_to_try(Some("glide")).err().map(|e| e.to_string());
        assert!(err.is_some_and(|e| e.contains("glide")));
    }
}

//! The GPU path tracer (`shaders/path_trace.wgsl`): the CPU path tracer's unidirectional
//! estimator on the GPU, over the same [`TraceScene`], for the materials and lights it
//! supports ([`unsupported`] names the rest; the CLI's `--device auto` falls back to the
//! CPU for them). The scene's world-space hierarchy (the CPU path tracer's own) is uploaded
//! as one BLAS under an identity instance.

use super::scene_rays::{RAYS, SceneRays};
use crate::error::{Error, Result};
use crate::rays::tlas::{InstanceInput, RayScene, SURFACE_OPAQUE};
use crate::reference::path::traced_scene::{TraceEnvironment, TraceLight};
use crate::reference::path::{HDR_MAX, LightVisibility, ReferenceOptions, TraceScene, Traced};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use crate::render::shaders::ShaderDef;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

crate::choice::choices! {
/// Where `lumen reference` path-traces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TraceDevice: "device" {
    /// The GPU when the adapter is a hardware GPU and it traces everything in the scene,
    /// else the CPU.
    #[default]
    Auto = "auto",
    /// The GPU path tracer; an error for a scene it does not trace.
    Gpu = "gpu",
    /// The CPU path tracer, every feature and every estimator.
    Cpu = "cpu",
}
}

/// Whether `device` traces `scene` on the GPU of `adapter`, or why not (the CPU then).
pub fn choose_gpu(
    device: TraceDevice,
    adapter: &wgpu::AdapterInfo,
    scene: &TraceScene,
) -> std::result::Result<(), String> {
    let missing = unsupported(scene);
    match device {
        TraceDevice::Cpu => Err("--device cpu".into()),
        TraceDevice::Gpu | TraceDevice::Auto if !missing.is_empty() => Err(format!(
            "the GPU path tracer does not trace {} yet",
            missing.join(", ")
        )),
        TraceDevice::Auto if adapter.device_type == wgpu::DeviceType::Cpu => Err(format!(
            "the adapter ({}) is a software rasterizer on the CPU, where the CPU path tracer is faster",
            adapter.name
        )),
        TraceDevice::Gpu | TraceDevice::Auto => Ok(()),
    }
}

const BINDINGS: BindGroupSpec = BindGroupSpec::compute("path trace", declared::PATH_TRACE_0);

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtParams {
    world_from_clip: [[f32; 4]; 4],
    eye: [f32; 4],
    environment: [f32; 4],
    background: [f32; 4],
    size_sample: [u32; 4],
    counts: [u32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtMaterial {
    base_metallic: [f32; 4],
    params: [f32; 4],
    emitted: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtTriangle {
    n: [[f32; 4]; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtLight {
    a: [f32; 4],
    b: [f32; 4],
    c: [f32; 4],
    d: [f32; 4],
}

/// What the GPU path tracer does not trace in `scene` (empty: it traces all of it).
pub fn unsupported(scene: &TraceScene) -> Vec<&'static str> {
    let mut out = Vec::new();
    let mut add = |cond: bool, what: &'static str| {
        if cond && !out.contains(&what) {
            out.push(what);
        }
    };
    add(
        scene.camera.lens.is_some_and(|(radius, _)| radius > 0.0),
        "depth of field (a thin lens)",
    );
    add(
        matches!(scene.environment, TraceEnvironment::Image(_)),
        "an image environment",
    );
    for m in &scene.materials {
        add(m.maps.is_some(), "textures");
        add(m.blend, "alpha blending");
        add(m.transmission.is_some(), "transmission");
        add(m.clearcoat.is_some(), "clearcoat");
        add(m.sheen.is_some(), "sheen");
        add(m.anisotropy.is_some(), "anisotropy");
        add(m.specular_tint.is_some(), "a specular tint");
        add(m.iridescence.is_some(), "iridescence");
        add(m.diffuse_transmission.is_some(), "diffuse transmission");
    }
    out
}

fn light(l: &TraceLight, physical: bool) -> PtLight {
    let tested = if l.casts_shadows() || physical {
        1.0
    } else {
        0.0
    };
    match *l {
        TraceLight::Directional {
            direction_to_light,
            illuminance,
            tan_angular_radius,
            ..
        } => PtLight {
            a: direction_to_light.extend(0.0).into(),
            b: illuminance.extend(0.0).into(),
            c: [0.0, 0.0, 0.0, tan_angular_radius],
            d: [0.0, 0.0, tested, 0.0],
        },
        TraceLight::Point {
            position_m,
            intensity,
            inv_range2,
            ..
        } => PtLight {
            a: position_m.extend(1.0).into(),
            b: intensity.extend(inv_range2).into(),
            c: [0.0; 4],
            d: [0.0, 0.0, tested, 0.0],
        },
        TraceLight::Spot {
            position_m,
            axis,
            intensity,
            inv_range2,
            cone_scale,
            cone_offset,
            ..
        } => PtLight {
            a: position_m.extend(2.0).into(),
            b: intensity.extend(inv_range2).into(),
            c: axis.extend(0.0).into(),
            d: [cone_scale, cone_offset, tested, 0.0],
        },
    }
}

fn storage<T: Pod>(gpu: &Gpu, label: &str, data: &[T], fallback: T) -> wgpu::Buffer {
    let fallback = [fallback];
    let data: &[T] = if data.is_empty() { &fallback } else { data };
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(data),
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// Path-traces `scene` on the GPU: the mean of `samples_per_pixel` paths per pixel
/// (linear, pre-exposed, clamped to [`HDR_MAX`]), a path whose radiance is not finite
/// counted and left out, as [`crate::reference::path::render`] does. `progress` is called
/// with the samples done. An error naming what it does not trace when [`unsupported`]
/// is not empty.
pub fn render_gpu(
    gpu: &Gpu,
    scene: &TraceScene,
    options: &ReferenceOptions,
    progress: &dyn Fn(u32),
) -> Result<Traced> {
    let missing = unsupported(scene);
    if !missing.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "the GPU path tracer does not trace {} yet (use the CPU)",
            missing.join(", ")
        )));
    }
    let (w, h) = (options.size.0.max(1), options.size.1.max(1));
    let rays = SceneRays::with_scene(
        gpu,
        RayScene::new(
            &[scene.bvh.blas()],
            &[InstanceInput {
                blas: 0,
                world_from_local: Mat4::IDENTITY,
                surface: SURFACE_OPAQUE,
                material: 0,
            }],
        ),
    );
    let materials: Vec<PtMaterial> = scene
        .materials
        .iter()
        .map(|m| PtMaterial {
            base_metallic: m.base_color.extend(m.metallic).into(),
            params: [
                m.roughness,
                m.specular_level,
                f32::from(u8::from(m.unlit)),
                0.0,
            ],
            emitted: m.emitted().extend(0.0).into(),
        })
        .collect();
    let triangles: Vec<PtTriangle> = scene
        .corners
        .iter()
        .zip(&scene.material)
        .map(|(c, &m)| PtTriangle {
            n: [0, 1, 2].map(|k| {
                let w = if k == 0 { f32::from_bits(m) } else { 0.0 };
                c[k].normal.extend(w).into()
            }),
        })
        .collect();
    let physical = scene.light_visibility == LightVisibility::Physical;
    let lights: Vec<PtLight> = scene.lights.iter().map(|l| light(l, physical)).collect();
    let (table, table_size) = scene
        .energy_compensation
        .as_ref()
        .map_or((vec![1.0], 0), |t| (t.values().to_vec(), t.size() as u32));
    let environment = match scene.environment {
        TraceEnvironment::Uniform(c) => c.extend(1.0),
        _ => Vec3::ZERO.extend(0.0),
    };
    let model = scene.visibility as u32;
    let seed = (options.seed ^ (options.seed >> 32)) as u32;
    let params = |sample: u32| PtParams {
        world_from_clip: scene.camera.world_from_clip.to_cols_array_2d(),
        eye: scene
            .camera
            .position
            .extend(f32::from_bits(seed.wrapping_mul(0x9e37_79b9) ^ 0x85eb_ca6b))
            .into(),
        environment: environment.into(),
        background: scene.background.map_or([0.0; 4], |c| c.extend(1.0).into()),
        size_sample: [w, h, sample, options.max_bounces.max(1)],
        counts: [lights.len() as u32, model, table_size, 0],
    };
    let uniform = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("path trace: params"),
        size: std::mem::size_of::<PtParams>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let zero_material = PtMaterial::zeroed();
    let buffers = [
        storage(gpu, "path trace: materials", &materials, zero_material),
        storage(
            gpu,
            "path trace: triangles",
            &triangles,
            PtTriangle::zeroed(),
        ),
        storage(gpu, "path trace: lights", &lights, PtLight::zeroed()),
        storage(gpu, "path trace: compensation", &table, 1.0f32),
    ];
    let sum = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("path trace: sum"),
        size: u64::from(w) * u64::from(h) * 16,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let composed = gpu
        .shaders
        .compose("path_trace.wgsl", &[ShaderDef::U32("RAYS_GROUP", 1)])?;
    let module = create_module(gpu, "path trace", &composed)?;
    let (own_layout, rays_layout) = (BINDINGS.layout(gpu), RAYS.layout(gpu));
    let layout = pipeline_layout(gpu, "path trace", &[&own_layout, &rays_layout]);
    let pipeline = compute_pipeline(gpu, "path trace", Some(&layout), &module, "cs_path_trace")?;
    let mut resources = vec![uniform.as_entire_binding()];
    resources.extend(buffers.iter().map(|b| b.as_entire_binding()));
    resources.push(sum.as_entire_binding());
    let own = BINDINGS.group(gpu, &own_layout, resources)?;
    let rays_group = RAYS.group(
        gpu,
        &rays_layout,
        rays.resources()
            .ok_or_else(|| Error::Gpu("no ray structure".into()))?,
    )?;
    let spp = options.samples_per_pixel.max(1);
    for sample in 0..spp {
        gpu.queue
            .write_buffer(&uniform, 0, bytemuck::bytes_of(&params(sample)));
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("path trace"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("path trace"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &own, &[]);
            pass.set_bind_group(1, &rays_group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        let index = gpu.queue.submit([encoder.finish()]);
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            })
            .map_err(|e| Error::Gpu(format!("waiting for a path-tracing sample: {e}")))?;
        progress(sample + 1);
    }
    let encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("path trace: readback"),
        });
    let bytes = crate::render::readback::read_buffer(gpu, encoder, &sum)?;
    let sums: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    let mut image = image::Rgba32FImage::new(w, h);
    let mut dropped = 0u64;
    for (out, s) in image.pixels_mut().zip(sums) {
        let kept = s[3].max(0.0);
        dropped += u64::from(spp) - kept as u64;
        let mean = |c: f32| (f64::from(c) / f64::from(kept.max(1.0))).min(HDR_MAX) as f32;
        out.0 = [mean(s[0]), mean(s[1]), mean(s[2]), 1.0];
    }
    Ok(Traced {
        image,
        dropped_samples: dropped,
    })
}

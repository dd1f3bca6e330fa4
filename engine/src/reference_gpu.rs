//! The GPU path tracer (`shaders/path_trace.wgsl`), where the reference meets the
//! renderer's ray core (as [`crate::trace_input`] is where it meets extraction, so that
//! [`crate::reference`] depends on nothing in [`crate::render`]): the CPU path tracer's
//! unidirectional estimator on the GPU, over the same [`TraceScene`], for the materials and lights it
//! supports ([`unsupported`] names the rest; the CLI's `--device auto` falls back to the
//! CPU for them). The scene's world-space hierarchy (the CPU path tracer's own) is uploaded
//! as one BLAS under an identity instance.

use crate::error::{Error, Result};
use crate::rays::tlas::{InstanceInput, RayScene, SURFACE_BLENDED, SURFACE_OPAQUE};
use crate::reference::path::traced_scene::{TraceEnvironment, TraceLight};
use crate::reference::path::{HDR_MAX, LightVisibility, ReferenceOptions, TraceScene, Traced};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use crate::render::rays::scene_rays::{RAYS, RAYS_GROUP, SceneRays};
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

/// The path tracer's own group (0): parameters, materials, triangles, lights, the
/// compensation table and the running sum.
pub const BINDINGS: BindGroupSpec = BindGroupSpec::compute("path trace", declared::PATH_TRACE_0);

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtParams {
    world_from_clip: [[f32; 4]; 4],
    eye: [f32; 4],
    environment: [f32; 4],
    background: [f32; 4],
    size_sample: [u32; 4],
    counts: [u32; 4],
    lens_right: [f32; 4],
    lens_up: [f32; 4],
    forward: [f32; 4],
    /// The image environment in the data buffer: first word of its texels, of its row
    /// table and of its column tables, and its width (0: no image).
    image: [u32; 4],
    /// Its height, its rotation about +y and its total weight (f32 bits), unused.
    image_size: [u32; 4],
    /// Samples per pixel this dispatch adds, unused ×3.
    batch: [u32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtMaterial {
    base_metallic: [f32; 4],
    params: [f32; 4],
    emissive: [f32; 4],
    /// Slots of base colour, metallic-roughness, normal and emissive maps in the data
    /// buffer's slot table (`NO_SLOT`: none).
    maps: [u32; 4],
    /// Normal scale, alpha, alpha cutoff (−1: not masked), 1 where the material has maps
    /// (its vertex colour and textures apply).
    alpha: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PtTriangle {
    n: [[f32; 4]; 3],
    /// Per corner: texture coordinates of sets 0 (xy) and 1 (zw).
    uv: [[f32; 4]; 3],
    /// Per corner: linear vertex colour.
    color: [[f32; 4]; 3],
    /// Per corner: tangent and handedness.
    tangent: [[f32; 4]; 3],
}

/// No texture in this slot.
const NO_SLOT: u32 = u32::MAX;
/// Words of one slot in the data buffer.
const SLOT_WORDS: usize = 12;

/// The data buffer: the compensation table (f32 bits) from word 0, then the texture
/// slots (`SLOT_WORDS` each: first texel word, width, height, flags — bit 0 sRGB, bit 1
/// nearest, bits 2–3 and 4–5 the wrap modes of u and v, bit 6 texture coordinate set 1 —
/// and the transform's two rows as f32 bits), then every texture's texels (RGBA8, one
/// word each). Returns the words, the first slot's word and each material's map slots.
fn data_words(scene: &TraceScene, table: &[f32]) -> (Vec<u32>, u32, Vec<[u32; 4]>) {
    use crate::scene::{ColorSpace, Filter, Wrap};
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => 0u32,
        Wrap::MirroredRepeat => 1,
        Wrap::ClampToEdge => 2,
    };
    let mut words: Vec<u32> = table.iter().map(|v| v.to_bits()).collect();
    let slots_at = words.len() as u32;
    let mut slots: Vec<&crate::reference::path::textures::TraceSlot> = Vec::new();
    let maps: Vec<[u32; 4]> = scene
        .maps
        .iter()
        .map(|m| {
            [0usize, 1, 2, 4].map(|k| {
                m.slots[k].as_ref().map_or(NO_SLOT, |slot| {
                    slots.push(slot);
                    slots.len() as u32 - 1
                })
            })
        })
        .collect();
    let mut texel_at = slots_at as usize + slots.len() * SLOT_WORDS;
    let mut texels = Vec::new();
    for slot in &slots {
        let t = slot.texture();
        let s = slot.slot();
        let flags = u32::from(t.color_space == ColorSpace::Srgb)
            | u32::from(s.sampler.mag == Filter::Nearest) << 1
            | wrap(s.sampler.wrap_u) << 2
            | wrap(s.sampler.wrap_v) << 4
            | u32::from(s.uv_set == 1) << 6;
        let [r0, r1] = slot.rows();
        words.extend([texel_at as u32, t.width.max(1), t.height.max(1), flags]);
        words.extend([r0.x, r0.y, r0.z, r1.x, r1.y, r1.z].map(f32::to_bits));
        words.extend([0, 0]);
        let count = t.width.max(1) as usize * t.height.max(1) as usize;
        texels.extend((0..count).map(|i| {
            t.rgba8
                .get(4 * i..4 * i + 4)
                .map_or(u32::MAX, |p| u32::from_le_bytes([p[0], p[1], p[2], p[3]]))
        }));
        texel_at += count;
    }
    words.extend(texels);
    (words, slots_at, maps)
}

/// Appends the image environment's texels (3 words each), row table and column tables to
/// `words`; the params' `image` and `image_size` (zeros without an image).
fn environment_words(scene: &TraceScene, words: &mut Vec<u32>) -> ([u32; 4], [u32; 4]) {
    let TraceEnvironment::Image(img) = &scene.environment else {
        return ([0; 4], [0; 4]);
    };
    let t = img.tables();
    let texels_at = words.len() as u32;
    words.extend(
        t.texels
            .iter()
            .flat_map(|c| [c.x, c.y, c.z])
            .map(f32::to_bits),
    );
    let rows_at = words.len() as u32;
    words.extend(t.rows.iter().map(|v| v.to_bits()));
    let columns_at = words.len() as u32;
    words.extend(t.columns.iter().map(|v| v.to_bits()));
    (
        [texels_at, rows_at, columns_at, t.width as u32],
        [t.height as u32, t.rotation.to_bits(), t.total.to_bits(), 0],
    )
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
    for m in &scene.materials {
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
    let (table, table_size) = scene
        .energy_compensation
        .as_ref()
        .map_or((Vec::new(), 0), |t| (t.values().to_vec(), t.size() as u32));
    let (mut data, slots_at, material_slots) = data_words(scene, &table);
    let (image, image_size) = environment_words(scene, &mut data);
    let materials: Vec<PtMaterial> = scene
        .materials
        .iter()
        .map(|m| {
            let maps = m.maps.and_then(|i| scene.maps.get(i as usize));
            PtMaterial {
                base_metallic: m.base_color.extend(m.metallic).into(),
                params: [
                    m.roughness,
                    m.specular_level,
                    f32::from(u8::from(m.unlit)),
                    f32::from(u8::from(m.blend)),
                ],
                emissive: m.emissive.extend(0.0).into(),
                maps: m
                    .maps
                    .and_then(|i| material_slots.get(i as usize).copied())
                    .unwrap_or([NO_SLOT; 4]),
                alpha: [
                    maps.map_or(1.0, |m| m.normal_scale),
                    m.alpha,
                    maps.and_then(|m| m.alpha_cutoff).unwrap_or(-1.0),
                    f32::from(u8::from(maps.is_some())),
                ],
            }
        })
        .collect();
    let masked = materials
        .iter()
        .any(|m| m.alpha[2] >= 0.0 || m.params[3] > 0.0);
    let triangles: Vec<PtTriangle> = scene
        .corners
        .iter()
        .zip(&scene.material)
        .map(|(c, &m)| PtTriangle {
            n: [0, 1, 2].map(|k| {
                let w = if k == 0 { f32::from_bits(m) } else { 0.0 };
                c[k].normal.extend(w).into()
            }),
            uv: c.map(|c| [c.uv[0].x, c.uv[0].y, c.uv[1].x, c.uv[1].y]),
            color: c.map(|c| c.color.into()),
            tangent: c.map(|c| c.tangent.into()),
        })
        .collect();
    let rays = SceneRays::with_scene(
        gpu,
        RayScene::new(
            &[scene.bvh.blas()],
            &[InstanceInput {
                blas: 0,
                world_from_local: Mat4::IDENTITY,
                // The callback decides per material, masked or blended.
                surface: if masked {
                    SURFACE_BLENDED
                } else {
                    SURFACE_OPAQUE
                },
                material: 0,
            }],
        ),
    );
    let physical = scene.light_visibility == LightVisibility::Physical;
    let lights: Vec<PtLight> = scene.lights.iter().map(|l| light(l, physical)).collect();
    // w: 0 no environment, 1 uniform, 2 an image.
    let environment = match scene.environment {
        TraceEnvironment::None => Vec3::ZERO.extend(0.0),
        TraceEnvironment::Uniform(c) => c.extend(1.0),
        TraceEnvironment::Image(_) => Vec3::ZERO.extend(2.0),
    };
    let model = scene.visibility as u32;
    let seed = (options.seed ^ (options.seed >> 32)) as u32;
    // The thin lens: aperture radius (m; 0 for a pinhole) and focus distance (m; 0 for
    // none, at infinity).
    let (radius, focus) = match scene.camera.lens {
        Some((r, f)) if r > 0.0 => (r, if f.is_finite() { f } else { 0.0 }),
        _ => (0.0, 0.0),
    };
    let params = |sample: u32, batch: u32| PtParams {
        world_from_clip: scene.camera.world_from_clip.to_cols_array_2d(),
        eye: scene
            .camera
            .position
            .extend(f32::from_bits(seed.wrapping_mul(0x9e37_79b9) ^ 0x85eb_ca6b))
            .into(),
        environment: environment.into(),
        background: scene.background.map_or([0.0; 4], |c| c.extend(1.0).into()),
        size_sample: [w, h, sample, options.max_bounces.max(1)],
        counts: [lights.len() as u32, model, table_size, slots_at],
        lens_right: scene.camera.basis.x_axis.extend(radius).into(),
        lens_up: scene.camera.basis.y_axis.extend(focus).into(),
        forward: scene.camera.basis.z_axis.extend(0.0).into(),
        image,
        image_size,
        batch: [batch, 0, 0, 0],
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
        storage(gpu, "path trace: data", &data, 0u32),
    ];
    let sum = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("path trace: sum"),
        size: u64::from(w) * u64::from(h) * 16,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let composed = gpu.shaders.compose(
        "path_trace.wgsl",
        &[ShaderDef::U32("RAYS_GROUP", RAYS_GROUP)],
    )?;
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
    // Paths per dispatch: about 2¹⁵ and at most 16 per pixel (one dispatch per sample
    // from 182×182 up), so that progress moves, no dispatch runs long enough to trip a
    // driver's watchdog, and a small image does not pay a dispatch per sample. More per
    // pixel is slower on lavapipe: a SIMD lane that finishes its paths waits for the
    // slowest in its group.
    let per_dispatch = ((1u64 << 15) / (u64::from(w) * u64::from(h))).clamp(1, 16) as u32;
    let mut sample = 0;
    while sample < spp {
        let batch = per_dispatch.min(spp - sample);
        gpu.queue
            .write_buffer(&uniform, 0, bytemuck::bytes_of(&params(sample, batch)));
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
            .map_err(|e| Error::Gpu(format!("waiting for path-tracing samples: {e}")))?;
        sample += batch;
        progress(sample);
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

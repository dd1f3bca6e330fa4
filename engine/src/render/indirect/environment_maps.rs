//! Image-based lighting on the GPU: preprocessing of environment images (once per image,
//! cached), the split-sum BRDF table (once per renderer), and the per-frame environment
//! uniform the lighting and sky passes read.
//!
//! Preprocessing of an image, each step timed:
//! 1. upload the sanitized equirect as `Rgba16Float`;
//! 2. project it on 9 spherical harmonics on the CPU (diffuse irradiance);
//! 3. resample it into a cube map (face side: the next power of two of width/4, 32–1024);
//! 4. build the cube's mip pyramid by 2×2 averaging (energy-preserving);
//! 5. prefilter a second cube, mip m for perceptual roughness m/(mips − 1), by GGX
//!    importance sampling with filtered sampling from the pyramid.

use crate::error::{Error, Result};
use crate::quality::Quality;
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameErrors;
use crate::render::gpu_types::GpuEnvironment;
use crate::render::pipelines::fullscreen_pipeline;
use crate::render::pipelines::{compute_pipeline, create_module};
use crate::render::shaders::ShaderDef;
use crate::render::targets::Target;
use crate::scene::environment::EquirectImage;
use crate::shading::ibl::{sh_project, sh_uniform};
use bevy_ecs::prelude::*;
use glam::Vec3;
use std::collections::HashMap;
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Format of the environment cube maps.
pub const CUBE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the split-sum BRDF table (two channels: A and B).
pub const LUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;
/// Most prefiltered mips (roughness 0, 1/6, …, 1 for 7).
pub const MAX_PREFILTERED_MIPS: u32 = 7;

/// An environment image ready for shading.
pub struct PreparedEnvironment {
    /// The GGX-prefiltered cube map: mip m for perceptual roughness m / (mips − 1).
    pub specular: wgpu::Texture,
    /// A cube view of all its mips.
    pub view: wgpu::TextureView,
    /// Number of prefiltered mips.
    pub mips: u32,
    /// Spherical harmonics of the radiance (bands 0–2, RGB), before the intensity.
    pub sh: [Vec3; 9],
    /// How long each preprocessing step took (ms).
    pub steps: Vec<(&'static str, f64)>,
    /// The source cube map (mip pyramid), kept for tests and debug views.
    pub source: wgpu::Texture,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    size: u32,
    mip: u32,
    mips: u32,
    samples: u32,
    source_size: f32,
    pad: [f32; 3],
}

/// A cube map's source pyramid and its GGX prefiltering ([`Ibl::prefilter_strip`]).
pub struct PrefilteredCube {
    /// The GGX-prefiltered cube: mip m for perceptual roughness m / (mips − 1).
    pub specular: wgpu::Texture,
    /// A cube view of all its mips.
    pub view: wgpu::TextureView,
    /// Number of prefiltered mips.
    pub mips: u32,
    /// The source cube (mip pyramid).
    pub source: wgpu::Texture,
    /// How long each step took (ms).
    pub steps: Vec<(&'static str, f64)>,
}

/// The bind group of indirect light that the lighting and reflection passes share: the
/// environment (split-sum image-based lighting) and the AO pass's occlusion.
pub const ENVIRONMENT: BindGroupSpec =
    BindGroupSpec::fragment("lighting: environment", declared::LIGHTING_2);

/// The GPU side of image-based lighting.
#[derive(Resource)]
pub struct Ibl {
    equirect_to_cube: wgpu::ComputePipeline,
    downsample: wgpu::ComputePipeline,
    prefilter: wgpu::ComputePipeline,
    /// Linear, mip-mapped, clamped: cube maps and the BRDF table.
    pub sampler: wgpu::Sampler,
    /// Linear, repeating in u (the equirect's longitude).
    equirect_sampler: wgpu::Sampler,
    /// The split-sum BRDF table, once built: (target, size, samples).
    pub lut: Option<(Target, u32, u32)>,
    dummy_lut: Target,
    cache: HashMap<(u64, u32), PreparedEnvironment>,
    dummy_cube: wgpu::TextureView,
    /// The environment uniform ([`GpuEnvironment`]).
    pub uniform: wgpu::Buffer,
    /// The cube view the passes bind this frame: the prepared environment or a 1×1 dummy.
    pub bound_cube: Option<(u64, u32)>,
    /// Preprocessing steps run during the last frame, its probe captures included (ms);
    /// the app clears it before each frame.
    pub last_steps: Vec<(String, f64)>,
    /// Called with (step, done, total) while an environment is prefiltered.
    progress: Option<Progress>,
}

/// A progress callback: step name, steps done, steps in all.
pub type Progress = Box<dyn FnMut(&str, u32, u32) + Send + Sync>;

/// The split-sum table's shader defs: `size`² texels, `samples` importance samples per
/// texel (at least 1).
pub fn lut_defs(size: u32, samples: u32) -> Vec<ShaderDef> {
    vec![
        ShaderDef::U32("LUT_SAMPLES", samples.max(1)),
        ShaderDef::U32("LUT_SIZE", size),
    ]
}

/// An `Rgba16Float` cube texture of `size`² faces and `mips` mips.
pub fn cube_texture(gpu: &Gpu, label: &str, size: u32, mips: u32) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 6,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: CUBE_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// A cube view of all of `texture`'s mips.
pub fn cube_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    })
}

/// A face strip: the six faces of one cube mip of `size`² texels side by side in a 2D
/// texture, written by the preprocessing shaders and copied into the cube.
pub fn face_strip(gpu: &Gpu, size: u32) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("environment face strip"),
        size: wgpu::Extent3d {
            width: size * 6,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: CUBE_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Copies the face strip `strip` into mip `mip` (of `size`² texels per face) of `cube`.
fn copy_strip_to_cube(
    encoder: &mut wgpu::CommandEncoder,
    strip: &wgpu::Texture,
    cube: &wgpu::Texture,
    mip: u32,
    size: u32,
) {
    for face in 0..6 {
        encoder.copy_texture_to_texture(
            wgpu::TexelCopyTextureInfo {
                texture: strip,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: face * size,
                    y: 0,
                    z: 0,
                },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyTextureInfo {
                texture: cube,
                mip_level: mip,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: face,
                },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
        );
    }
}

fn layer_view(texture: &wgpu::Texture, mip: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_mip_level: mip,
        mip_level_count: Some(1),
        base_array_layer: 0,
        array_layer_count: Some(6),
        ..Default::default()
    })
}

impl Ibl {
    /// Compiles the preprocessing pipelines.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let source = gpu.shaders.compose("ibl_preprocess.wgsl", &[])?;
        let module = create_module(gpu, "ibl preprocessing", &source)?;
        let dummy = cube_texture(gpu, "dummy environment", 1, 1);
        Ok(Ibl {
            equirect_to_cube: compute_pipeline(
                gpu,
                "cs_equirect_to_cube",
                None,
                &module,
                "cs_equirect_to_cube",
            )?,
            downsample: compute_pipeline(gpu, "cs_downsample", None, &module, "cs_downsample")?,
            prefilter: compute_pipeline(gpu, "cs_prefilter", None, &module, "cs_prefilter")?,
            sampler: gpu.mipmapped_sampler("ibl linear"),
            equirect_sampler: gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("equirect"),
                address_mode_u: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            lut: None,
            dummy_lut: Target::new(gpu, "dummy brdf lut", (1, 1), LUT_FORMAT),
            cache: HashMap::new(),
            dummy_cube: cube_view(&dummy),
            uniform: gpu
                .uniform_buffer("environment", std::mem::size_of::<GpuEnvironment>() as u64),
            bound_cube: None,
            last_steps: Vec::new(),
            progress: None,
        })
    }

    /// Reports preprocessing progress to `progress` (e.g. a terminal progress bar).
    pub fn set_progress(&mut self, progress: Progress) {
        self.progress = Some(progress);
    }

    /// Removes and returns the progress callback (to move it to a new `Ibl`).
    pub fn take_progress(&mut self) -> Option<Progress> {
        self.progress.take()
    }

    fn report(&mut self, step: &str, done: u32, total: u32) {
        if let Some(p) = self.progress.as_mut() {
            p(step, done, total);
        }
    }

    /// The cube view to bind: the prepared environment's, or a 1×1 dummy.
    pub fn cube_view(&self) -> &wgpu::TextureView {
        self.bound_cube
            .and_then(|k| self.cache.get(&k))
            .map_or(&self.dummy_cube, |p| &p.view)
    }

    /// The BRDF table view to bind (a 1×1 dummy until one is built).
    pub fn lut_view(&self) -> &wgpu::TextureView {
        self.lut
            .as_ref()
            .map_or(&self.dummy_lut.view, |(t, _, _)| &t.view)
    }

    /// The prepared environment of `image` at `samples` prefilter samples, if prepared.
    pub fn prepared(&self, image: &EquirectImage, samples: u32) -> Option<&PreparedEnvironment> {
        self.cache.get(&(image.id, samples))
    }

    fn run(gpu: &Gpu, label: &str, record: impl FnOnce(&mut wgpu::CommandEncoder)) -> Result<f64> {
        let start = Instant::now();
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        record(&mut encoder);
        let index = gpu.checked(label, |_| gpu.queue.submit([encoder.finish()]))?;
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            })
            .map_err(|e| Error::Gpu(format!("{label}: {e}")))?;
        Ok(start.elapsed().as_secs_f64() * 1e3)
    }

    fn dispatch(
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        params: Params,
        extra: &[wgpu::BindGroupEntry],
    ) {
        let params_buffer = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ibl params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: params_buffer.as_entire_binding(),
        }];
        entries.extend_from_slice(extra);
        let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ibl preprocessing"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ibl preprocessing"),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &group, &[]);
        let groups = params.size.div_ceil(8);
        pass.dispatch_workgroups(groups, groups, 6);
    }

    /// Builds the mip pyramid of a cube whose level 0 is `strip` (six faces of `size`²
    /// texels side by side, as the preprocessing shaders write them) and prefilters it with
    /// `samples` GGX samples per texel: steps 4 and 5 of the module's list, for an
    /// environment image and for a reflection probe's capture alike. At most `max_mips`
    /// prefiltered mips (and [`MAX_PREFILTERED_MIPS`]). `progress`, when given, numbers the
    /// steps (first, total) for the progress callback.
    pub fn prefilter_strip(
        &mut self,
        gpu: &Gpu,
        strip: wgpu::Texture,
        size: u32,
        samples: u32,
        max_mips: u32,
        progress: Option<(u32, u32)>,
    ) -> Result<PrefilteredCube> {
        let (first_step, total) = progress.unwrap_or((0, 0));
        let report = progress.is_some();
        let source_mips = size.ilog2() + 1;
        let mips = source_mips.min(MAX_PREFILTERED_MIPS).min(max_mips.max(1));
        let base = Params {
            size,
            mip: 0,
            mips: 0,
            samples,
            source_size: size as f32,
            pad: [0.0; 3],
        };
        let source = cube_texture(gpu, "environment source cube", size, source_mips);
        if report {
            self.report("cube mips", first_step, total);
        }
        let mut strip = strip;
        let ms = Ibl::run(gpu, "cube mips", |encoder| {
            copy_strip_to_cube(encoder, &strip, &source, 0, size);
            for mip in 1..source_mips {
                let level_size = (size >> mip).max(1);
                let next = face_strip(gpu, level_size);
                Ibl::dispatch(
                    gpu,
                    encoder,
                    &self.downsample,
                    Params {
                        size: level_size,
                        mip,
                        ..base
                    },
                    &[
                        wgpu::BindGroupEntry {
                            binding: 5,
                            resource: wgpu::BindingResource::TextureView(
                                &strip.create_view(&Default::default()),
                            ),
                        },
                        wgpu::BindGroupEntry {
                            binding: 6,
                            resource: wgpu::BindingResource::TextureView(
                                &next.create_view(&Default::default()),
                            ),
                        },
                    ],
                );
                copy_strip_to_cube(encoder, &next, &source, mip, level_size);
                strip = next;
            }
        })?;
        let mut steps = vec![("cube mips", ms)];
        let specular = cube_texture(gpu, "environment specular cube", size, mips);
        let source_cube = cube_view(&source);
        // One submission per mip, so that a large environment reports progress.
        let mut ms = 0.0;
        for mip in 0..mips {
            if report {
                self.report("ggx prefilter", first_step + 1 + mip, total);
            }
            ms += Ibl::run(gpu, "ggx prefilter", |encoder| {
                Ibl::dispatch(
                    gpu,
                    encoder,
                    &self.prefilter,
                    Params {
                        size: size >> mip,
                        mip,
                        mips,
                        ..base
                    },
                    &[
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&layer_view(
                                &specular, mip,
                            )),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::Sampler(&self.sampler),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: wgpu::BindingResource::TextureView(&source_cube),
                        },
                    ],
                );
            })?;
        }
        if report {
            self.report("done", total, total);
        }
        steps.push(("ggx prefilter", ms));
        Ok(PrefilteredCube {
            view: cube_view(&specular),
            specular,
            mips,
            source,
            steps,
        })
    }

    /// Prefilters `image` (once per image and sample count; later calls return the cached
    /// result) and records the time of each step.
    pub fn prepare_image(
        &mut self,
        gpu: &Gpu,
        image: &EquirectImage,
        samples: u32,
    ) -> Result<&PreparedEnvironment> {
        let key = (image.id, samples);
        if self.cache.contains_key(&key) {
            return self
                .cache
                .get(&key)
                .ok_or_else(|| Error::Gpu("environment cache".into()));
        }
        let mut steps: Vec<(&'static str, f64)> = Vec::new();
        let size = (image.width / 4).next_power_of_two().clamp(32, 1024);
        let total = 4 + (size.ilog2() + 1).min(MAX_PREFILTERED_MIPS);
        self.report("upload", 0, total);

        let t = Instant::now();
        // Checked before any GPU call: an image past the device's 2D limit is box-filtered
        // down to it on the CPU, with a warning.
        let limit = gpu.device.limits().max_texture_dimension_2d;
        let fitted = image.downscaled_to_fit(limit);
        if let Some(small) = &fitted {
            log::warn!(
                "{}: {}×{} exceeds the device's texture limit of {limit}: downscaled to {}×{}",
                image
                    .path
                    .as_ref()
                    .map_or("environment".into(), |p| p.display().to_string()),
                image.width,
                image.height,
                small.width,
                small.height
            );
        }
        let image = fitted.as_ref().unwrap_or(image);
        let data: Vec<half::f16> = image
            .texels
            .iter()
            .flat_map(|t| [t[0], t[1], t[2], 1.0].map(half::f16::from_f32))
            .collect();
        let equirect = gpu.device.create_texture_with_data(
            &gpu.queue,
            &wgpu::TextureDescriptor {
                label: Some("environment equirect"),
                size: wgpu::Extent3d {
                    width: image.width,
                    height: image.height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: CUBE_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&data),
        );
        steps.push(("upload", t.elapsed().as_secs_f64() * 1e3));

        self.report("spherical harmonics", 1, total);
        let t = Instant::now();
        let sh = sh_project(image.width, image.height, &image.texels);
        steps.push(("spherical harmonics", t.elapsed().as_secs_f64() * 1e3));

        self.report("equirect to cube", 2, total);
        // Every mip of the source cube is computed into a face strip (a 2D texture with the
        // six faces side by side) and copied into the cube; each downsample reads the
        // previous strip. This is for GL, where a cube can be neither sampled as a 2D array
        // nor copied from, and where sampling mip n−1 of a texture sets its level range to
        // n−1 so that an image store into mip n of the same texture is dropped.
        let equirect_view = equirect.create_view(&Default::default());
        let base = Params {
            size,
            mip: 0,
            mips: 0,
            samples,
            source_size: size as f32,
            pad: [0.0; 3],
        };
        let strip = face_strip(gpu, size);
        let ms = Ibl::run(gpu, "equirect to cube", |encoder| {
            Ibl::dispatch(
                gpu,
                encoder,
                &self.equirect_to_cube,
                base,
                &[
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&self.equirect_sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&equirect_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 6,
                        resource: wgpu::BindingResource::TextureView(
                            &strip.create_view(&Default::default()),
                        ),
                    },
                ],
            );
        })?;
        steps.push(("equirect to cube", ms));
        let prefiltered = self.prefilter_strip(
            gpu,
            strip,
            size,
            samples,
            MAX_PREFILTERED_MIPS,
            Some((3, total)),
        )?;
        steps.extend(prefiltered.steps);
        self.cache.insert(
            key,
            PreparedEnvironment {
                specular: prefiltered.specular,
                view: prefiltered.view,
                mips: prefiltered.mips,
                sh,
                steps,
                source: prefiltered.source,
            },
        );
        self.cache
            .get(&key)
            .ok_or_else(|| Error::Gpu("environment cache".into()))
    }

    /// Builds the split-sum BRDF table of `size`² texels with `samples` samples per texel,
    /// unless one of that size and sample count exists. Returns the time taken (ms).
    pub fn ensure_lut(&mut self, gpu: &Gpu, size: u32, samples: u32) -> Result<Option<f64>> {
        let size = size.clamp(8, 1024);
        if self
            .lut
            .as_ref()
            .is_some_and(|(_, s, n)| *s == size && *n == samples)
        {
            return Ok(None);
        }
        let start = Instant::now();
        let source = gpu
            .shaders
            .compose("brdf_lut.wgsl", &lut_defs(size, samples))?;
        let module = create_module(gpu, "brdf lut", &source)?;
        let pipeline = fullscreen_pipeline(
            gpu,
            "brdf lut",
            None,
            &module,
            ("vs_fullscreen", "fs_brdf_lut"),
            &[LUT_FORMAT],
            None,
        )?;
        let target = Target::new(gpu, "brdf lut", (size, size), LUT_FORMAT);
        Ibl::run(gpu, "brdf lut", |encoder| {
            let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("brdf lut"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            rp.set_pipeline(&pipeline);
            rp.draw(0..3, 0..1);
        })?;
        self.lut = Some((target, size, samples));
        Ok(Some(start.elapsed().as_secs_f64() * 1e3))
    }
}

/// Prefilters the frame's environment (first use only), builds the BRDF table when
/// anything needs it (the environment, energy compensation, the probes, or a clearcoat,
/// opaque or blended, whose albedo reads it), and writes the pre-exposed environment
/// uniform.
pub fn prepare_ibl(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    quality: Res<Quality>,
    mut ibl: ResMut<Ibl>,
    mut errors: ResMut<FrameErrors>,
) {
    let ibl = &mut *ibl;
    let exposure = frame.camera.as_ref().map_or(1.0, |c| c.exposure);
    let env = frame.environment.as_ref();
    if env.is_some()
        || quality.energy_compensation
        || quality.gi.enabled
        || quality.reflection_probes.enabled
        || frame.material_maps.iter().any(|m| m.clearcoat.is_some())
    {
        match ibl.ensure_lut(&gpu, quality.brdf_lut_size, quality.brdf_lut_samples) {
            Ok(Some(ms)) => ibl.last_steps.push(("brdf lut".into(), ms)),
            Ok(None) => {}
            Err(e) => {
                errors.0.push(e);
                return;
            }
        }
    }
    let mut uniform = GpuEnvironment::default();
    let mut bound = None;
    if let Some(env) = env {
        let (sh, mips) = match &env.image {
            Some(image) => {
                let cached = ibl.cache.contains_key(&(image.id, quality.ibl_samples));
                match ibl.prepare_image(&gpu, image, quality.ibl_samples) {
                    Ok(prepared) => {
                        if !cached {
                            let steps: Vec<(String, f64)> = prepared
                                .steps
                                .iter()
                                .map(|(s, ms)| ((*s).to_string(), *ms))
                                .collect();
                            ibl.last_steps.extend(steps);
                        }
                        bound = Some((image.id, quality.ibl_samples));
                        let p = ibl.cache.get(&(image.id, quality.ibl_samples));
                        (p.map_or([Vec3::ZERO; 9], |p| p.sh), p.map_or(1, |p| p.mips))
                    }
                    Err(e) => {
                        errors.0.push(e);
                        return;
                    }
                }
            }
            None => (sh_uniform(env.uniform), 1),
        };
        let scale = env.intensity * exposure;
        for (k, c) in sh.iter().enumerate() {
            uniform.sh[k] = (*c * scale).min(Vec3::splat(f32::MAX)).extend(0.0).into();
        }
        let radiance = env.uniform * scale;
        uniform.uniform_radiance = radiance.min(Vec3::splat(f32::MAX)).extend(0.0).into();
        uniform.params = [
            scale,
            env.rotation,
            (mips - 1) as f32,
            env.background_blur * (mips - 1) as f32,
        ];
    }
    ibl.bound_cube = bound;
    gpu.queue
        .write_buffer(&ibl.uniform, 0, bytemuck::bytes_of(&uniform));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        crate::assert_wgsl_twin!(Params, "ibl_preprocess.wgsl", &[], "Params", [
            size, mip, mips, samples, source_size, pad => "pad0",
        ]);
    }
}

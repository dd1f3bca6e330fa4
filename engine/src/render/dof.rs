//! Depth of field (`shaders/dof.wgsl`): the thin-lens circle of confusion, a ring gather
//! at half resolution with separate far and near fields, composited at full resolution.
//! Runs only when the camera has [`crate::scene::DepthOfField`].

use crate::error::Result;
use crate::render::device::Gpu;
use crate::render::extract::{ExtractedCamera, ExtractedFrame};
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::create_module;
use crate::render::pipelines::{draw_fullscreen, fullscreen_pipeline};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::targets::{RenderTargets, Target};
use crate::scene::DepthOfField;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use std::collections::HashMap;
use wgpu::util::DeviceExt;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Depth of field.
    pub const Dof: PassId = PassId::new("dof");
}

/// The depth-of-field passes compile one set of pipelines (the composite per HDR format,
/// which the targets decide).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DofVariant;

impl FramePass for DofPass {
    const ID: PassId = PassId::Dof;
    const READS: &'static [Slot] = &[HDR, DEPTH];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = DofVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        DofPass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<DofVariant> {
        let camera = world.resource::<ExtractedFrame>().camera.as_ref();
        let reason = match camera.and_then(|c| c.depth_of_field.map(|d| (c, d))) {
            Some((c, d)) => format!(
                "f/{:.1}, focus {:.2} m, {:.0} mm, {} rings, CoC ≤ {:.0} px",
                c.lens.aperture_f_stops,
                c.lens.focus_distance_m,
                c.focal_length_m * 1e3,
                d.rings,
                d.max_coc_px
            ),
            None => "depth of field is off".into(),
        };
        PassDecision::new(
            camera.is_some_and(|c| c.depth_of_field.is_some()),
            reason,
            DofVariant,
        )
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_dof.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        dof_pass.into_configs()
    }
}

/// Format of the half-resolution depth-of-field targets.
pub const DOF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the near-field tile target (largest near CoC radius, half-res pixels).
const TILE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// Half-resolution pixels per side of a near-field tile (`TILE` in `dof.wgsl`).
const TILE: u32 = 8;

/// The thin lens as the CoC shaders read it (the first five fields of `DofParams` in
/// `dof.wgsl` and of `DebugParams` in `debug_view.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LensUniform {
    /// Focus distance (m); infinity as the largest float (the shaders test `> 3e38`).
    pub focus_m: f32,
    /// Focal length (m).
    pub focal_length_m: f32,
    /// Aperture diameter f/N (m).
    pub aperture_diameter_m: f32,
    /// Full-resolution pixels per metre on the sensor, for a target `height` pixels high.
    pub pixels_per_m: f32,
    /// Largest CoC radius (full-resolution pixels).
    pub max_radius_px: f32,
}

impl LensUniform {
    /// The lens of `camera` with `dof`'s largest CoC, for a target `height` pixels high.
    pub fn new(camera: &ExtractedCamera, dof: DepthOfField, height: u32) -> LensUniform {
        let lens = camera.lens;
        LensUniform {
            focus_m: lens.focus_distance_m.min(f32::MAX),
            focal_length_m: camera.focal_length_m,
            aperture_diameter_m: camera.focal_length_m / lens.aperture_f_stops,
            pixels_per_m: height as f32 / (lens.sensor_height_mm * 1e-3),
            max_radius_px: dof.max_coc_px * 0.5,
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    lens: LensUniform,
    rings: u32,
    pad: [f32; 2],
}

struct DofTargets {
    size: (u32, u32),
    format: wgpu::TextureFormat,
    sharp: Target,
    input: Target,
    tiles: Target,
    far: Target,
    near: Target,
}

/// The depth-of-field passes.
#[derive(Resource)]
pub struct DofPass {
    prepare: wgpu::RenderPipeline,
    tiles: wgpu::RenderPipeline,
    blur: wgpu::RenderPipeline,
    composite: HashMap<wgpu::TextureFormat, wgpu::RenderPipeline>,
    module: wgpu::ShaderModule,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    targets: Option<DofTargets>,
    bind_groups: Option<(u64, [wgpu::BindGroup; 4])>,
}

impl DofPass {
    /// Compiles the three pipelines.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let source = gpu.shaders.compose("dof.wgsl", &[])?;
        let module = create_module(gpu, "dof", &source)?;
        let pipeline = |entry, formats: &[wgpu::TextureFormat]| {
            fullscreen_pipeline(
                gpu,
                entry,
                None,
                &module,
                ("vs_fullscreen", entry),
                formats,
                None,
            )
        };
        Ok(DofPass {
            prepare: pipeline("fs_dof_prepare", &[DOF_FORMAT])?,
            tiles: pipeline("fs_dof_tiles", &[TILE_FORMAT])?,
            blur: pipeline("fs_dof_blur", &[DOF_FORMAT, DOF_FORMAT])?,
            composite: HashMap::new(),
            params: gpu
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("dof params"),
                    contents: &[0; std::mem::size_of::<Params>()],
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                }),
            sampler: gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("dof linear"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            targets: None,
            bind_groups: None,
            module,
        })
    }

    /// The composite pipeline writing an HDR target of `format`, compiled on first use.
    fn composite_pipeline(&mut self, gpu: &Gpu, format: wgpu::TextureFormat) -> Result<()> {
        if !self.composite.contains_key(&format) {
            let pipeline = fullscreen_pipeline(
                gpu,
                "fs_dof_composite",
                None,
                &self.module,
                ("vs_fullscreen", "fs_dof_composite"),
                &[format],
                None,
            )?;
            self.composite.insert(format, pipeline);
        }
        Ok(())
    }
}

/// Sizes the targets, writes the lens parameters and builds the bind groups.
pub fn prepare_dof(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    buffers: Res<SceneBuffers>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<DofPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let (Some(camera), Some(t)) = (frame.camera.as_ref(), targets.current.as_ref()) else {
        return;
    };
    let (Some(dof), Some(depth)) = (camera.depth_of_field, t.get(DEPTH)) else {
        return;
    };
    if let Err(e) = pass.composite_pipeline(&gpu, t.hdr_format) {
        errors.0.push(e);
        return;
    }
    if pass
        .targets
        .as_ref()
        .is_none_or(|d| d.size != t.size || d.format != t.hdr_format)
    {
        let half = (t.size.0.div_ceil(2), t.size.1.div_ceil(2));
        pass.targets = Some(DofTargets {
            size: t.size,
            format: t.hdr_format,
            sharp: Target::new(&gpu, "dof sharp", t.size, t.hdr_format),
            input: Target::new(&gpu, "dof input", half, DOF_FORMAT),
            tiles: Target::new(
                &gpu,
                "dof near tiles",
                (half.0.div_ceil(TILE), half.1.div_ceil(TILE)),
                TILE_FORMAT,
            ),
            far: Target::new(&gpu, "dof far", half, DOF_FORMAT),
            near: Target::new(&gpu, "dof near", half, DOF_FORMAT),
        });
        pass.bind_groups = None;
    }
    let params = Params {
        lens: LensUniform::new(camera, dof, t.size.1),
        rings: dof.rings,
        pad: [0.0; 2],
    };
    if !(params.lens.pixels_per_m.is_finite() && params.lens.aperture_diameter_m.is_finite()) {
        errors.0.push(crate::Error::Scene(
            "depth of field: the lens gives no finite aperture".into(),
        ));
        return;
    }
    gpu.queue
        .write_buffer(&pass.params, 0, bytemuck::bytes_of(&params));
    let key = t.generation + (buffers.generation << 32);
    if pass.bind_groups.as_ref().is_some_and(|(k, _)| *k == key) {
        return;
    }
    let Some(d) = pass.targets.as_ref() else {
        return;
    };
    fn view(b: u32, target: &Target) -> wgpu::BindGroupEntry<'_> {
        wgpu::BindGroupEntry {
            binding: b,
            resource: wgpu::BindingResource::TextureView(&target.view),
        }
    }
    let common = |b: u32| match b {
        0 => wgpu::BindGroupEntry {
            binding: 0,
            resource: buffers.view.as_entire_binding(),
        },
        _ => wgpu::BindGroupEntry {
            binding: 1,
            resource: pass.params.as_entire_binding(),
        },
    };
    let group = |pipeline: &wgpu::RenderPipeline, entries: &[wgpu::BindGroupEntry]| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("dof"),
            layout: &pipeline.get_bind_group_layout(0),
            entries,
        })
    };
    let prepare = group(
        &pass.prepare,
        &[common(0), common(1), view(2, &d.sharp), view(3, depth)],
    );
    let tiles = group(&pass.tiles, &[common(1), view(4, &d.input)]);
    let blur = group(
        &pass.blur,
        &[common(1), view(4, &d.input), view(8, &d.tiles)],
    );
    let Some(composite_pipeline) = pass.composite.get(&t.hdr_format) else {
        return;
    };
    let composite = group(
        composite_pipeline,
        &[
            common(0),
            common(1),
            view(2, &d.sharp),
            view(3, depth),
            view(5, &d.far),
            view(6, &d.near),
            wgpu::BindGroupEntry {
                binding: 7,
                resource: wgpu::BindingResource::Sampler(&pass.sampler),
            },
        ],
    );
    pass.bind_groups = Some((key, [prepare, tiles, blur, composite]));
}

/// Records the depth-of-field passes: copy, prepare, near tiles, blur, composite into the
/// HDR target.
pub fn dof_pass(
    pass: Res<DofPass>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(t), Some(d), Some((_, [prepare, tiles, blur, composite]))) = (
        encoder.as_mut(),
        targets.current.as_ref(),
        pass.targets.as_ref(),
        pass.bind_groups.as_ref(),
    ) else {
        return;
    };
    let (Some(composite_pipeline), Some(hdr)) = (pass.composite.get(&t.hdr_format), t.get(HDR))
    else {
        return;
    };
    encoder.copy_texture_to_texture(
        hdr.texture.as_image_copy(),
        d.sharp.texture.as_image_copy(),
        hdr.texture.size(),
    );
    draw_fullscreen(
        encoder,
        timer,
        "dof prepare",
        &[&d.input.view],
        &pass.prepare,
        prepare,
    );
    draw_fullscreen(
        encoder,
        timer,
        "dof tiles",
        &[&d.tiles.view],
        &pass.tiles,
        tiles,
    );
    draw_fullscreen(
        encoder,
        timer,
        "dof blur",
        &[&d.far.view, &d.near.view],
        &pass.blur,
        blur,
    );
    draw_fullscreen(
        encoder,
        timer,
        "dof composite",
        &[&hdr.view],
        composite_pipeline,
        composite,
    );
}

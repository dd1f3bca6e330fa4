//! The irradiance volume on the GPU: the probe records, the reduction of each captured cube
//! face into its probe (`shaders/probe_capture.wgsl`), and the bake of the records into
//! the two atlases the lighting pass samples (`shaders/probe_bake.wgsl`) through
//! [`PROBES`] (`shaders/volume_lookup.wgsl`). The formulas are in
//! [`crate::shading::irradiance_volume`].
//!
//! Probes are captured by rendering the frame's own capture passes from each probe
//! ([`crate::render::indirect::capture`]). A capture pass accumulates into the records while the
//! lighting (of the frame, and of the captures themselves) samples the atlases baked at the
//! end of the previous pass, so the light of pass k includes the probe light of pass k − 1:
//! one more bounce per pass. The atlases (DDGI's layout) make the lookup two bilinear
//! samples per probe: sixteen per pixel.

use crate::error::Result;
use crate::quality::GiSettings;
use crate::quality::knob::Value;
use crate::quality::knobs::GI;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::frame::{CaptureTarget, CaptureView, FrameEncoder, FrameErrors};
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::targets::RenderTargets;
use crate::scene::{
    Camera, DirectionalLight, Environment, GlobalTransform, IrradianceVolume, Material,
    MaterialMaps, Mesh3d, Meshes, PointLight, ReflectionProbe, ShadowSettings, SpotLight,
};
use crate::shading::irradiance_volume::{
    IRRADIANCE_SIDE, OCT_SIDE, probe_counts, probe_origin, probe_spacing,
};
use bevy_ecs::prelude::*;
use glam::{UVec3, Vec3};

/// vec4s per probe record: the irradiance texels, then the moment texels.
pub const RECORD_STRIDE: u32 = IRRADIANCE_SIDE * IRRADIANCE_SIDE + OCT_SIDE * OCT_SIDE;

/// Format of both atlases.
pub const ATLAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Group 3 of the lighting and reflection passes: the irradiance volume's grid and the
/// atlases it samples (bindings 0–3, `volume_lookup.wgsl`), then the reflection probes
/// (4–7, `probe_reflections.wgsl`, [`crate::render::indirect::reflection_probes`]).
pub const PROBES: BindGroupSpec = BindGroupSpec::fragment("probes", declared::LIGHTING_3);

/// The resources of [`PROBES`], in order.
pub fn probe_bindings<'a>(
    volume: &'a IrradianceVolumeGpu,
    reflections: &'a crate::render::indirect::reflection_probes::ReflectionProbesGpu,
) -> Vec<wgpu::BindingResource<'a>> {
    use wgpu::BindingResource::{Sampler, TextureView};
    vec![
        volume.uniform.as_entire_binding(),
        TextureView(volume.irradiance_atlas()),
        TextureView(volume.moment_atlas()),
        Sampler(&volume.sampler),
        reflections.uniform.as_entire_binding(),
        TextureView(reflections.cube(0)),
        TextureView(reflections.cube(1)),
        Sampler(&reflections.sampler),
    ]
}

/// The bindings of the bake of the records into the atlases.
pub const BAKE: BindGroupSpec = BindGroupSpec::compute("probe bake", declared::PROBE_BAKE_0);
// `probe_bake.wgsl` declares the atlases it writes `rgba16float`, and BAKE comes from it.
const _: () = assert!(matches!(ATLAS_FORMAT, wgpu::TextureFormat::Rgba16Float));

/// The bindings of the reduction of one captured face.
pub const CAPTURE: BindGroupSpec =
    BindGroupSpec::compute("probe capture", declared::PROBE_CAPTURE_0);

/// `VolumeUniform` of `volume_lookup.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuVolume {
    /// Corner probe (m), and 1 once a capture pass has completed.
    pub origin_ready: [f32; 4],
    /// Spacing per axis (m), and the exposure the irradiance atlas was baked with.
    pub spacing_exposure: [f32; 4],
    /// Probes per axis, and probe tiles per atlas row.
    pub counts_tiles: [u32; 4],
    /// 1 / size in texels of the irradiance atlas (xy) and the moment atlas (zw).
    pub texel_sizes: [f32; 4],
}

/// `BakeParams` of `probe_bake.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct BakeParams {
    probes_tiles_stride: [u32; 4],
    exposure_range: [f32; 4],
}

/// Probe tiles per atlas row for `probes` probes (a square-ish atlas), and rows.
pub fn atlas_tiles(probes: u32) -> (u32, u32) {
    let per_row = (probes.max(1) as f32).sqrt().ceil() as u32;
    (per_row, probes.max(1).div_ceil(per_row))
}

/// The two atlases of a grid of `probes` probes: irradiance (tiles of
/// ([`IRRADIANCE_SIDE`] + 2)²) and moments (tiles of ([`OCT_SIDE`] + 2)²).
struct Atlases {
    irradiance: wgpu::TextureView,
    moments: wgpu::TextureView,
    irradiance_size: (u32, u32),
    moments_size: (u32, u32),
}

impl Atlases {
    fn new(gpu: &Gpu, probes: u32) -> Atlases {
        let (per_row, rows) = atlas_tiles(probes);
        let make = |label, tile: u32| {
            let size = (per_row * tile, rows * tile);
            let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: ATLAS_FORMAT,
                usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            (texture.create_view(&Default::default()), size)
        };
        let (irradiance, irradiance_size) = make("probe irradiance atlas", IRRADIANCE_SIDE + 2);
        let (moments, moments_size) = make("probe moment atlas", OCT_SIDE + 2);
        Atlases {
            irradiance,
            moments,
            irradiance_size,
            moments_size,
        }
    }
}

/// `CaptureParams` of `probe_capture.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct CaptureParams {
    probe_face_stride: [u32; 4],
    range: [f32; 4],
}

/// A grid of probes and how it is captured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// The probe with the smallest coordinates (m).
    pub origin: Vec3,
    /// Distance between neighbours along each axis (m).
    pub spacing: Vec3,
    /// Probes along each axis.
    pub counts: UVec3,
    /// Side of each captured cube face (pixels).
    pub face_size: u32,
    /// Capture passes to converge.
    pub bounces: u32,
}

impl Grid {
    /// The grid over the box `min`..`max` (sorted per axis), at `spacing_m` or, without
    /// one, `gi.density` probes along the longest side.
    pub fn new(min: Vec3, max: Vec3, spacing_m: Option<f32>, gi: &GiSettings) -> Grid {
        let (lo, hi) = (min.min(max), min.max(max));
        let extent = hi - lo;
        let density = gi
            .density
            .clamp(1, crate::shading::irradiance_volume::MAX_PROBES_PER_AXIS);
        let spacing_m = spacing_m
            .filter(|s| s.is_finite() && *s > 0.0)
            .unwrap_or(extent.max_element() / density as f32);
        let counts = probe_counts(extent, spacing_m);
        let spacing = probe_spacing(extent, counts);
        Grid {
            origin: probe_origin(lo, hi, counts, spacing),
            spacing,
            counts,
            face_size: gi.face_size.clamp(4, 64),
            bounces: gi.bounces.clamp(1, 4),
        }
    }

    /// Number of probes.
    pub fn len(&self) -> u32 {
        self.counts.x * self.counts.y * self.counts.z
    }

    /// Whether the grid has no probe (never: every axis has at least one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Position of probe `i` (x fastest, then y, then z), in metres.
    pub fn position(&self, i: u32) -> Vec3 {
        let c = self.counts;
        let index = UVec3::new(i % c.x, (i / c.x) % c.y, i / (c.x * c.y));
        self.origin + index.as_vec3() * self.spacing
    }

    /// The largest distance a probe's moments store: twice a cell's diagonal (m).
    pub fn range_m(&self) -> f32 {
        2.0 * self.spacing.length()
    }
}

/// The grid this frame's scene asks for, or why it has none.
pub fn grid_for(world: &mut World, gi: &GiSettings) -> std::result::Result<Grid, String> {
    if !gi.enabled {
        return Err(format!(
            "global illumination off ({})",
            GI.setting(Value::Bool(false))
        ));
    }
    let explicit = world
        .query::<&IrradianceVolume>()
        .iter(world)
        .next()
        .copied();
    if let Some(v) = explicit {
        if !(v.min.is_finite() && v.max.is_finite()) {
            return Err("the IrradianceVolume's bounds are not finite".into());
        }
        return Ok(Grid::new(v.min, v.max, v.spacing_m, gi));
    }
    if !gi.auto_place {
        return Err("no IrradianceVolume, and automatic placement is off".into());
    }
    let bounds = crate::scene::mesh::scene_bounds(world);
    match bounds {
        Some(b) => Ok(Grid::new(b.min, b.max, None, gi)),
        None => Err("no mesh to place probes around".into()),
    }
}

/// The filter of entities whose change a probe capture sees.
type SceneChange = (
    Without<Camera>,
    Or<(
        Changed<GlobalTransform>,
        Changed<Mesh3d>,
        Changed<Material>,
        Changed<MaterialMaps>,
        Changed<DirectionalLight>,
        Changed<PointLight>,
        Changed<SpotLight>,
        Changed<ShadowSettings>,
        Changed<Environment>,
        Changed<IrradianceVolume>,
        Changed<ReflectionProbe>,
    )>,
);

/// Whether anything a capture sees changed since the last call: meshes, materials,
/// transforms (the camera's excepted), lights, the environment, the volume or the quality.
pub fn scene_changed(
    changed: Query<(), SceneChange>,
    mut removed: RemovedComponents<Mesh3d>,
    quality: Res<crate::quality::Quality>,
    meshes: Res<Meshes>,
) -> bool {
    let removed = removed.read().count() > 0;
    !changed.is_empty() || removed || quality.is_changed() || meshes.is_changed()
}

/// The volume's GPU state: records, atlases, uniform, the reduction and bake pipelines,
/// and where the capture stands.
#[derive(Resource)]
pub struct IrradianceVolumeGpu {
    reduce: wgpu::ComputePipeline,
    capture_layout: wgpu::BindGroupLayout,
    bake: wgpu::ComputePipeline,
    bake_layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    bake_params: wgpu::Buffer,
    /// The grid uniform ([`GpuVolume`]).
    pub uniform: wgpu::Buffer,
    records: wgpu::Buffer,
    atlases: Atlases,
    /// A linear, clamped sampler for the atlases.
    pub sampler: wgpu::Sampler,
    capacity: u32,
    /// The grid in use, if any.
    pub grid: Option<Grid>,
    /// Why there is no grid, when there is none.
    pub skip_reason: String,
    /// Capture passes completed since the grid was placed or the scene changed.
    pub completed_passes: u32,
    /// The next probe to capture in the current pass.
    pub next_probe: u32,
    /// Whether the atlases hold a completed pass (of this scene or, after a change, of the
    /// previous one: the frame keeps showing it while the volume converges again).
    pub ready: bool,
    /// Whether the uniform is set for captures, which read the atlases only once a pass of
    /// the current round has completed, so that a converged volume does not depend on what
    /// the scene was before it changed.
    capturing: bool,
    /// The exposure the irradiance atlas was baked with.
    baked_exposure: f32,
    /// The targets captures render into (swapped with the frame's while one runs).
    pub capture_targets: RenderTargets,
    capture_group: CachedGroup,
    /// Cube faces captured since the renderer was installed.
    pub faces_captured: u64,
}

fn record_buffer(gpu: &Gpu, probes: u32) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("irradiance probes"),
        size: u64::from(probes.max(1)) * u64::from(RECORD_STRIDE) * 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

fn compute(
    gpu: &Gpu,
    label: &str,
    file: &str,
    entry: &str,
    layout: &wgpu::BindGroupLayout,
) -> Result<wgpu::ComputePipeline> {
    let source = gpu.shaders.compose(file, &[])?;
    let module = create_module(gpu, label, &source)?;
    let layout = pipeline_layout(gpu, label, &[layout]);
    compute_pipeline(gpu, label, Some(&layout), &module, entry)
}

impl IrradianceVolumeGpu {
    /// Compiles the reduction and the bake, and creates one-probe records and atlases.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let capture_layout = CAPTURE.layout(gpu);
        let bake_layout = BAKE.layout(gpu);
        let uniform = |label, size| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let volume = IrradianceVolumeGpu {
            reduce: compute(
                gpu,
                "probe capture",
                "probe_capture.wgsl",
                "cs_reduce",
                &capture_layout,
            )?,
            capture_layout,
            bake: compute(
                gpu,
                "probe bake",
                "probe_bake.wgsl",
                "cs_bake",
                &bake_layout,
            )?,
            bake_layout,
            params: uniform(
                "probe capture params",
                std::mem::size_of::<CaptureParams>() as u64,
            ),
            bake_params: uniform(
                "probe bake params",
                std::mem::size_of::<BakeParams>() as u64,
            ),
            uniform: uniform("irradiance volume", std::mem::size_of::<GpuVolume>() as u64),
            records: record_buffer(gpu, 1),
            atlases: Atlases::new(gpu, 1),
            sampler: gpu.sampler("probe atlases", wgpu::FilterMode::Linear),
            capacity: 1,
            grid: None,
            skip_reason: "not placed yet".into(),
            completed_passes: 0,
            next_probe: 0,
            ready: false,
            capturing: false,
            baked_exposure: 1.0,
            capture_targets: RenderTargets::default(),
            capture_group: CachedGroup::default(),
            faces_captured: 0,
        };
        volume.write_uniform(gpu);
        Ok(volume)
    }

    /// The irradiance atlas the lighting samples.
    pub fn irradiance_atlas(&self) -> &wgpu::TextureView {
        &self.atlases.irradiance
    }

    /// The moment atlas the lighting samples.
    pub fn moment_atlas(&self) -> &wgpu::TextureView {
        &self.atlases.moments
    }

    /// Uses `grid` (or none) from now on: records and atlases are reallocated when the
    /// probe count changes, and capture starts over with nothing ready.
    pub fn set_grid(&mut self, gpu: &Gpu, grid: Option<Grid>) {
        let probes = grid.map_or(1, |g| g.len());
        if probes > self.capacity || grid.map(|g| g.len()) != self.grid.map(|g| g.len()) {
            self.capacity = self.capacity.max(probes);
            self.records = record_buffer(gpu, self.capacity);
            self.atlases = Atlases::new(gpu, probes);
        }
        self.grid = grid;
        self.ready = false;
        self.restart(gpu);
    }

    /// Starts capturing from the first pass again (the scene changed). The frame keeps
    /// reading the atlases until the first new pass completes; the uniform is written
    /// again at once, so that the new round's first captures, already set up for
    /// capturing, read no probe light (they would otherwise add the old round's bounces
    /// to the new one's).
    pub fn restart(&mut self, gpu: &Gpu) {
        self.completed_passes = 0;
        self.next_probe = 0;
        self.write_uniform(gpu);
    }

    /// Whether every pass is done.
    pub fn converged(&self) -> bool {
        self.grid.is_none_or(|g| self.completed_passes >= g.bounces)
    }

    /// Called after probe `next_probe` was captured: moves on, and at the end of a pass
    /// bakes the records into the atlases (irradiance pre-exposed by `exposure`) and
    /// submits the bake.
    pub fn probe_done(&mut self, gpu: &Gpu, exposure: f32) -> Result<()> {
        let Some(grid) = self.grid else {
            return Ok(());
        };
        self.next_probe += 1;
        if self.next_probe < grid.len() {
            return Ok(());
        }
        self.next_probe = 0;
        self.completed_passes += 1;
        self.ready = true;
        self.baked_exposure = if exposure.is_finite() && exposure > 0.0 {
            exposure
        } else {
            1.0
        };
        let (per_row, _) = atlas_tiles(grid.len());
        let params = BakeParams {
            probes_tiles_stride: [grid.len(), per_row, RECORD_STRIDE, 0],
            exposure_range: [self.baked_exposure, grid.range_m(), 0.0, 0.0],
        };
        gpu.queue
            .write_buffer(&self.bake_params, 0, bytemuck::bytes_of(&params));
        let group = BAKE.group(
            gpu,
            &self.bake_layout,
            vec![
                self.bake_params.as_entire_binding(),
                self.records.as_entire_binding(),
                wgpu::BindingResource::TextureView(&self.atlases.irradiance),
                wgpu::BindingResource::TextureView(&self.atlases.moments),
            ],
        )?;
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("probe bake"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("probe bake"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.bake);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(grid.len(), 1, 1);
        }
        self.write_uniform(gpu);
        gpu.checked("probe bake", |_| gpu.queue.submit([encoder.finish()]))?;
        Ok(())
    }

    /// Sets the uniform for captures (`true`, before them) or for the frame (`false`,
    /// after them).
    pub fn set_capturing(&mut self, gpu: &Gpu, capturing: bool) {
        self.capturing = capturing;
        self.write_uniform(gpu);
    }

    fn write_uniform(&self, gpu: &Gpu) {
        let g = self.grid.unwrap_or(Grid {
            origin: Vec3::ZERO,
            spacing: Vec3::ONE,
            counts: UVec3::ONE,
            face_size: 4,
            bounces: 1,
        });
        let (per_row, _) = atlas_tiles(g.len());
        let inverse = |(w, h): (u32, u32)| [1.0 / w.max(1) as f32, 1.0 / h.max(1) as f32];
        let [iw, ih] = inverse(self.atlases.irradiance_size);
        let [mw, mh] = inverse(self.atlases.moments_size);
        let data = GpuVolume {
            origin_ready: {
                let ready = if self.capturing {
                    self.completed_passes > 0
                } else {
                    self.ready
                };
                g.origin.extend(if ready { 1.0 } else { 0.0 }).into()
            },
            spacing_exposure: g.spacing.extend(self.baked_exposure).into(),
            counts_tiles: g.counts.extend(per_row).into(),
            texel_sizes: [iw, ih, mw, mh],
        };
        gpu.queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&data));
    }
}

/// Records the reduction of the face just captured into its probe (the last system of
/// [`crate::render::CaptureSchedule`]).
pub fn record_capture_reduce(
    gpu: Res<Gpu>,
    buffers: Res<SceneBuffers>,
    targets: Res<RenderTargets>,
    capture: Option<Res<CaptureView>>,
    mut volume: ResMut<IrradianceVolumeGpu>,
    mut encoder: ResMut<FrameEncoder>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(CaptureView {
        target: CaptureTarget::IrradianceProbe(probe),
        face,
        ..
    }) = capture.as_deref().copied()
    else {
        return;
    };
    let (Some(grid), Some(t)) = (volume.grid, targets.current.as_ref()) else {
        return;
    };
    let Some([hdr, depth]) = t.views([HDR, DEPTH]) else {
        return;
    };
    let volume = &mut *volume;
    let resources = vec![
        buffers.view.as_entire_binding(),
        wgpu::BindingResource::TextureView(hdr),
        wgpu::BindingResource::TextureView(depth),
        volume.params.as_entire_binding(),
        volume.records.as_entire_binding(),
    ];
    if let Err(e) = volume
        .capture_group
        .get(&gpu, &CAPTURE, &volume.capture_layout, resources)
    {
        errors.0.push(e);
        return;
    }
    let params = CaptureParams {
        probe_face_stride: [probe, face, RECORD_STRIDE, 0],
        range: [grid.range_m(), 0.0, 0.0, 0.0],
    };
    gpu.queue
        .write_buffer(&volume.params, 0, bytemuck::bytes_of(&params));
    let (Some(encoder), Some(group)) = (encoder.encoder.as_mut(), volume.capture_group.group())
    else {
        return;
    };
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("probe capture reduce"),
        timestamp_writes: None,
    });
    pass.set_pipeline(&volume.reduce);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(1, 1, 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_uniforms_lay_out_as_the_shaders_do() {
        crate::assert_wgsl_twin!(
            GpuVolume,
            "volume_lookup.wgsl",
            &[],
            "VolumeUniform",
            [origin_ready, spacing_exposure, counts_tiles, texel_sizes]
        );
        crate::assert_wgsl_twin!(
            BakeParams,
            "probe_bake.wgsl",
            &[],
            "BakeParams",
            [probes_tiles_stride, exposure_range]
        );
        crate::assert_wgsl_twin!(
            CaptureParams,
            "probe_capture.wgsl",
            &[],
            "CaptureParams",
            [probe_face_stride, range]
        );
    }
}

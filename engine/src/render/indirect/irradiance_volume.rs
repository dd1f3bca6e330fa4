//! The irradiance volume on the GPU: the probe records, the grid's uniform, and the
//! reduction of each captured cube face into its probe (`shaders/probe_capture.wgsl`).
//! The lighting pass reads the records through [`PROBES`] (`shaders/volume_lookup.wgsl`);
//! the formulas are in [`crate::irradiance_volume`].
//!
//! Probes are captured by rendering the frame's own capture passes from each probe
//! ([`crate::render::capture`]). Two record buffers alternate: a capture pass writes one
//! while the lighting (of the frame, and of the captures themselves) reads the other, so
//! the light of pass k includes the probe light of pass k − 1: one more bounce per pass.

use crate::error::Result;
use crate::irradiance_volume::{
    OCT_SIDE, probe_counts, probe_origin, probe_spacing,
};
use crate::quality::GiSettings;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::pipelines::create_module;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::targets::RenderTargets;
use crate::scene::{
    Camera, DirectionalLight, Environment, GlobalTransform, IrradianceVolume, Material,
    MaterialMaps, Mesh3d, Meshes, PointLight, ShadowSettings, SpotLight,
};
use bevy_ecs::prelude::*;
use glam::{UVec3, Vec3};

/// vec4s per probe record: 9 SH coefficients, then the moment texels.
pub const RECORD_STRIDE: u32 = 9 + OCT_SIDE * OCT_SIDE;

/// The lighting pass's group 3: the grid and the probe records it reads.
pub const PROBES: BindGroupSpec = BindGroupSpec {
    label: "lighting: probes",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("volume", Binding::Uniform),
        ("volume_probes", Binding::Storage),
    ],
};

/// The bindings of the reduction of one captured face.
pub const CAPTURE: BindGroupSpec = BindGroupSpec {
    label: "probe capture",
    visibility: wgpu::ShaderStages::COMPUTE,
    bindings: &[
        ("view", Binding::Uniform),
        ("hdr", Binding::TextureLoad),
        ("depth_buffer", Binding::TextureLoad),
        ("params", Binding::Uniform),
        ("probes", Binding::StorageReadWrite),
    ],
};

/// `VolumeUniform` of `volume_lookup.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuVolume {
    /// Corner probe (m), and 1 once a capture pass has completed.
    pub origin_ready: [f32; 4],
    /// Spacing per axis (m), and the largest distance a moment stores (m).
    pub spacing_range: [f32; 4],
    /// Probes per axis, and [`RECORD_STRIDE`].
    pub counts_stride: [u32; 4],
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
        let density = gi.density.clamp(1, crate::irradiance_volume::MAX_PROBES_PER_AXIS);
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
        return Err("global illumination off (--gi off)".into());
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
    let placed: Vec<_> = world
        .query::<(&Mesh3d, &GlobalTransform)>()
        .iter(world)
        .map(|(mesh, t)| (mesh.0, t.0))
        .collect();
    let meshes = world.resource::<Meshes>();
    let bounds = placed
        .iter()
        .filter_map(|(mesh, m)| meshes.get(*mesh)?.bounds()?.transformed(m))
        .reduce(|a, b| a.union(&b));
    match bounds {
        Some(b) => Ok(Grid::new(b.min, b.max, None, gi)),
        None => Err("no mesh to place probes around".into()),
    }
}

/// Whether anything a capture sees changed since the last call: meshes, materials,
/// transforms (the camera's excepted), lights, the environment, the volume or the quality.
pub fn scene_changed(
    changed: Query<
        (),
        (
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
            )>,
        ),
    >,
    mut removed: RemovedComponents<Mesh3d>,
    quality: Res<crate::quality::Quality>,
    meshes: Res<Meshes>,
) -> bool {
    let removed = removed.read().count() > 0;
    !changed.is_empty() || removed || quality.is_changed() || meshes.is_changed()
}

/// The volume's GPU state: records, uniform, the reduction pipeline, and where the
/// capture stands.
#[derive(Resource)]
pub struct IrradianceVolumeGpu {
    pipeline: wgpu::ComputePipeline,
    capture_layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    /// The grid uniform ([`GpuVolume`]).
    pub uniform: wgpu::Buffer,
    records: [wgpu::Buffer; 2],
    capacity: u32,
    read: usize,
    /// Bumped whenever the records the lighting reads change buffer.
    pub generation: u64,
    /// The grid in use, if any.
    pub grid: Option<Grid>,
    /// Why there is no grid, when there is none.
    pub skip_reason: String,
    /// Capture passes completed since the grid was placed or the scene changed.
    pub completed_passes: u32,
    /// The next probe to capture in the current pass.
    pub next_probe: u32,
    /// Whether the records the lighting reads hold a completed pass.
    pub ready: bool,
    /// The face being captured (probe, face), while a capture runs.
    pub capturing: Option<(u32, u32)>,
    /// The targets captures render into (swapped with the frame's while one runs).
    pub capture_targets: RenderTargets,
    capture_group: Option<([u64; 3], wgpu::BindGroup)>,
    /// Cube faces captured since the renderer was installed.
    pub faces_captured: u64,
}

fn record_buffer(gpu: &Gpu, probes: u32) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("irradiance probes"),
        size: u64::from(probes.max(1)) * u64::from(RECORD_STRIDE) * 16,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl IrradianceVolumeGpu {
    /// Compiles the reduction and creates one-probe records.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let source = gpu.shaders.compose("probe_capture.wgsl", &[])?;
        let module = create_module(gpu, "probe capture", &source)?;
        let capture_layout = CAPTURE.layout(gpu);
        let layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("probe capture"),
                bind_group_layouts: &[Some(&capture_layout)],
                immediate_size: 0,
            });
        let pipeline = gpu.checked("probe capture pipeline", |device| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("probe capture"),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("cs_reduce"),
                compilation_options: Default::default(),
                cache: None,
            })
        })?;
        let uniform = |label, size| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        Ok(IrradianceVolumeGpu {
            pipeline,
            capture_layout,
            params: uniform(
                "probe capture params",
                std::mem::size_of::<CaptureParams>() as u64,
            ),
            uniform: uniform("irradiance volume", std::mem::size_of::<GpuVolume>() as u64),
            records: [record_buffer(gpu, 1), record_buffer(gpu, 1)],
            capacity: 1,
            read: 0,
            generation: 1,
            grid: None,
            skip_reason: "not placed yet".into(),
            completed_passes: 0,
            next_probe: 0,
            ready: false,
            capturing: None,
            capture_targets: RenderTargets::default(),
            capture_group: None,
            faces_captured: 0,
        })
    }

    /// The records the lighting reads.
    pub fn read_records(&self) -> &wgpu::Buffer {
        &self.records[self.read]
    }

    /// Uses `grid` (or none) from now on: the records are reallocated when they are too
    /// small, and capture starts over with nothing ready.
    pub fn set_grid(&mut self, gpu: &Gpu, grid: Option<Grid>) {
        if let Some(g) = grid
            && g.len() > self.capacity
        {
            self.capacity = g.len();
            self.records = [
                record_buffer(gpu, self.capacity),
                record_buffer(gpu, self.capacity),
            ];
        }
        self.grid = grid;
        self.ready = false;
        self.generation += 1;
        self.restart();
        self.write_uniform(gpu);
    }

    /// Starts capturing from the first pass again (the scene changed). The records read
    /// now stay in use until the first new pass completes.
    pub fn restart(&mut self) {
        self.completed_passes = 0;
        self.next_probe = 0;
    }

    /// Whether every pass is done.
    pub fn converged(&self) -> bool {
        self.grid.is_none_or(|g| self.completed_passes >= g.bounces)
    }

    /// Called after probe `next_probe` was captured: moves on, and at the end of a pass
    /// makes its records the ones the lighting reads.
    pub fn probe_done(&mut self, gpu: &Gpu) {
        let Some(grid) = self.grid else { return };
        self.next_probe += 1;
        if self.next_probe >= grid.len() {
            self.next_probe = 0;
            self.completed_passes += 1;
            self.read = 1 - self.read;
            self.ready = true;
            self.generation += 1;
            self.write_uniform(gpu);
        }
    }

    fn write_uniform(&self, gpu: &Gpu) {
        let g = self.grid.unwrap_or(Grid {
            origin: Vec3::ZERO,
            spacing: Vec3::ONE,
            counts: UVec3::ONE,
            face_size: 4,
            bounces: 1,
        });
        let data = GpuVolume {
            origin_ready: g.origin.extend(if self.ready { 1.0 } else { 0.0 }).into(),
            spacing_range: g.spacing.extend(g.range_m()).into(),
            counts_stride: g.counts.extend(RECORD_STRIDE).into(),
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
    mut volume: ResMut<IrradianceVolumeGpu>,
    mut encoder: ResMut<FrameEncoder>,
    mut errors: ResMut<FrameErrors>,
) {
    let (Some((probe, face)), Some(grid), Some(t)) =
        (volume.capturing, volume.grid, targets.current.as_ref())
    else {
        return;
    };
    let Some([hdr, depth]) = t.views([HDR, DEPTH]) else {
        return;
    };
    let write = 1 - volume.read;
    let key = [t.generation, buffers.generation, volume.generation];
    if volume.capture_group.as_ref().is_none_or(|(k, _)| *k != key) {
        let group = CAPTURE.group(
            &gpu,
            &volume.capture_layout,
            vec![
                buffers.view.as_entire_binding(),
                wgpu::BindingResource::TextureView(hdr),
                wgpu::BindingResource::TextureView(depth),
                volume.params.as_entire_binding(),
                volume.records[write].as_entire_binding(),
            ],
        );
        match group {
            Ok(g) => volume.capture_group = Some((key, g)),
            Err(e) => {
                errors.0.push(e);
                return;
            }
        }
    }
    let params = CaptureParams {
        probe_face_stride: [probe, face, RECORD_STRIDE, 0],
        range: [grid.range_m(), 0.0, 0.0, 0.0],
    };
    gpu.queue
        .write_buffer(&volume.params, 0, bytemuck::bytes_of(&params));
    let (Some(encoder), Some((_, group))) = (encoder.encoder.as_mut(), &volume.capture_group)
    else {
        return;
    };
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("probe capture reduce"),
        timestamp_writes: None,
    });
    pass.set_pipeline(&volume.pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(1, 1, 1);
}

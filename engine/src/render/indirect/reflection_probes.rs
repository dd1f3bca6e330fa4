//! Reflection probes on the GPU: where they are placed, the copy of each captured face into
//! a face strip (`shaders/reflection_capture.wgsl`), the prefiltered cube maps (the
//! environment's own prefilter, [`crate::render::indirect::environment_maps::Ibl::prefilter_strip`]), and the
//! uniform the lighting and reflection passes read (`shaders/probe_reflections.wgsl`).
//! The formulas are in [`crate::shading::reflection_probe`].

use crate::error::Result;
use crate::quality::ReflectionProbeSettings;
use crate::quality::knob::Value;
use crate::quality::knobs::REFLECTION_PROBES;
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::frame::{CaptureTarget, CaptureView, FrameEncoder, FrameErrors};
use crate::render::graph::slots::HDR;
use crate::render::indirect::environment_maps::{PrefilteredCube, cube_texture, cube_view};
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use crate::render::targets::RenderTargets;
use crate::scene::{Camera, GlobalTransform, ReflectionProbe};
use bevy_ecs::prelude::*;
use glam::Vec3;

/// Probes the passes bind at once.
pub const MAX_REFLECTION_PROBES: usize = 2;

// `reflection_capture.wgsl` declares the strip it writes `rgba16float`, and FACE_COPY
// comes from it.
const _: () = assert!(matches!(
    crate::render::indirect::environment_maps::CUBE_FORMAT,
    wgpu::TextureFormat::Rgba16Float
));

/// The bindings of the copy of one captured face into the strip.
pub const FACE_COPY: BindGroupSpec =
    BindGroupSpec::compute("reflection capture", declared::REFLECTION_CAPTURE_0);

/// `ReflectionProbe` of `probe_reflections.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuReflectionProbe {
    /// Position (m), fade band (m).
    pub position_blend: [f32; 4],
    /// Half-size of the box (m), highest prefiltered mip.
    pub half_extents_mips: [f32; 4],
    /// The capture's exposure, then unused.
    pub exposure: [f32; 4],
}

/// `ReflectionProbes` of `probe_reflections.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GpuReflectionProbes {
    /// The probes in use first.
    pub items: [GpuReflectionProbe; MAX_REFLECTION_PROBES],
    /// How many are in use, then unused.
    pub count: [u32; 4],
}

/// A probe where the scene asks for one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedProbe {
    /// Position (m).
    pub position: Vec3,
    /// Half-size of its box (m).
    pub half_extents: Vec3,
    /// Fade band inside the box's faces (m).
    pub blend_m: f32,
}

/// A captured and prefiltered probe.
pub struct CapturedProbe {
    /// Where it was captured.
    pub placed: PlacedProbe,
    /// Its prefiltered cube.
    pub cube: PrefilteredCube,
    /// The exposure its capture was pre-exposed by.
    pub exposure: f32,
}

/// The probes this frame's scene asks for (at most [`MAX_REFLECTION_PROBES`]: those whose
/// boxes hold the camera, then the nearest), or why there are none.
pub fn probes_for(
    world: &mut World,
    settings: &ReflectionProbeSettings,
) -> std::result::Result<Vec<PlacedProbe>, String> {
    if !settings.enabled {
        return Err(format!(
            "reflection probes off ({})",
            REFLECTION_PROBES.setting(Value::Bool(false))
        ));
    }
    let explicit: Vec<PlacedProbe> = world
        .query::<(&ReflectionProbe, &GlobalTransform)>()
        .iter(world)
        .map(|(p, t)| PlacedProbe {
            position: t.translation(),
            half_extents: p.half_extents.abs(),
            blend_m: p.blend_m.max(0.0),
        })
        .filter(|p| p.position.is_finite() && p.half_extents.is_finite() && p.blend_m.is_finite())
        .collect();
    if !explicit.is_empty() {
        let camera = world
            .query_filtered::<&GlobalTransform, With<Camera>>()
            .iter(world)
            .next()
            .map_or(Vec3::ZERO, |t| t.translation());
        let mut ranked = explicit;
        ranked.sort_by(|a, b| {
            let rank = |p: &PlacedProbe| {
                let inside = ((camera - p.position).abs() - p.half_extents).max_element() <= 0.0;
                (!inside, (camera - p.position).length())
            };
            rank(a)
                .partial_cmp(&rank(b))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        ranked.truncate(MAX_REFLECTION_PROBES);
        return Ok(ranked);
    }
    if !settings.auto_place {
        return Err("no ReflectionProbe, and automatic placement is off".into());
    }
    let bounds = crate::scene::mesh::scene_bounds(world);
    match bounds {
        Some(b) => {
            let half = ((b.max - b.min) * 0.5).max(Vec3::splat(1e-3));
            Ok(vec![PlacedProbe {
                position: (b.min + b.max) * 0.5,
                half_extents: half,
                blend_m: 0.1 * half.min_element(),
            }])
        }
        None => Err("no mesh to place a probe among".into()),
    }
}

/// The probes' GPU state.
#[derive(Resource)]
pub struct ReflectionProbesGpu {
    copy: wgpu::ComputePipeline,
    copy_layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    /// The uniform ([`GpuReflectionProbes`]).
    pub uniform: wgpu::Buffer,
    dummy: wgpu::TextureView,
    /// A trilinear, clamped sampler for the cubes.
    pub sampler: wgpu::Sampler,
    /// The probes the scene asks for.
    pub placed: Vec<PlacedProbe>,
    /// Per placed probe, its capture once done.
    pub captured: Vec<Option<CapturedProbe>>,
    /// Per placed probe, whether its capture is older than the scene.
    pub stale: Vec<bool>,
    /// The strip the capture in progress writes.
    pub strip: Option<wgpu::Texture>,
    /// Why there are no probes, when there are none.
    pub skip_reason: String,
    /// Probes captured since the renderer was installed.
    pub captures: u64,
}

impl ReflectionProbesGpu {
    /// Compiles the face copy; no probe yet.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let copy_layout = FACE_COPY.layout(gpu);
        let source = gpu.shaders.compose("reflection_capture.wgsl", &[])?;
        let module = create_module(gpu, "reflection capture", &source)?;
        let layout = pipeline_layout(gpu, "reflection capture", &[&copy_layout]);
        let copy = compute_pipeline(
            gpu,
            "reflection capture",
            Some(&layout),
            &module,
            "cs_copy_face",
        )?;
        let buffer = |label, size| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let probes = ReflectionProbesGpu {
            copy,
            copy_layout,
            params: buffer("reflection capture params", 16),
            uniform: buffer(
                "reflection probes",
                std::mem::size_of::<GpuReflectionProbes>() as u64,
            ),
            dummy: cube_view(&cube_texture(gpu, "no reflection probe", 1, 1)),
            sampler: gpu.mipmapped_sampler("reflection probes"),
            placed: Vec::new(),
            captured: Vec::new(),
            stale: Vec::new(),
            strip: None,
            skip_reason: "not placed yet".into(),
            captures: 0,
        };
        probes.write_uniform(gpu);
        Ok(probes)
    }

    /// The cube bound in slot `i`: the probe's, or a black 1×1 cube.
    pub fn cube(&self, i: usize) -> &wgpu::TextureView {
        match self.captured.get(i) {
            Some(Some(c)) => &c.cube.view,
            _ => &self.dummy,
        }
    }

    /// Uses `placed` from now on: a probe that moved or changed its box loses its capture.
    pub fn place(&mut self, gpu: &Gpu, placed: Vec<PlacedProbe>) {
        if placed == self.placed {
            return;
        }
        self.captured = placed.iter().map(|_| None).collect();
        self.stale = vec![true; placed.len()];
        self.placed = placed;
        self.write_uniform(gpu);
    }

    /// The next probe whose capture is missing or stale.
    pub fn next_stale(&self) -> Option<usize> {
        self.stale.iter().position(|s| *s)
    }

    /// Keeps the capture of probe `slot`.
    pub fn set_captured(&mut self, gpu: &Gpu, slot: usize, probe: CapturedProbe) {
        if let (Some(c), Some(s)) = (self.captured.get_mut(slot), self.stale.get_mut(slot)) {
            *c = Some(probe);
            *s = false;
        }
        self.captures += 1;
        self.write_uniform(gpu);
    }

    /// The slots the shaders look up: the last captured slot + 1 (0 with no capture).
    /// The lighting and reflection passes compile it in (`REFLECTION_PROBE_SLOTS`).
    pub fn slots(&self) -> u32 {
        self.captured
            .iter()
            .rposition(Option::is_some)
            .map_or(0, |slot| slot as u32 + 1)
    }

    /// Writes the uniform: the captured probes, in slot order.
    pub fn write_uniform(&self, gpu: &Gpu) {
        let mut data = GpuReflectionProbes::default();
        for (slot, c) in self.captured.iter().enumerate() {
            if let Some(c) = c {
                data.items[slot] = GpuReflectionProbe {
                    position_blend: c.placed.position.extend(c.placed.blend_m).into(),
                    half_extents_mips: c
                        .placed
                        .half_extents
                        .extend((c.cube.mips - 1) as f32)
                        .into(),
                    exposure: [c.exposure, 0.0, 0.0, 0.0],
                };
            }
        }
        data.count = [self.slots(), 0, 0, 0];
        gpu.queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&data));
    }
}

/// Copies the face just captured into the strip of the reflection probe being captured
/// (a system of [`crate::render::CaptureSchedule`]).
pub fn record_face_copy(
    gpu: Res<Gpu>,
    targets: Res<RenderTargets>,
    capture: Option<Res<CaptureView>>,
    probes: Res<ReflectionProbesGpu>,
    mut encoder: ResMut<FrameEncoder>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(CaptureView {
        target: CaptureTarget::ReflectionProbe(_),
        face,
        ..
    }) = capture.as_deref().copied()
    else {
        return;
    };
    let (Some(t), Some(strip), Some(encoder)) = (
        targets.current.as_ref(),
        probes.strip.as_ref(),
        encoder.encoder.as_mut(),
    ) else {
        return;
    };
    let Some(hdr) = t.view(HDR) else {
        return;
    };
    let size = t.size.0;
    gpu.queue
        .write_buffer(&probes.params, 0, bytemuck::cast_slice(&[face, size, 0, 0]));
    let strip_view = strip.create_view(&Default::default());
    let group = match FACE_COPY.group(
        &gpu,
        &probes.copy_layout,
        vec![
            wgpu::BindingResource::TextureView(hdr),
            probes.params.as_entire_binding(),
            wgpu::BindingResource::TextureView(&strip_view),
        ],
    ) {
        Ok(g) => g,
        Err(e) => {
            errors.0.push(e);
            return;
        }
    };
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("reflection capture copy"),
        timestamp_writes: None,
    });
    pass.set_pipeline(&probes.copy);
    pass.set_bind_group(0, &group, &[]);
    pass.dispatch_workgroups(size.div_ceil(8), size.div_ceil(8), 1);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders::ShaderDef;

    #[test]
    fn the_probes_lay_out_as_the_shader_does() {
        let slots = MAX_REFLECTION_PROBES as u32;
        let defs = [ShaderDef::U32("REFLECTION_PROBE_SLOTS", slots)];
        let entry = "probe_reflections.wgsl";
        crate::assert_wgsl_twin!(
            GpuReflectionProbe,
            entry,
            &defs,
            "ReflectionProbe",
            [position_blend, half_extents_mips, exposure]
        );
        crate::assert_wgsl_twin!(
            GpuReflectionProbes,
            entry,
            &defs,
            "ReflectionProbes",
            [items, count]
        );
    }
}

//! The depth pyramid (`shaders/depth_pyramid.wgsl`): the depth buffer and, above it,
//! levels that each hold the nearest depth of the texels they cover (reversed Z: the
//! largest value). Screen-space reflections trace over it hierarchically (Uludag 2014,
//! "Hi-Z Screen-Space Cone-Traced Reflections", GPU Pro 5): a ray skips a whole texel of a
//! high level when it stays in front of that texel's nearest surface.
//!
//! Level 0 is the depth buffer itself, read in place (with a full-resolution copy into
//! the buffer the pass took 19.1 ms at 1280×720 on lavapipe, without it 6.5–6.8 ms:
//! docs/src/measured.md); the levels above live one after the other in a storage buffer
//! ([`PyramidLayout`]), built by one compute dispatch per level. A mip chain does not
//! serve every backend: GL cannot render R32Float, and reads the upper mips of an R32Uint
//! texture as 0.
//!
//! It runs only when screen-space reflections do (the same conditions,
//! [`reflections_skip_reason`]).

use crate::error::Result;
use crate::quality::Quality;
use crate::quality::knob::Value;
use crate::quality::knobs::SSR;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::DEPTH;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::create_module;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use wgpu::util::DeviceExt;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The hierarchical depth pyramid.
    pub const DepthPyramid: PassId = PassId::new("depth pyramid");
}

/// The most levels a pyramid has (a side of up to 32768 pixels).
pub const MAX_LEVELS: usize = 16;

/// The pyramid, which the pass owns and keeps between frames.
pub const DEPTH_PYRAMID: Slot = Slot::owned("depth pyramid");

/// The bindings of the build: the depth buffer, the layout, the level a dispatch writes
/// and the pyramid.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "depth pyramid",
    visibility: wgpu::ShaderStages::COMPUTE,
    bindings: &[
        ("depth_buffer", Binding::TextureLoad),
        ("levels", Binding::Uniform),
        ("step", Binding::Uniform),
        ("pyramid", Binding::StorageReadWrite),
    ],
};

/// `PyramidLayout` of `pyramid_layout.wgsl`: per level, its first element in the
/// buffer, width and height; and the number of levels. Level 0 is the depth buffer and
/// takes no room in the buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PyramidLayout {
    /// (first element, width, height, 0) per level.
    pub levels: [[u32; 4]; MAX_LEVELS],
    /// (number of levels, 0, 0, 0).
    pub count: [u32; 4],
}

impl PyramidLayout {
    /// The levels over a depth buffer of `size`: each half the one below (rounded
    /// down, at least 1), down to 1×1, the ones above level 0 packed one after the other
    /// from element 0; and the number of elements they take in all.
    pub fn new(size: (u32, u32)) -> (PyramidLayout, u64) {
        let mut layout = PyramidLayout {
            levels: [[0; 4]; MAX_LEVELS],
            count: [0; 4],
        };
        let (mut w, mut h) = (size.0.max(1), size.1.max(1));
        let mut offset = 0u64;
        for (k, level) in layout.levels.iter_mut().enumerate() {
            *level = [offset as u32, w, h, 0];
            if k > 0 {
                offset += u64::from(w) * u64::from(h);
            }
            layout.count[0] = k as u32 + 1;
            if w == 1 && h == 1 {
                break;
            }
            (w, h) = ((w / 2).max(1), (h / 2).max(1));
        }
        (layout, offset)
    }
}

/// The pyramid's buffers and the groups that build each level above level 0.
pub struct Pyramid {
    /// Size of level 0 (the frame's).
    pub size: (u32, u32),
    /// The levels' layout (a uniform buffer of [`PyramidLayout`]).
    pub layout: wgpu::Buffer,
    /// The levels (u32 depth bits).
    pub buffer: wgpu::Buffer,
    /// Where each level lies in `buffer`.
    levels: PyramidLayout,
    groups: Vec<wgpu::BindGroup>,
}

/// The depth pyramid pass.
#[derive(Resource)]
pub struct DepthPyramidPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Compiled when the pass first runs: level 1's (`cs_first`, from the depth buffer)
    /// and the levels' above (`cs_build`, from the level below).
    pipelines: Option<[wgpu::ComputePipeline; 2]>,
    /// One uniform per level: the level its dispatch writes.
    steps: Vec<wgpu::Buffer>,
    /// The pyramid, once a frame has needed it.
    pub pyramid: Option<Pyramid>,
    /// Bumped when the pyramid is remade, so users rebuild their bind groups.
    pub generation: u64,
    depth_generation: u64,
}

impl FramePass for DepthPyramidPass {
    const ID: PassId = PassId::DepthPyramid;
    const READS: &'static [Slot] = &[DEPTH];
    const WRITES: &'static [Slot] = &[DEPTH_PYRAMID];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(DepthPyramidPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        match reflections_skip_reason(world) {
            Some(reason) => {
                PassDecision::new(false, format!("no reflections to trace: {reason}"), ())
            }
            None => PassDecision::new(
                true,
                "nearest depth per level, for the reflection tracer",
                (),
            ),
        }
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_pyramid.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        pyramid_pass.into_configs()
    }
}

impl DepthPyramidPass {
    /// Creates the layouts and the per-level uniforms; the pipeline compiles when the
    /// pass first runs.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("depth pyramid"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let steps = (0..MAX_LEVELS as u32)
            .map(|level| {
                gpu.device
                    .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("depth pyramid level"),
                        contents: bytemuck::bytes_of(&[level, 0, 0, 0]),
                        usage: wgpu::BufferUsages::UNIFORM,
                    })
            })
            .collect();
        DepthPyramidPass {
            layout,
            pipeline_layout,
            pipelines: None,
            steps,
            pyramid: None,
            generation: 0,
            depth_generation: 0,
        }
    }

    fn pipeline(&mut self, gpu: &Gpu) -> Result<()> {
        if self.pipelines.is_some() {
            return Ok(());
        }
        let module = create_module(
            gpu,
            "depth pyramid",
            &gpu.shaders.compose("depth_pyramid.wgsl", &[])?,
        )?;
        let entry = |entry_point: &str| {
            gpu.checked("depth pyramid pipeline", |device| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some("depth pyramid"),
                    layout: Some(&self.pipeline_layout),
                    module: &module,
                    entry_point: Some(entry_point),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
        };
        self.pipelines = Some([entry("cs_first")?, entry("cs_build")?]);
        Ok(())
    }
}

/// Why screen-space reflections, the pyramid's only user, are not traced this frame, if
/// they are not ([`crate::render::indirect::reflections`] decides with it too).
pub fn reflections_skip_reason(world: &World) -> Option<String> {
    let ssr = world.resource::<Quality>().ssr;
    let frame = world.resource::<ExtractedFrame>();
    if !ssr.enabled {
        return Some(format!(
            "screen-space reflections are off ({})",
            SSR.setting(Value::Bool(false))
        ));
    }
    if frame.instances.is_empty() {
        return Some("nothing is drawn".into());
    }
    // A roughness map can only lower a material's roughness factor; maps without one
    // (the neutral maps of forward-drawn materials) leave it as it is.
    let smoothest = frame
        .instances
        .iter()
        .map(|i| i.params[1])
        .fold(f32::INFINITY, f32::min);
    let factors_only = frame
        .material_maps
        .iter()
        .all(|m| m.maps.metallic_roughness.is_none());
    if factors_only && smoothest > ssr.max_roughness {
        return Some(format!(
            "no surface smoother than the cutoff (roughness {:.2}; the smoothest is {smoothest:.2})",
            ssr.max_roughness
        ));
    }
    let gpu = world.resource::<Gpu>();
    if !gpu
        .adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
    {
        return Some("the adapter has no compute shaders to build the depth pyramid".into());
    }
    None
}

/// (Re)creates the pyramid at the frame's size and the groups that build each level.
pub fn prepare_pyramid(
    gpu: Res<Gpu>,
    targets: Res<RenderTargets>,
    mut pass: ResMut<DepthPyramidPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(t) = targets.current.as_ref() else {
        return;
    };
    let Some(depth) = t.view(DEPTH) else {
        return;
    };
    if let Err(e) = pass.pipeline(&gpu) {
        errors.0.push(e);
        return;
    }
    if pass.pyramid.as_ref().is_some_and(|p| p.size == t.size)
        && pass.depth_generation == t.generation
    {
        return;
    }
    let (layout, elements) = PyramidLayout::new(t.size);
    let layout_buffer = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("depth pyramid layout"),
            contents: bytemuck::bytes_of(&layout),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("depth pyramid"),
        // At least one element: a 1×1 frame has no level above the depth buffer.
        size: elements.max(1) * 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let count = layout.count[0] as usize;
    let mut groups = Vec::with_capacity(count);
    for step in &pass.steps[1..count] {
        match BINDINGS.group(
            &gpu,
            &pass.layout,
            vec![
                wgpu::BindingResource::TextureView(depth),
                layout_buffer.as_entire_binding(),
                step.as_entire_binding(),
                buffer.as_entire_binding(),
            ],
        ) {
            Ok(g) => groups.push(g),
            Err(e) => {
                errors.0.push(e);
                return;
            }
        }
    }
    pass.pyramid = Some(Pyramid {
        size: t.size,
        layout: layout_buffer,
        buffer,
        levels: layout,
        groups,
    });
    pass.depth_generation = t.generation;
    pass.generation += 1;
}

/// Records one dispatch per level from level 1 up (each reads the one below it).
pub fn pyramid_pass(pass: Res<DepthPyramidPass>, mut encoder: ResMut<FrameEncoder>) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(p), Some([first, above])) = (
        encoder.as_mut(),
        pass.pyramid.as_ref(),
        pass.pipelines.as_ref(),
    ) else {
        return;
    };
    let scope = timer.begin_pass(PassId::DepthPyramid);
    {
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("depth pyramid"),
            timestamp_writes: timer.compute_writes(&scope),
        });
        for (k, (group, level)) in p.groups.iter().zip(&p.levels.levels[1..]).enumerate() {
            cp.set_pipeline(if k == 0 { first } else { above });
            cp.set_bind_group(0, group, &[]);
            cp.dispatch_workgroups(level[1].div_ceil(8), level[2].div_ceil(8), 1);
        }
    }
    timer.end_pass(scope);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_halve_down_to_one_texel_and_pack_without_gaps() {
        let (layout, elements) = PyramidLayout::new((1280, 720));
        let count = layout.count[0] as usize;
        assert_eq!(count, 11, "1280 → 640 → … → 1");
        assert_eq!(layout.levels[0], [0, 1280, 720, 0]);
        assert_eq!(
            layout.levels[1],
            [0, 640, 360, 0],
            "level 0 is the depth buffer"
        );
        assert_eq!(layout.levels[2], [640 * 360, 320, 180, 0]);
        assert_eq!(&layout.levels[count - 1][1..3], &[1, 1]);
        let sum: u64 = layout.levels[1..count]
            .iter()
            .map(|l| u64::from(l[1]) * u64::from(l[2]))
            .sum();
        assert_eq!(sum, elements);
        let (one, n) = PyramidLayout::new((1, 1));
        assert_eq!((one.count[0], n), (1, 0));
        let (big, _) = PyramidLayout::new((32768, 3));
        assert_eq!(big.count[0] as usize, MAX_LEVELS);
    }
}

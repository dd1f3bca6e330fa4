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
//! [`crate::render::extract::reflecting::skip_after_gbuffer`], which follows the G-buffer's
//! decision).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::reflecting::skip_after_gbuffer;
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::DEPTH;
use crate::render::graph::{
    BufferDesc, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing, Slot,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipelines::{compute_pipeline, create_module, pipeline_layout};
use bevy_ecs::prelude::*;
use wgpu::util::DeviceExt;

#[allow(non_upper_case_globals)]
impl PassId {
    /// The hierarchical depth pyramid.
    pub const DepthPyramid: PassId = PassId::new("depth pyramid");
}

/// The most levels a pyramid has (a side of up to 32768 pixels).
pub const MAX_LEVELS: usize = 16;

/// The pyramid's levels above level 0 (the depth buffer): u32 depth bits, packed as
/// [`DEPTH_PYRAMID_LAYOUT`] says.
pub const DEPTH_PYRAMID: Slot = Slot::buffer(
    "depth pyramid",
    BufferDesc {
        usage: wgpu::BufferUsages::STORAGE,
        history: false,
    },
);

/// Where each level lies in [`DEPTH_PYRAMID`]: a uniform [`PyramidLayout`].
pub const DEPTH_PYRAMID_LAYOUT: Slot = Slot::buffer(
    "depth pyramid layout",
    BufferDesc {
        usage: wgpu::BufferUsages::UNIFORM,
        history: false,
    },
);

/// The bindings of the build: the depth buffer, the layout, the level a dispatch writes
/// and the pyramid.
pub const BINDINGS: BindGroupSpec =
    BindGroupSpec::compute("depth pyramid", declared::DEPTH_PYRAMID_0);

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
    /// This frame's levels.
    levels: Option<PyramidLayout>,
    /// The group that builds each level above level 0.
    groups: Vec<CachedGroup>,
}

impl FramePass for DepthPyramidPass {
    const ID: PassId = PassId::DepthPyramid;
    const READS: &'static [Slot] = &[DEPTH];
    const WRITES: &'static [Slot] = &[DEPTH_PYRAMID, DEPTH_PYRAMID_LAYOUT];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(DepthPyramidPass::new(gpu))
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<()> {
        let output = world
            .get_resource::<crate::render::frame::FrameOutput>()
            .map_or((1, 1), |o| o.size);
        // At least one element: a 1×1 frame has no level above the depth buffer.
        let elements = PyramidLayout::new(output).1.max(1);
        let decision = match skip_after_gbuffer(world, plan) {
            Some(reason) => {
                PassDecision::new(false, format!("no reflections to trace: {reason}"), ())
            }
            None => PassDecision::new(
                true,
                "nearest depth per level, for the reflection tracer",
                (),
            ),
        };
        decision
            .sized(DEPTH_PYRAMID, Sizing::Buffer(elements * 4))
            .sized(
                DEPTH_PYRAMID_LAYOUT,
                Sizing::Buffer(std::mem::size_of::<PyramidLayout>() as u64),
            )
    }

    crate::pass_systems!(prepare_pyramid, pyramid_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![ShaderBuild::new(
            "depth_pyramid.wgsl",
            Vec::new(),
            &[(0, BINDINGS)],
        )]
    }
}

impl DepthPyramidPass {
    /// Creates the layouts and the per-level uniforms; the pipeline compiles when the
    /// pass first runs.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        let pipeline_layout = pipeline_layout(gpu, "depth pyramid", &[&layout]);
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
            levels: None,
            groups: Vec::new(),
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
            compute_pipeline(
                gpu,
                "depth pyramid",
                Some(&self.pipeline_layout),
                &module,
                entry_point,
            )
        };
        self.pipelines = Some([entry("cs_first")?, entry("cs_build")?]);
        Ok(())
    }
}

/// Writes the levels' layout and makes (or keeps) the groups that build each level.
pub fn prepare_pyramid(mut p: Prepare<DepthPyramidPass>) -> Result<()> {
    let Some(t) = p.targets.current.as_ref() else {
        return Ok(());
    };
    let (Some(depth), Some(buffer), Some(layout_buffer)) = (
        t.view(DEPTH),
        t.buffer(DEPTH_PYRAMID),
        t.buffer(DEPTH_PYRAMID_LAYOUT),
    ) else {
        return Ok(());
    };
    p.pass.pipeline(&p.gpu)?;
    let (layout, _) = PyramidLayout::new(t.size);
    p.gpu
        .queue
        .write_buffer(layout_buffer, 0, bytemuck::bytes_of(&layout));
    let count = layout.count[0] as usize;
    let pass = &mut *p.pass;
    pass.levels = Some(layout);
    pass.groups
        .resize_with(count.saturating_sub(1), CachedGroup::default);
    for (step, group) in pass.steps[1..count].iter().zip(&mut pass.groups) {
        let made = group.get(
            &p.gpu,
            &BINDINGS,
            &pass.layout,
            vec![
                wgpu::BindingResource::TextureView(depth),
                layout_buffer.as_entire_binding(),
                step.as_entire_binding(),
                buffer.as_entire_binding(),
            ],
        );
        made?;
    }
    Ok(())
}

/// Records one dispatch per level from level 1 up (each reads the one below it).
pub fn pyramid_pass(mut r: Record<DepthPyramidPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(levels), Some([first, above])) = (
        encoder.as_mut(),
        r.pass.levels.as_ref(),
        r.pass.pipelines.as_ref(),
    ) else {
        return;
    };
    let scope = timer.begin_pass(PassId::DepthPyramid);
    {
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("depth pyramid"),
            timestamp_writes: timer.compute_writes(&scope),
        });
        for (k, (group, level)) in r.pass.groups.iter().zip(&levels.levels[1..]).enumerate() {
            let Some(group) = group.group() else {
                continue;
            };
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
    fn the_layout_lays_out_as_the_shader_does() {
        crate::assert_wgsl_twin!(
            PyramidLayout,
            "depth_pyramid.wgsl",
            &[],
            "PyramidLayout",
            [levels, count]
        );
    }

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

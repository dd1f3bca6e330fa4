//! Tiled light culling (`shaders/light_culling.wgsl`): a compute pass that lists, per
//! 16×16-pixel tile, the unshadowed point and spot lights whose range reaches the tile's
//! geometry, so the lighting pass pays only for those. Runs when the scene has at least
//! [`LIGHT_CULLING_MIN_LIGHTS`] unshadowed point and spot lights and
//! [`crate::quality::Quality::light_culling`] is on.

use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::LIGHT_CULLING;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::DEPTH;
use crate::render::graph::slots::LIGHT_TILES;
use crate::render::graph::{
    Fact, FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Sizing, Slot,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{ComputePipelines, ShaderVariant};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use bevy_ecs::prelude::*;

/// Pixels per tile side (`TILE_SIZE` in `light_tiles.wgsl`).
pub const TILE_SIZE: u32 = 16;
/// Lights of one kind a tile lists (`MAX_TILE_LIGHTS`); more make the tile fall back to
/// every light of that kind.
pub const MAX_TILE_LIGHTS: u32 = 255;
/// Words per tile (`TILE_STRIDE`).
const TILE_STRIDE: u32 = 2 + 2 * MAX_TILE_LIGHTS;
/// The fewest unshadowed point and spot lights for which culling runs. Below it the
/// culling pass costs more than it saves (README, "Light culling", measured on lavapipe).
pub const LIGHT_CULLING_MIN_LIGHTS: u32 = 8;

/// The light culling pass's bind group.
pub const BINDINGS: BindGroupSpec =
    BindGroupSpec::compute("light culling", declared::LIGHT_CULLING_0);

/// Whether light culling runs this frame: the lighting pass then reads the tile lists.
pub const LIGHTS_CULLED: Fact<bool> = Fact::new("light culling runs");

#[allow(non_upper_case_globals)]
impl PassId {
    /// Lists the lights that reach each screen tile.
    pub const LightCulling: PassId = PassId::new("light culling");
}

/// The light culling shader variant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LightCullingVariant {
    /// Lights are read from the uniform copy (every light fits it), not from the storage
    /// buffer.
    pub uniform_lights: bool,
    /// Lights the uniform copy of the light array holds.
    pub uniform_capacity: u32,
}

/// `UNIFORM_LIGHTS`, and the uniform copy's capacity (at least 1, a WGSL array's least).
impl ShaderVariant for LightCullingVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![
            ShaderDef::Bool("UNIFORM_LIGHTS", self.uniform_lights),
            ShaderDef::U32("UNIFORM_LIGHT_CAPACITY", self.uniform_capacity.max(1)),
        ]
    }
}

impl FramePass for LightCullingPass {
    const ID: PassId = PassId::LightCulling;
    const CAPTURE: bool = true;
    const READS: &'static [Slot] = &[DEPTH];
    const WRITES: &'static [Slot] = &[LIGHT_TILES];
    const PUBLISHES: &'static [FactId] = &[LIGHTS_CULLED.id];
    type Variant = LightCullingVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(LightCullingPass::new(gpu))
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<LightCullingVariant> {
        let frame = world.resource::<ExtractedFrame>();
        let quality = world.resource::<crate::quality::Quality>();
        let buffers = world.resource::<SceneBuffers>();
        let instances = frame.instances.len();
        let counts = frame.light_counts;
        let unshadowed = (counts.point - frame.shadowed_counts[1].min(counts.point))
            + (counts.spot - frame.shadowed_counts[2].min(counts.spot));
        let min_lights = LIGHT_CULLING_MIN_LIGHTS;
        let capture = world.contains_resource::<crate::render::frame::CaptureView>();
        let reason = if capture {
            // Measured: with culled tiles, captures of the `lights` scene differed between
            // GL and Vulkan by up to 47/255 in the frame, without them by 4/255 (as the
            // frame itself); a probe's small 90° views gain little from tiles anyway.
            "probe capture: every pixel loops over all lights".into()
        } else if !quality.light_culling {
            format!("off ({})", LIGHT_CULLING.setting(Value::Bool(false)))
        } else if instances == 0 {
            "nothing to light".into()
        } else if unshadowed >= min_lights {
            format!("{unshadowed} unshadowed point/spot light(s) into 16×16-pixel tiles")
        } else {
            format!(
                "{unshadowed} unshadowed point/spot light(s): fewer than {min_lights}, every pixel loops over all"
            )
        };
        let runs = !capture && quality.light_culling && instances > 0 && unshadowed >= min_lights;
        let output = world
            .get_resource::<crate::render::frame::FrameOutput>()
            .map_or((1, 1), |o| o.size);
        let (x, y) = tile_count(output);
        let bytes = if runs {
            u64::from(x) * u64::from(y) * u64::from(TILE_STRIDE) * 4
        } else {
            16
        };
        PassDecision::new(
            runs,
            reason,
            LightCullingVariant {
                uniform_lights: buffers.lights_fit_uniform(frame),
                uniform_capacity: buffers.uniform_light_capacity,
            },
        )
        .sized(LIGHT_TILES, Sizing::Buffer(bytes))
        .publishing(&LIGHTS_CULLED, runs)
    }

    crate::pass_systems!(prepare_light_culling, light_culling_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        [false, true]
            .map(|uniform_lights| {
                let variant = LightCullingVariant {
                    uniform_lights,
                    uniform_capacity: 8,
                };
                ShaderBuild::new(
                    "light_culling.wgsl",
                    variant.shader_defs(),
                    &[(0, BINDINGS)],
                )
            })
            .to_vec()
    }
}

/// The culling pipelines (compiled on first use, one per variant), the tile buffer's
/// bind group and this frame's dispatch.
#[derive(Resource)]
pub struct LightCullingPass {
    layout: wgpu::BindGroupLayout,
    pipelines: ComputePipelines<LightCullingVariant>,
    /// The variant this frame dispatches.
    variant: LightCullingVariant,
    tile_count: (u32, u32),
    bind_group: CachedGroup,
}

impl LightCullingPass {
    /// The bind group layout; no pipeline is compiled yet.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        LightCullingPass {
            pipelines: ComputePipelines::new(
                gpu,
                ("light culling", "light_culling.wgsl", "cs_cull"),
                &[&layout],
            ),
            layout,
            variant: LightCullingVariant::default(),
            tile_count: (0, 0),
            bind_group: CachedGroup::default(),
        }
    }
}

/// Tiles across and down a target of `size` pixels.
pub fn tile_count(size: (u32, u32)) -> (u32, u32) {
    (size.0.div_ceil(TILE_SIZE), size.1.div_ceil(TILE_SIZE))
}

/// Compiles the variant this frame needs, sizes the tile buffer for this frame's target
/// and rebuilds the bind group on changes.
pub fn prepare_light_culling(
    mut p: Prepare<LightCullingPass>,
    buffers: Res<SceneBuffers>,
) -> Result<()> {
    let (Some(t), Some(variant)) = (
        p.targets.current.as_ref(),
        p.plan.variant::<LightCullingPass>(),
    ) else {
        return Ok(());
    };
    let (Some(depth), Some(tiles)) = (t.view(DEPTH), t.buffer(LIGHT_TILES)) else {
        return Ok(());
    };
    p.pass.pipelines.ensure(&p.gpu, variant)?;
    p.pass.variant = *variant;
    p.pass.tile_count = tile_count(t.size);
    let LightCullingPass {
        layout, bind_group, ..
    } = &mut *p.pass;
    let resources = vec![
        buffers.view.as_entire_binding(),
        buffers.lights.buffer.as_entire_binding(),
        wgpu::BindingResource::TextureView(depth),
        tiles.as_entire_binding(),
        buffers.lights_uniform.as_entire_binding(),
    ];
    bind_group
        .get(&p.gpu, &BINDINGS, layout, resources)
        .map(|_| ())
}

/// Records the culling dispatch: one invocation per tile, in 8×8 workgroups.
pub fn light_culling_pass(mut r: Record<LightCullingPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let pipeline = r.pass.pipelines.get(&r.pass.variant);
    let (Some(encoder), Some(group), Some(pipeline)) =
        (encoder.as_mut(), r.pass.bind_group.group(), pipeline)
    else {
        return;
    };
    let scope = timer.begin_pass(PassId::LightCulling);
    {
        let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("light culling"),
            timestamp_writes: timer.compute_writes(&scope),
        });
        cp.set_pipeline(pipeline);
        cp.set_bind_group(0, group, &[]);
        cp.dispatch_workgroups(
            r.pass.tile_count.0.div_ceil(8),
            r.pass.tile_count.1.div_ceil(8),
            1,
        );
    }
    timer.end_pass(scope);
}

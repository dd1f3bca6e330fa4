//! The clearcoat pass (`shaders/coat.wgsl`): the coat of every clearcoated opaque surface
//! ([`crate::scene::Material::clearcoat`], glTF's `KHR_materials_clearcoat`), drawn over
//! the lit frame once the deferred lighting and SSR have lit the base beneath it.
//!
//! The coat is not in the G-buffer. Its surfaces are drawn a second time, with the
//! G-buffer's textured vertex code, and a fragment is kept where it lies on the opaque
//! depth the G-buffer wrote (`GreaterEqual` with reversed Z, pulled a few depth units
//! towards the camera so that the same triangle always passes). Each fragment is lit by
//! the deferred pass's own code (`surface_light.wgsl`: every light kind, shadows, the
//! environment, the probes, the AO pass's occlusion, the light tiles) as a surface with
//! only the coat's specular lobe, and leaves `(factor · L_coat, factor · E_coat)`;
//! the pipeline composites it as `dst ← src + dst·(1 − α)`, which dims the base's light
//! by what the coat reflects (`crate::clearcoat`). The frame's coverage (alpha) is kept.
//!
//! So a scene without a clearcoat pays nothing, and the G-buffer layout is unchanged; the
//! price is a second draw of the coated meshes (docs/src/materials.md#clearcoat). Probe
//! captures do not run this pass: probes see coated surfaces without their coat.
//!
//! Its group 0 is the view ([`VIEW`]); it binds the lighting pass's groups 1 to 3 as they
//! are and the material maps as group 4, which hold the coat's factor and roughness: it
//! runs only on adapters with five bind groups. Compiled per (lighting variant,
//! double-sided, HDR format).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::deform::DEFORMED_VERTICES;
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::forward::{
    ForwardInputs, ForwardPipelines, ForwardShape, MAPS_GROUP, draw_batches,
};
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::indirect::ambient_occlusion::AMBIENT_OCCLUSION;
use crate::render::light_culling::LIGHT_TILES;
use crate::render::lighting::{LightingPass, LightingVariant};
use crate::render::material_maps::{GpuMaterialMaps, group_def};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::shadow::pass::SHADOW_ATLAS;
use crate::render::targets::{self, RenderTargets};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::{ScheduleSystem, SystemParam};

#[allow(non_upper_case_globals)]
impl PassId {
    /// The clearcoat of coated surfaces over the lit frame.
    pub const Clearcoat: PassId = PassId::new("clearcoat");
}

/// Group 0: the view.
pub const VIEW: BindGroupSpec = BindGroupSpec {
    label: "clearcoat",
    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
    bindings: &[("view", Binding::Uniform)],
};

/// The coat's blend: colour "over" with premultiplied alpha, dst ← src + dst·(1 − α);
/// the frame's alpha (its coverage) is kept.
const COAT_BLEND: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// Depth units the coat is pulled towards the camera (reversed Z: up), so that a coat
/// fragment passes `GreaterEqual` against the depth its own triangle wrote even where the
/// two vertex programs round differently.
const COAT_DEPTH_BIAS: i32 = 4;

impl FramePass for CoatPass {
    const ID: PassId = PassId::Clearcoat;
    const READS: &'static [Slot] = &[
        DEFORMED_VERTICES,
        HDR,
        DEPTH,
        SHADOW_ATLAS,
        LIGHT_TILES,
        AMBIENT_OCCLUSION,
    ];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = Option<LightingVariant>;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        let lighting = world.resource::<LightingPass>();
        let maps = world.resource::<GpuMaterialMaps>();
        Ok(CoatPass::new(gpu, lighting.layouts(), &maps.layout))
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<Option<LightingVariant>> {
        let frame = world.resource::<ExtractedFrame>();
        let gpu = world.resource::<Gpu>();
        let count = frame.coated_batches().count();
        let lighting = plan.variant::<LightingPass>().copied();
        let hdr = world
            .resource::<crate::quality::Quality>()
            .hdr_precision
            .format();
        let blendable = hdr != wgpu::TextureFormat::Rgba32Float
            || gpu
                .device
                .features()
                .contains(wgpu::Features::FLOAT32_BLENDABLE);
        let groups = gpu.device.limits().max_bind_groups;
        let (runs, reason) = if count == 0 {
            (false, "no clearcoated surface in view".to_string())
        } else if lighting.is_none() {
            (false, "the lighting pass does not run".into())
        } else if groups <= MAPS_GROUP {
            (
                false,
                format!(
                    "{count} clearcoated batch(es) drawn without their coat: the adapter has {groups} bind groups, the pass needs 5"
                ),
            )
        } else if !blendable {
            (
                false,
                format!(
                    "{count} clearcoated batch(es) drawn without their coat: this adapter cannot blend the f32 HDR target (the f16 target can)"
                ),
            )
        } else {
            (
                true,
                format!("{count} clearcoated batch(es), coat over the lit base"),
            )
        };
        PassDecision::new(runs, reason, lighting.filter(|_| runs))
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_coat.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        coat_pass.into_configs()
    }
}

/// The clearcoat pass's pipelines and its view group.
#[derive(Resource)]
pub struct CoatPass {
    pipelines: ForwardPipelines<LightingVariant>,
    /// The view group and the scene buffers' generation it was built from.
    view_group: Option<(u64, wgpu::BindGroup)>,
}

impl CoatPass {
    /// The layouts: the view, the lighting pass's groups 1 to 3 (`lighting`), and the
    /// material maps' (`maps`).
    pub fn new(
        gpu: &Gpu,
        lighting: &[wgpu::BindGroupLayout; 4],
        maps: &wgpu::BindGroupLayout,
    ) -> CoatPass {
        CoatPass {
            pipelines: ForwardPipelines::new(gpu, "clearcoat", &VIEW, lighting, maps),
            view_group: None,
        }
    }

    /// The WGSL header of `variant`, for a uniform light copy of `uniform_capacity`
    /// lights: the lighting pass's, and the maps' group.
    pub fn defs(variant: LightingVariant, uniform_capacity: u32) -> Vec<ShaderDef> {
        let mut defs = LightingPass::defs(variant, uniform_capacity);
        defs.push(group_def(MAPS_GROUP));
        defs
    }
}

/// The coat's pipeline into `format`: "over" with the coat's weight as alpha, on the
/// opaque depth.
fn coat_shape(format: wgpu::TextureFormat) -> ForwardShape {
    ForwardShape {
        entry: "fs_main",
        targets: vec![Some(wgpu::ColorTargetState {
            format,
            blend: Some(COAT_BLEND),
            write_mask: wgpu::ColorWrites::ALL,
        })],
        depth: wgpu::DepthStencilState {
            format: targets::DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            // Reversed Z: on the opaque surface or in front of it.
            depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState {
                constant: COAT_DEPTH_BIAS,
                slope_scale: 0.0,
                clamp: 0.0,
            },
        },
    }
}

/// What the clearcoat pass prepares from, besides its own resource.
#[derive(SystemParam)]
pub struct PrepareInputs<'w> {
    frame: Res<'w, ExtractedFrame>,
    buffers: Res<'w, SceneBuffers>,
    targets: Res<'w, RenderTargets>,
}

/// Compiles the pipelines this frame's coated batches need and rebuilds the view group
/// when the scene buffers were recreated.
pub fn prepare_coat(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    inputs: PrepareInputs,
    mut pass: ResMut<CoatPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let PrepareInputs {
        frame,
        buffers,
        targets,
    } = inputs;
    let (Some(Some(variant)), Some(t)) = (
        plan.variant::<CoatPass>().copied(),
        targets.current.as_ref(),
    ) else {
        return;
    };
    let capacity = buffers.uniform_light_capacity;
    if let Err(e) = pass.pipelines.ensure(
        &gpu,
        (variant, t.hdr_format),
        frame.coated_batches(),
        ("coat.wgsl", &|| CoatPass::defs(variant, capacity)),
        &coat_shape,
    ) {
        errors.0.push(e);
        return;
    }
    if pass
        .view_group
        .as_ref()
        .is_some_and(|(k, _)| *k == buffers.generation)
    {
        return;
    }
    match VIEW.group(
        &gpu,
        &pass.pipelines.view_layout,
        vec![buffers.view.as_entire_binding()],
    ) {
        Ok(group) => pass.view_group = Some((buffers.generation, group)),
        Err(e) => errors.0.push(e),
    }
}

/// Records the coated batches' coats over the HDR target.
pub fn coat_pass(
    plan: Res<FramePlan>,
    pass: Res<CoatPass>,
    inputs: ForwardInputs,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(t), Some(Some(variant)), Some((_, view_group)), Some(shared)) = (
        encoder.as_mut(),
        inputs.targets.current.as_ref(),
        plan.variant::<CoatPass>().copied(),
        pass.view_group.as_ref(),
        inputs.lighting.shared_groups(),
    ) else {
        return;
    };
    let Some([hdr, depth]) = t.views([HDR, DEPTH]) else {
        return;
    };
    let scope = timer.begin_pass(PassId::Clearcoat);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clearcoat"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        draw_batches(
            &mut rp,
            &inputs,
            (view_group, shared),
            MAPS_GROUP,
            inputs.frame.coated_batches(),
            |batch| {
                pass.pipelines
                    .get(variant, batch.double_sided, t.hdr_format)
            },
        );
    }
    timer.end_pass(scope);
}

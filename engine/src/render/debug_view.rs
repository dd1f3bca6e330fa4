//! Debug views: one channel of the frame shown instead of the tone-mapped image
//! (`shaders/debug_view.wgsl`). The pass, and its pipeline, exist only while a view is
//! chosen; it replaces the tone mapping pass.
//!
//! What each view shows, as display values (8-bit value = shown value × 255):
//!
//! | view | shown |
//! | --- | --- |
//! | albedo | the base colour as stored (sRGB-encoded) |
//! | normal | world-space normal `n · 0.5 + 0.5`; black background |
//! | metallic, roughness | the stored value as grey |
//! | occlusion | the occlusion indirect light sees, as grey: the material's, combined with the AO pass's where it runs (`combine_occlusion`); black background |
//! | depth | [`depth_grey`] of the view depth; black background |
//! | shadow atlas | stored shadow depth (reversed Z: 1 near the light, 0 cleared) of the square atlas, which fills the frame's height from the left edge |
//! | validation, validation-strict | the worst verdict of `lumen::validate`'s metal/roughness rules on the G-buffer's base colour and metallic: green valid, yellow borderline, red invalid (`Verdict::color`); black background |
//! | CoC | thin-lens CoC radius ÷ the largest radius, red in front of the focus plane, green behind it (the lens's settings even when depth of field is off) |

use crate::choice::Choice;
use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::dof::LensUniform;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors, FrameOutput};
use crate::render::graph::slots::{DEPTH, DISPLAY, GBUFFER_BASE_COLOR, GBUFFER_NORMAL};
use crate::render::graph::{FactId, FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::indirect::ambient_occlusion::{AMBIENT_OCCLUSION, SCREEN_AO};
use crate::render::pipelines::{draw_fullscreen, fullscreen_variant};
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::shadow::atlas::ShadowAtlas;
use crate::render::shadow::pass::SHADOW_ATLAS;
use crate::render::targets::RenderTargets;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use std::collections::HashMap;

crate::choice::choices! {
/// Which channel the frame shows: a resource; [`DebugView::Off`] is the normal image.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DebugView: "debug view" {
    /// The tone-mapped image.
    #[default]
    Off(0) = "off",
    /// Base colour.
    Albedo(1) = "albedo",
    /// World-space normal.
    Normal(2) = "normal",
    /// Metallic.
    Metallic(3) = "metallic",
    /// Perceptual roughness.
    Roughness(4) = "roughness",
    /// Ambient occlusion.
    Occlusion(5) = "occlusion",
    /// View depth, logarithmic.
    Depth(6) = "depth",
    /// The shadow map atlas.
    ShadowAtlas(7) = "shadow-atlas",
    /// The thin-lens circle of confusion.
    CircleOfConfusion(8) = "coc",
    /// The texture validator's heat map of the metal/roughness rules (tolerant).
    Validation(9) = "validation",
    /// The same with the strict dark floor (50 sRGB).
    ValidationStrict(10) = "validation-strict",
}
}

/// View depth (m) as the depth view's grey level: 1 at 0.1 m, 0 at 100 m and beyond,
/// logarithmic between (a decade every third of the range). Twin of `depth_grey` in
/// `shaders/debug_view.wgsl`.
pub fn depth_grey(depth_m: f32) -> f32 {
    (1.0 - (depth_m.max(1e-6) / 0.1).log2() / 1000f32.log2()).clamp(0.0, 1.0)
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    lens: LensUniform,
    atlas_side: f32,
    pad: [f32; 2],
}

/// The debug view pass's bind group.
pub const BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "debug view",
    visibility: wgpu::ShaderStages::FRAGMENT,
    bindings: &[
        ("view", Binding::Uniform),
        ("params", Binding::Uniform),
        ("gbuffer0", Binding::TextureLoad),
        ("gbuffer1", Binding::TextureLoad),
        ("depth_buffer", Binding::TextureLoad),
        ("shadow_atlas", Binding::TextureLoad),
        ("screen_ao", Binding::TextureLoad),
    ],
};

#[allow(non_upper_case_globals)]
impl PassId {
    /// A debug view of one channel, instead of tone mapping.
    pub const DebugView: PassId = PassId::new("debug view");
}

/// The debug view shader variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DebugViewVariant {
    /// The display image's format (sRGB-encoded by the shader unless it is an sRGB format).
    pub format: wgpu::TextureFormat,
    /// The channel shown.
    pub view: DebugView,
    /// The AO pass runs (the occlusion view combines its result).
    pub screen_ao: bool,
}

impl FramePass for DebugViewPass {
    const ID: PassId = PassId::DebugView;
    const READS: &'static [Slot] = &[
        GBUFFER_BASE_COLOR,
        GBUFFER_NORMAL,
        DEPTH,
        SHADOW_ATLAS,
        AMBIENT_OCCLUSION,
    ];
    const WRITES: &'static [Slot] = &[DISPLAY];
    const CONSULTS: &'static [FactId] = &[SCREEN_AO.id];
    type Variant = DebugViewVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        Ok(DebugViewPass::new(gpu))
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<DebugViewVariant> {
        let view = *world.resource::<DebugView>();
        let on = view != DebugView::Off;
        PassDecision::new(
            on,
            if on {
                format!("shows the {} channel", view.name())
            } else {
                "no debug view chosen".into()
            },
            DebugViewVariant {
                format: world.resource::<FrameOutput>().format,
                view,
                screen_ao: plan.fact(&SCREEN_AO).copied().unwrap_or(false),
            },
        )
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_debug_view.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        debug_view_pass.into_configs()
    }
}

/// The debug view pass's pipelines and bindings.
#[derive(Resource)]
pub struct DebugViewPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<DebugViewVariant, wgpu::RenderPipeline>,
    bind_group: CachedGroup,
    params: wgpu::Buffer,
}

impl DebugViewPass {
    /// Creates the bind group layout; pipelines compile per view on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("debug view"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        DebugViewPass {
            layout,
            pipeline_layout,
            pipelines: HashMap::new(),
            bind_group: CachedGroup::default(),
            params: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("debug view params"),
                size: std::mem::size_of::<Params>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    fn pipeline(&mut self, gpu: &Gpu, variant: DebugViewVariant) -> Result<()> {
        if self.pipelines.contains_key(&variant) {
            return Ok(());
        }
        let DebugViewVariant {
            format,
            view,
            screen_ao,
        } = variant;
        let pipeline = fullscreen_variant(
            gpu,
            "debug view",
            &self.pipeline_layout,
            "debug_view.wgsl",
            &[
                ShaderDef::U32("DEBUG_VIEW", view as u32),
                ShaderDef::Bool("ENCODE_SRGB", !format.is_srgb()),
                ShaderDef::Bool("SCREEN_AO", screen_ao),
            ],
            format,
        )?;
        self.pipelines.insert(variant, pipeline);
        Ok(())
    }
}

/// Compiles the chosen view's pipeline, writes its parameters and binds the targets.
#[allow(clippy::too_many_arguments)]
pub fn prepare_debug_view(
    gpu: Res<Gpu>,
    plan: Res<FramePlan>,
    frame: Res<ExtractedFrame>,
    targets: Res<RenderTargets>,
    buffers: Res<SceneBuffers>,
    shadows: Res<ShadowAtlas>,
    mut pass: ResMut<DebugViewPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let Some(&variant) = plan.variant::<DebugViewPass>() else {
        return;
    };
    if let Err(e) = pass.pipeline(&gpu, variant) {
        errors.0.push(e);
        return;
    }
    let (Some(t), Some(camera)) = (targets.current.as_ref(), frame.camera.as_ref()) else {
        return;
    };
    let Some([base_color, normal, depth, ao]) =
        t.views([GBUFFER_BASE_COLOR, GBUFFER_NORMAL, DEPTH, AMBIENT_OCCLUSION])
    else {
        return;
    };
    let params = Params {
        lens: LensUniform::new(camera, camera.depth_of_field.unwrap_or_default(), t.size.1),
        atlas_side: shadows.atlas.texture.width() as f32,
        pad: [0.0; 2],
    };
    gpu.queue
        .write_buffer(&pass.params, 0, bytemuck::bytes_of(&params));
    let DebugViewPass {
        layout,
        bind_group,
        params,
        ..
    } = &mut *pass;
    let resources = vec![
        buffers.view.as_entire_binding(),
        params.as_entire_binding(),
        wgpu::BindingResource::TextureView(base_color),
        wgpu::BindingResource::TextureView(normal),
        wgpu::BindingResource::TextureView(depth),
        wgpu::BindingResource::TextureView(&shadows.atlas.view),
        wgpu::BindingResource::TextureView(ao),
    ];
    if let Err(e) = bind_group.get(&gpu, &BINDINGS, layout, resources) {
        errors.0.push(e);
    }
}

/// Records the debug view into the frame's output view.
pub fn debug_view_pass(
    pass: Res<DebugViewPass>,
    plan: Res<FramePlan>,
    output: Res<FrameOutput>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(target), Some(bind_group), Some(pipeline)) = (
        encoder.as_mut(),
        output.view.as_ref(),
        pass.bind_group.group(),
        plan.variant::<DebugViewPass>()
            .and_then(|v| pass.pipelines.get(v)),
    ) else {
        return;
    };
    draw_fullscreen(
        encoder,
        timer,
        PassId::DebugView.name(),
        &[target],
        pipeline,
        bind_group,
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for &v in DebugView::ALL {
            assert_eq!(DebugView::parse(v.name()), Ok(v));
        }
        let err = DebugView::parse("albedoo").expect_err("unknown");
        assert!(err.contains("shadow-atlas"), "{err}");
    }

    #[test]
    fn depth_grey_spans_three_decades() {
        assert_eq!(depth_grey(0.1), 1.0);
        assert!((depth_grey(1.0) - 2.0 / 3.0).abs() < 1e-6);
        assert!((depth_grey(10.0) - 1.0 / 3.0).abs() < 1e-6);
        assert_eq!(depth_grey(100.0), 0.0);
        assert_eq!(depth_grey(1e9), 0.0);
        assert_eq!(depth_grey(0.0), 1.0);
    }
}

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
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameOutput;
use crate::render::graph::slots::AMBIENT_OCCLUSION;
use crate::render::graph::slots::SHADOW_ATLAS;
use crate::render::graph::slots::{DEPTH, DISPLAY, GBUFFER_BASE_COLOR, GBUFFER_NORMAL};
use crate::render::graph::{FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::indirect::gtao::SCREEN_AO;
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::{Fullscreen, FullscreenPipelines, ShaderVariant};
use crate::render::post::dof::LensUniform;
use crate::render::scene_buffers::SceneBuffers;
use crate::render::shaders::ShaderDef;
use crate::render::shadow::atlas::ShadowAtlas;
use bevy_ecs::prelude::*;

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
pub const BINDINGS: BindGroupSpec = BindGroupSpec::fragment("debug view", declared::DEBUG_VIEW_0);

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

    crate::pass_systems!(prepare_debug_view, debug_view_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        let formats = [
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureFormat::Rgba8UnormSrgb,
        ];
        DebugView::ALL
            .iter()
            .zip(formats.iter().cycle())
            .flat_map(|(&view, &format)| {
                [false, true].map(|screen_ao| DebugViewVariant {
                    format,
                    view,
                    screen_ao,
                })
            })
            .map(|v| ShaderBuild::new("debug_view.wgsl", v.shader_defs(), &[(0, BINDINGS)]))
            .collect()
    }
}

impl ShaderVariant for DebugViewVariant {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        vec![
            ShaderDef::U32("DEBUG_VIEW", self.view as u32),
            ShaderDef::Bool("ENCODE_SRGB", !self.format.is_srgb()),
            ShaderDef::Bool("SCREEN_AO", self.screen_ao),
        ]
    }
}

/// The debug view pass's pipelines and bindings.
#[derive(Resource)]
pub struct DebugViewPass {
    layout: wgpu::BindGroupLayout,
    pipelines: FullscreenPipelines<DebugViewVariant>,
    bind_group: CachedGroup,
    params: wgpu::Buffer,
}

impl DebugViewPass {
    /// Creates the bind group layout; pipelines compile per view on first use.
    pub fn new(gpu: &Gpu) -> Self {
        let layout = BINDINGS.layout(gpu);
        DebugViewPass {
            pipelines: FullscreenPipelines::new(
                gpu,
                Fullscreen::new("debug view", "debug_view.wgsl"),
                &[&layout],
            ),
            layout,
            bind_group: CachedGroup::default(),
            params: gpu.uniform_buffer("debug view params", std::mem::size_of::<Params>() as u64),
        }
    }
}

/// Compiles the chosen view's pipeline, writes its parameters and binds the targets.
#[allow(clippy::too_many_arguments)]
pub fn prepare_debug_view(
    mut p: Prepare<DebugViewPass>,
    frame: Res<ExtractedFrame>,
    buffers: Res<SceneBuffers>,
    shadows: Res<ShadowAtlas>,
) -> Result<()> {
    let Some(&variant) = p.plan.variant::<DebugViewPass>() else {
        return Ok(());
    };
    p.pass
        .pipelines
        .ensure(&p.gpu, variant, &[variant.format])?;
    let (Some(t), Some(camera)) = (p.targets.current.as_ref(), frame.camera.as_ref()) else {
        return Ok(());
    };
    let Some([base_color, normal, depth, ao]) =
        t.views([GBUFFER_BASE_COLOR, GBUFFER_NORMAL, DEPTH, AMBIENT_OCCLUSION])
    else {
        return Ok(());
    };
    let params = Params {
        lens: LensUniform::new(camera, camera.depth_of_field.unwrap_or_default(), t.size.1),
        atlas_side: shadows.atlas.texture.width() as f32,
        pad: [0.0; 2],
    };
    p.gpu
        .queue
        .write_buffer(&p.pass.params, 0, bytemuck::bytes_of(&params));
    let DebugViewPass {
        layout,
        bind_group,
        params,
        ..
    } = &mut *p.pass;
    let resources = vec![
        buffers.view.as_entire_binding(),
        params.as_entire_binding(),
        wgpu::BindingResource::TextureView(base_color),
        wgpu::BindingResource::TextureView(normal),
        wgpu::BindingResource::TextureView(depth),
        wgpu::BindingResource::TextureView(&shadows.atlas.view),
        wgpu::BindingResource::TextureView(ao),
    ];
    bind_group
        .get(&p.gpu, &BINDINGS, layout, resources)
        .map(|_| ())
}

/// Records the debug view into the frame's output view.
pub fn debug_view_pass(mut r: Record<DebugViewPass>, output: Res<FrameOutput>) {
    let pipeline = r
        .plan
        .variant::<DebugViewPass>()
        .and_then(|v| r.pass.pipelines.get(*v, &[v.format]));
    if let Some(view) = output.view.as_ref() {
        let name = PassId::DebugView.name();
        r.encoder
            .fullscreen(name, &[view], pipeline, r.pass.bind_group.group());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        let variant = DebugViewVariant {
            format: wgpu::TextureFormat::Rgba8Unorm,
            view: DebugView::ALL[0],
            screen_ao: false,
        };
        let defs = variant.shader_defs();
        crate::assert_wgsl_twin!(Params, "debug_view.wgsl", &defs, "DebugParams", [
            lens => "focus_m", atlas_side, pad => "pad0",
        ]);
        let lens = std::mem::offset_of!(Params, lens);
        crate::render::post::dof::assert_lens_heads("debug_view.wgsl", &defs, "DebugParams", lens);
    }

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

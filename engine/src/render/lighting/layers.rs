//! The layers pass (`shaders/layers.wgsl`): the layers over opaque surfaces, drawn over the
//! lit frame once the deferred lighting and SSR have lit the base beneath them: a sheen
//! ([`crate::scene::Material::sheen`], glTF's `KHR_materials_sheen`) and, over it, a
//! clearcoat ([`crate::scene::Material::clearcoat`], `KHR_materials_clearcoat`). Before
//! them it lights some bases again: anisotropic ones
//! ([`crate::scene::Material::anisotropy`], `KHR_materials_anisotropy`), those with a
//! tinted specular colour ([`crate::scene::Material::specular_tint`],
//! `KHR_materials_specular`), iridescent ones ([`crate::scene::Material::iridescence`],
//! `KHR_materials_iridescence`) and translucent ones
//! ([`crate::scene::Material::diffuse_transmission`],
//! `KHR_materials_diffuse_transmission`). The G-buffer has no room for a direction, a
//! colour of F0, a film or light from behind, so such a surface is shaded a second time from its material with its own
//! lobe (`RELIT_BASE`), and that light replaces the deferred pass's (alpha 1).
//!
//! Layers are not in the G-buffer. Their surfaces are drawn again, with the G-buffer's
//! textured vertex code, and a fragment is kept where it lies on the opaque depth the
//! G-buffer wrote (`GreaterEqual` with reversed Z, pulled a few depth units towards the
//! camera so that the same triangle always passes). Each fragment is lit by the deferred
//! pass's own code (`surface_light.wgsl`: every light kind, shadows, the environment, the
//! probes, the AO pass's occlusion, the light tiles) as a surface with only the layer's
//! lobe (the coat's GGX lobe, or with `SHEEN_LOBE` the sheen's), and leaves
//! `(L_layer, 1 − w)`, w being what the layer lets through of the light beneath it
//! (`crate::shading::clearcoat::clearcoat_base_weight`, `crate::shading::sheen::sheen_base_weight`); the
//! pipeline composites it as `dst ← src + dst·(1 − α)`. Every sheen is drawn before
//! every coat, so a coat covers its own surface's sheen. The frame's coverage (alpha) is
//! kept.
//!
//! So a scene without a layer pays nothing, and the G-buffer layout is unchanged; the
//! price is a second draw of the layered meshes (docs/src/materials.md#clearcoat). Probe
//! captures do not run this pass: probes see layered surfaces without their layers.
//!
//! Its group 0 is the view and the sheen's albedo table ([`VIEW`]); it binds the lighting
//! pass's groups 1 to 3 as they are and the material maps as group 4, which hold each
//! layer's factors: it runs only on adapters with five bind groups. Compiled per
//! (lighting variant, layer, double-sided, HDR format).

use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, CachedGroup, declared};
use crate::render::device::Gpu;
use crate::render::extract::{Batch, ExtractedFrame};
use crate::render::frame::FrameEncoder;
use crate::render::geometry::gpu_material_maps::{GpuMaterialMaps, unit_defs};
use crate::render::graph::slots::AMBIENT_OCCLUSION;
use crate::render::graph::slots::DEFORMED_VERTICES;
use crate::render::graph::slots::LIGHT_TILES;
use crate::render::graph::slots::SHADOW_ATLAS;
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::graph::{FactId, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::indirect::light_groups::LightGroups;
use crate::render::lighting::forward::{
    ForwardInputs, ForwardPipelines, ForwardShape, MAPS_GROUP, PrepareInputs, draw_batches,
};
use crate::render::lighting::lobe_tables::LobeTables;
use crate::render::lighting::{GROUPS_BY_INDEX, LIGHTING, LightingVariant};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::ShaderVariant;
use crate::render::shaders::ShaderDef;
use crate::render::targets::{self};
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Relit bases, then the sheens and clearcoats of layered surfaces, over the lit
    /// frame.
    pub const Layers: PassId = PassId::new("layers");
}

/// Group 0: the view, the sheen's albedo table and the anisotropic lobe's split-sum
/// table (`shaders/anisotropic_dfg.wgsl`).
pub const VIEW: BindGroupSpec = BindGroupSpec::new(
    "layers",
    wgpu::ShaderStages::VERTEX_FRAGMENT,
    declared::LAYERS_0,
);

/// Which layer a draw adds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layer {
    /// The base again, with its anisotropic, tinted, iridescent or translucent lobes (`fs_relit`,
    /// compiled with `RELIT_BASE`), replacing the deferred pass's light.
    Relit,
    /// The sheen lobe (`fs_sheen`, compiled with `SHEEN_LOBE`).
    Sheen,
    /// The clearcoat's GGX lobe (`fs_coat`).
    Coat,
}

impl Layer {
    /// The order they are drawn in: the base beneath its layers, the coat on top.
    const ORDER: [Layer; 3] = [Layer::Relit, Layer::Sheen, Layer::Coat];
}

/// A layer's blend: colour "over" with premultiplied alpha, dst ← src + dst·(1 − α);
/// the frame's alpha (its coverage) is kept.
const LAYER_BLEND: wgpu::BlendState = wgpu::BlendState {
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

/// Depth units a layer is pulled towards the camera (reversed Z: up), so that a layer's
/// fragment passes `GreaterEqual` against the depth its own triangle wrote even where the
/// two vertex programs round differently.
const LAYER_DEPTH_BIAS: i32 = 4;

impl FramePass for LayersPass {
    const ID: PassId = PassId::Layers;
    const READS: &'static [Slot] = &[
        DEFORMED_VERTICES,
        HDR,
        DEPTH,
        SHADOW_ATLAS,
        LIGHT_TILES,
        AMBIENT_OCCLUSION,
    ];
    const WRITES: &'static [Slot] = &[HDR];
    const CONSULTS: &'static [FactId] = &[LIGHTING.id];
    type Variant = Option<LightingVariant>;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        if !world.contains_resource::<LightGroups>() {
            world.insert_resource(LightGroups::new(gpu));
        }
        let groups = world.resource::<LightGroups>();
        let maps = world.resource::<GpuMaterialMaps>();
        Ok(LayersPass::new(gpu, &groups.layouts, maps))
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<Option<LightingVariant>> {
        let frame = world.resource::<ExtractedFrame>();
        let gpu = world.resource::<Gpu>();
        let counts = [
            (frame.relit_batches().count(), "relit base"),
            (frame.sheened_batches().count(), "sheen"),
            (frame.coated_batches().count(), "clearcoat"),
        ];
        // "2 sheen and 1 clearcoat layer(s)", "1 relit base, 1 sheen and 1 clearcoat
        // layer(s)", "1 clearcoat layer(s)".
        let named: Vec<String> = counts
            .iter()
            .filter(|(n, _)| *n > 0)
            .map(|(n, what)| format!("{n} {what}"))
            .collect();
        let layers = match named.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
            None => String::new(),
        };
        let lighting = plan.fact(&LIGHTING).copied();
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
        let (runs, reason) = if named.is_empty() {
            (
                false,
                "no surface with anisotropy, a specular tint, a film, a diffuse transmission, a sheen or a clearcoat in view"
                    .to_string(),
            )
        } else if lighting.is_none() {
            (false, "the lighting pass does not run".into())
        } else if groups <= MAPS_GROUP {
            (
                false,
                format!(
                    "{layers} layer(s) not drawn: the adapter has {groups} bind groups, the pass needs 5"
                ),
            )
        } else if !blendable {
            (
                false,
                format!(
                    "{layers} layer(s) not drawn: this adapter cannot blend the f32 HDR target (the f16 target can)"
                ),
            )
        } else {
            let units = world.resource::<GpuMaterialMaps>().units;
            (
                true,
                format!(
                    "{layers} layer(s) over the lit base{}",
                    crate::render::geometry::gpu_material_maps::unsampled_note(frame, units)
                ),
            )
        };
        // Layers are drawn over the lit base without the lighting pass's group 0: their
        // lights filter the shadow map themselves.
        let lighting = lighting.map(|l| LightingVariant {
            shadow_mask: 0,
            shadow_mask_lights: 0,
            half_volume: false,
            ..l
        });
        PassDecision::new(runs, reason, lighting.filter(|_| runs))
    }

    crate::pass_systems!(prepare_layers, layers_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        let mut builds = Vec::new();
        for (units, maps) in [
            (true, crate::render::geometry::gpu_material_maps::BINDINGS),
            (
                false,
                crate::render::geometry::gpu_material_maps::CORE_BINDINGS,
            ),
        ] {
            for layer in Layer::ORDER {
                let shader = LayerShader {
                    lighting: LightingVariant::everything(),
                    layer,
                    units,
                };
                let [_, lights, environment, probes] = GROUPS_BY_INDEX;
                builds.push(ShaderBuild::new(
                    "layers.wgsl",
                    shader.shader_defs(),
                    &[(0, VIEW), lights, environment, probes, (MAPS_GROUP, maps)],
                ));
            }
        }
        builds
    }
}

/// The layers pass's pipelines, its view group and its lobe tables.
#[derive(Resource)]
pub struct LayersPass {
    pipelines: ForwardPipelines<LayerShader>,
    /// The sheen's albedo table and the anisotropic lobe's split-sum table.
    tables: LobeTables,
    /// The view group.
    view_group: CachedGroup,
    /// Whether the maps' layout binds the extension units ([`GpuMaterialMaps::units`]).
    units: bool,
}

impl LayersPass {
    /// The layouts: the view, the lighting pass's groups 1 to 3 (`lighting`), and the
    /// material maps' (`maps`); and the lobe tables, filled on first use.
    pub fn new(
        gpu: &Gpu,
        lighting: &[wgpu::BindGroupLayout; 3],
        maps: &GpuMaterialMaps,
    ) -> LayersPass {
        LayersPass {
            pipelines: ForwardPipelines::new(gpu, "layers", &VIEW, lighting, &maps.layout),
            tables: LobeTables::new(gpu),
            view_group: CachedGroup::default(),
            units: maps.units,
        }
    }
}

/// The shader of one layer: the lighting pass's variant, the layer, and whether the maps'
/// layout binds the extension units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LayerShader {
    /// The lights, shadows and indirect light, as the lighting pass shades them.
    pub lighting: LightingVariant,
    /// The layer drawn.
    pub layer: Layer,
    /// The maps' layout binds the extension units ([`GpuMaterialMaps::units`]).
    pub units: bool,
}

/// The lighting pass's defs, with `SHEEN_LOBE` for the sheen and `RELIT_BASE` for the
/// relit base, and the maps' group (with the extension units where `units`).
impl ShaderVariant for LayerShader {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        let layer = self.layer;
        let mut defs: Vec<ShaderDef> = (self.lighting.shader_defs().into_iter())
            .map(|d| match d {
                ShaderDef::Bool("SHEEN_LOBE", _) => {
                    ShaderDef::Bool("SHEEN_LOBE", layer == Layer::Sheen)
                }
                ShaderDef::Bool("RELIT_BASE", _) => {
                    ShaderDef::Bool("RELIT_BASE", layer == Layer::Relit)
                }
                other => other,
            })
            .collect();
        defs.extend(unit_defs(MAPS_GROUP, self.units));
        defs
    }
}

/// The batches in view that carry `layer`.
fn layer_batches(frame: &ExtractedFrame, layer: Layer) -> impl Iterator<Item = &Batch> {
    frame.drawn_batches().filter(move |b| match layer {
        Layer::Relit => b.relit,
        Layer::Sheen => b.sheened,
        Layer::Coat => b.coated,
    })
}

/// The pipeline of `layer` into `format`: "over" with what the layer takes from the light
/// beneath it as alpha (all of it for a relit base), on the opaque depth.
fn layer_shape(layer: Layer, format: wgpu::TextureFormat) -> ForwardShape {
    ForwardShape {
        entry: match layer {
            Layer::Relit => "fs_relit",
            Layer::Sheen => "fs_sheen",
            Layer::Coat => "fs_coat",
        },
        targets: vec![Some(wgpu::ColorTargetState {
            format,
            blend: Some(LAYER_BLEND),
            write_mask: wgpu::ColorWrites::ALL,
        })],
        depth: wgpu::DepthStencilState {
            format: targets::DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            // Reversed Z: on the opaque surface or in front of it.
            depth_compare: Some(wgpu::CompareFunction::GreaterEqual),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState {
                constant: LAYER_DEPTH_BIAS,
                slope_scale: 0.0,
                clamp: 0.0,
            },
        },
    }
}

/// Compiles the pipelines this frame's layered batches need and rebuilds the view group
/// when the scene buffers were recreated.
pub fn prepare_layers(mut p: Prepare<LayersPass>, inputs: PrepareInputs) -> Result<()> {
    let PrepareInputs {
        frame,
        buffers,
        targets,
    } = inputs;
    let (Some(Some(variant)), Some(t)) = (
        p.plan.variant::<LayersPass>().copied(),
        targets.current.as_ref(),
    ) else {
        return Ok(());
    };
    let units = p.pass.units;
    // The sheen's and the anisotropic lobe's tables, for a frame that draws them.
    p.pass.tables.write_for(&p.gpu, &frame);
    for layer in Layer::ORDER {
        (p.pass.pipelines.ensure(
            &p.gpu,
            (
                LayerShader {
                    lighting: variant,
                    layer,
                    units,
                },
                t.hdr_format,
            ),
            layer_batches(&frame, layer),
            "layers.wgsl",
            &|format| layer_shape(layer, format),
        ))?;
    }
    let LayersPass {
        pipelines,
        tables,
        view_group,
        ..
    } = &mut *p.pass;
    let resources = vec![
        buffers.view.as_entire_binding(),
        tables.sheen_albedo.as_entire_binding(),
        tables.anisotropic_dfg.as_entire_binding(),
    ];
    view_group
        .get(&p.gpu, &VIEW, &pipelines.view_layout, resources)
        .map(|_| ())
}

/// Records the relit bases, then the layered batches' sheens, then their coats, over
/// the HDR target.
pub fn layers_pass(mut r: Record<LayersPass>, inputs: ForwardInputs) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(t), Some(Some(variant)), Some(view_group), Some(shared)) = (
        encoder.as_mut(),
        inputs.targets.current.as_ref(),
        r.plan.variant::<LayersPass>().copied(),
        r.pass.view_group.group(),
        inputs.lighting.groups(),
    ) else {
        return;
    };
    let Some([hdr, depth]) = t.views([HDR, DEPTH]) else {
        return;
    };
    let scope = timer.begin_pass(PassId::Layers);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("layers"),
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
        for layer in Layer::ORDER {
            draw_batches(
                &mut rp,
                &inputs,
                (view_group, shared),
                MAPS_GROUP,
                layer_batches(&inputs.frame, layer),
                |batch| {
                    let shader = LayerShader {
                        lighting: variant,
                        layer,
                        units: r.pass.units,
                    };
                    r.pass
                        .pipelines
                        .get(shader, batch.double_sided, t.hdr_format)
                },
            );
        }
    }
    timer.end_pass(scope);
}

//! The transparent pass (`shaders/transparent.wgsl`): alpha-blended surfaces
//! ([`crate::scene::Material::blend`]) and transmissive ones
//! ([`crate::scene::Material::transmission`]), drawn after the opaque frame is lit, one
//! primitive at a time, farthest first (the order of
//! [`ExtractedFrame::transparent_batches`]); or, with `--transparency weighted`, in any
//! order into the targets of weighted blended OIT, resolved over the frame once
//! ([`weighted`]). A transmissive surface samples the opaque frame's mip chain
//! ([`transmission_source`]) along its refracted ray (docs/src/materials.md#transmission).
//!
//! Each fragment is lit by the deferred pass's own code (`surface_light.wgsl`: every light
//! kind, shadows, the environment, the irradiance volume and the reflection probes), from
//! its material's maps instead of the G-buffer, and composited over the HDR target with
//! premultiplied alpha: `dst ← src + dst·(1 − α_src)`, Porter & Duff's "over" (1984). The
//! alpha channel, the frame's coverage, composites the same way. The pass depth-tests
//! against the opaque depth and writes no depth.
//!
//! Its group 0 is the view and the opaque frame's chain ([`VIEW`]). It binds the lighting
//! pass's groups 1 to 3 as they are, and the material maps as group 4
//! (`gpu_material_maps::group_def`): it runs only on adapters with five bind groups.
//! Compiled per (lighting variant, double-sided, HDR format); the variant is the lighting
//! pass's without its screen-space inputs: the AO pass's occlusion and the light tiles
//! belong to the opaque surface behind the fragment.

use crate::error::Result;
use crate::quality::Transparency;
use crate::render::bindings::CachedGroup;
use crate::render::device::Gpu;
use crate::render::extract::{Batch, ExtractedFrame};
use crate::render::frame::FrameEncoder;
use crate::render::fullscreen_step::FullscreenStep;
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
use crate::render::pipelines::{color_attachment, draw_fullscreen_with};
use crate::render::shaders::ShaderDef;
use crate::render::targets::{self};
use bevy_ecs::prelude::*;
use transmission_source::TRANSMISSION_SOURCE;
use weighted::{OIT_ACCUM, OIT_REVEAL, OVER};

pub mod transmission_source;
pub mod weighted;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Alpha-blended surfaces over the lit frame.
    pub const Transparent: PassId = PassId::new("transparent");
}

/// Group 0: the view, the opaque frame's mip chain, the anisotropic lobe's split-sum
/// table (binding 2, as in the layers pass: `shaders/anisotropic_dfg.wgsl`), the
/// chain's sampler and the sheen's albedo table (`shaders/sheen_table.wgsl`).
pub const VIEW: crate::render::bindings::BindGroupSpec =
    crate::render::bindings::BindGroupSpec::new(
        "transparent",
        wgpu::ShaderStages::VERTEX_FRAGMENT,
        crate::render::bindings::declared::TRANSPARENT_0,
    );

/// What a blended batch draws besides the lit base, from its maps entry: each is a
/// shader variant of the pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BlendedLobes {
    /// A lobe of its own (an anisotropy, a specular tint, an iridescent film or a diffuse
    /// transmission): compiled with `RELIT_BASE`, set by `shaders/relit_base.wgsl`.
    pub relit: bool,
    /// A sheen over the base, blended or transmissive (`shaders/blended_layers.wgsl`,
    /// `BLENDED_SHEEN`).
    pub sheen: bool,
    /// A clearcoat over the base and its sheen (`BLENDED_COAT`).
    pub coat: bool,
}

impl BlendedLobes {
    /// Every combination, in the order their pipelines are compiled.
    pub fn all() -> impl Iterator<Item = BlendedLobes> {
        (0..8u8).map(|k| BlendedLobes {
            relit: k & 1 != 0,
            sheen: k & 2 != 0,
            coat: k & 4 != 0,
        })
    }

    /// A sheen or a clearcoat: the variant lights layers over the base.
    pub fn layered(self) -> bool {
        self.sheen || self.coat
    }

    /// The lobes of `batch` in `frame` (none without a maps entry).
    fn of(frame: &ExtractedFrame, batch: &Batch) -> BlendedLobes {
        let entry = batch.maps.and_then(|i| frame.material_maps.get(i as usize));
        BlendedLobes {
            relit: entry.is_some_and(|m| {
                m.anisotropy.is_some()
                    || m.specular_tint.is_some()
                    || m.iridescence.is_some()
                    || m.diffuse_transmission.is_some()
            }),
            sheen: entry.is_some_and(|m| m.sheen.is_some()),
            coat: entry.is_some_and(|m| m.clearcoat.is_some()),
        }
    }
}

/// The pass's shader variant: the lighting pass's variant without its screen-space
/// inputs, and the compositing mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TransparentVariant {
    /// The lights and indirect terms compiled in.
    pub lighting: LightingVariant,
    /// Weighted blended OIT instead of sorted "over".
    pub weighted: bool,
    /// A transmissive surface is in view: the refraction code is compiled in.
    pub transmission: bool,
}

impl TransparentVariant {
    /// The variant for a frame whose lighting pass compiles `lighting`, compositing as
    /// `transparency` says, with refraction where `transmission`.
    pub fn of(
        lighting: LightingVariant,
        transparency: Transparency,
        transmission: bool,
    ) -> TransparentVariant {
        TransparentVariant {
            lighting: LightingVariant {
                screen_ao: false,
                ao_multi_bounce: false,
                light_culling: false,
                shadow_mask: 0,
                shadow_mask_lights: 0,
                half_volume: false,
                ..lighting
            },
            weighted: transparency == Transparency::WeightedBlended,
            transmission,
        }
    }
}

impl FramePass for TransparentPass {
    const ID: PassId = PassId::Transparent;
    const READS: &'static [Slot] = &[
        DEFORMED_VERTICES,
        HDR,
        DEPTH,
        SHADOW_ATLAS,
        LIGHT_TILES,
        AMBIENT_OCCLUSION,
        TRANSMISSION_SOURCE,
    ];
    const WRITES: &'static [Slot] = &[HDR];
    const OPTIONAL_WRITES: &'static [Slot] = &[OIT_ACCUM, OIT_REVEAL];
    const CONSULTS: &'static [FactId] = &[LIGHTING.id];
    type Variant = Option<TransparentVariant>;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        if !world.contains_resource::<LightGroups>() {
            world.insert_resource(LightGroups::new(gpu));
        }
        let groups = world.resource::<LightGroups>();
        let maps = world.resource::<GpuMaterialMaps>();
        Ok(TransparentPass::new(gpu, &groups.layouts, maps))
    }

    fn decide(world: &World, plan: &FramePlan) -> PassDecision<Option<TransparentVariant>> {
        let frame = world.resource::<ExtractedFrame>();
        let gpu = world.resource::<Gpu>();
        let transmitting = frame
            .transparent_batches()
            .filter(|b| b.transmissive)
            .count();
        let transmissive = transmitting > 0;
        // "3 blended", or "2 blended and 1 transmissive".
        let count = frame.transparent_batches().count();
        let blended = match (count - transmitting, transmitting) {
            (b, 0) => format!("{b} blended"),
            (0, t) => format!("{t} transmissive"),
            (b, t) => format!("{b} blended and {t} transmissive"),
        };
        // "3 blended surface(s) (1 with its own lobe, 2 with a sheen or a clearcoat)".
        let lobes: Vec<BlendedLobes> = frame
            .transparent_batches()
            .map(|b| BlendedLobes::of(frame, b))
            .collect();
        let own = lobes.iter().filter(|l| l.relit).count();
        let layered = lobes.iter().filter(|l| l.layered()).count();
        let drawn_with: Vec<String> = [
            (own, "with its own lobe"),
            (layered, "with a sheen or a clearcoat"),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect();
        let surfaces = match drawn_with.is_empty() {
            true => format!("{blended} surface(s)"),
            false => format!("{blended} surface(s) ({})", drawn_with.join(", ")),
        };
        let lighting = plan.fact(&LIGHTING).copied();
        let quality = world.resource::<crate::quality::Quality>();
        let hdr = quality.hdr_precision.format();
        let mode = quality.transparency;
        let blendable = hdr != wgpu::TextureFormat::Rgba32Float
            || gpu
                .device
                .features()
                .contains(wgpu::Features::FLOAT32_BLENDABLE);
        let (runs, reason) = if count == 0 {
            (
                false,
                "no blended or transmissive surface in view".to_string(),
            )
        } else if lighting.is_none() {
            (false, "the lighting pass does not run".into())
        } else if gpu.device.limits().max_bind_groups <= MAPS_GROUP {
            (
                false,
                format!(
                    "{surfaces} not drawn: the adapter has {} bind groups, the pass needs 5",
                    gpu.device.limits().max_bind_groups
                ),
            )
        } else if !blendable {
            (
                false,
                format!(
                    "{surfaces} not drawn: this adapter cannot blend the f32 HDR target (the f16 target can)"
                ),
            )
        } else {
            let units = world.resource::<GpuMaterialMaps>().units;
            let note = crate::render::geometry::gpu_material_maps::unsampled_note(frame, units);
            (
                true,
                match mode {
                    Transparency::Sorted => {
                        format!("{surfaces}, back to front, premultiplied alpha{note}")
                    }
                    Transparency::WeightedBlended => {
                        format!("{surfaces}, weighted blended OIT (any order, one resolve){note}")
                    }
                },
            )
        };
        let variant = lighting
            .filter(|_| runs)
            .map(|l| TransparentVariant::of(l, mode, transmissive));
        let weighted = variant.is_some_and(|v| v.weighted);
        PassDecision::new(runs, reason, variant)
            .writing(OIT_ACCUM, weighted)
            .writing(OIT_REVEAL, weighted)
    }

    crate::pass_systems!(prepare_transparent, transparent_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        let mut builds = vec![ShaderBuild::new(
            "transparent_resolve.wgsl",
            Vec::new(),
            &[(0, weighted::RESOLVE_BINDINGS)],
        )];
        for (units, maps) in [
            (true, crate::render::geometry::gpu_material_maps::BINDINGS),
            (
                false,
                crate::render::geometry::gpu_material_maps::CORE_BINDINGS,
            ),
        ] {
            for lobes in BlendedLobes::all() {
                let shader = TransparentShader {
                    variant: TransparentVariant::of(
                        LightingVariant::everything(),
                        crate::quality::Transparency::WeightedBlended,
                        true,
                    ),
                    lobes,
                    units,
                };
                let [_, lights, environment, probes] = GROUPS_BY_INDEX;
                builds.push(ShaderBuild::new(
                    "transparent.wgsl",
                    shader.shader_defs(),
                    &[(0, VIEW), lights, environment, probes, (MAPS_GROUP, maps)],
                ));
            }
        }
        builds
    }
}

/// The transparent pass's pipelines (per variant and the batch's [`BlendedLobes`]), its
/// view group and its lobe tables.
#[derive(Resource)]
pub struct TransparentPass {
    pipelines: ForwardPipelines<TransparentShader>,
    /// The view group.
    view_group: CachedGroup,
    /// 1 × 1 black, bound in the chain's place when no surface transmits.
    no_frame: wgpu::TextureView,
    /// Trilinear and clamped: what the transmission source is sampled with.
    sampler: wgpu::Sampler,
    resolve: FullscreenStep,
    /// Whether the maps' layout binds the extension units ([`GpuMaterialMaps::units`]).
    units: bool,
    /// The anisotropic lobe's split-sum table and the sheen's albedo table, for blended
    /// surfaces with those lobes.
    tables: LobeTables,
}

impl TransparentPass {
    /// The layouts: the view, the lighting pass's groups 1 to 3 (`lighting`), and the
    /// material maps' (`maps`).
    pub fn new(
        gpu: &Gpu,
        lighting: &[wgpu::BindGroupLayout; 3],
        maps: &GpuMaterialMaps,
    ) -> TransparentPass {
        let no_frame = gpu
            .device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("no transmission source"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: transmission_source::FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&wgpu::TextureViewDescriptor::default());
        TransparentPass {
            pipelines: ForwardPipelines::new(gpu, "transparent", &VIEW, lighting, &maps.layout),
            view_group: CachedGroup::default(),
            no_frame,
            sampler: transmission_source::sampler(gpu),
            resolve: weighted::resolve_step(gpu),
            units: maps.units,
            tables: LobeTables::new(gpu),
        }
    }
}

/// The shader of one kind of transparent batch: the pass's variant, the lobes of the
/// batches drawn, and whether the maps' layout binds the extension units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TransparentShader {
    /// The pass's variant.
    pub variant: TransparentVariant,
    /// The lobes of the batches this shader draws.
    pub lobes: BlendedLobes,
    /// The maps' layout binds the extension units ([`GpuMaterialMaps::units`]).
    pub units: bool,
}

/// The lighting pass's defs with `RELIT_BASE` where `lobes.relit`; with layers,
/// `RELIT_BASE` and `SHEEN_LOBE` as switches that the layers turn and only the layers'
/// code the batches have (`BLENDED_SHEEN`, `BLENDED_COAT`), else without the layers'
/// code; the maps' group, with the extension units where `units`; and `TRANSMISSION`.
impl ShaderVariant for TransparentShader {
    fn shader_defs(&self) -> Vec<ShaderDef> {
        let TransparentShader {
            variant,
            lobes,
            units,
        } = *self;
        let switch = |name, on| match lobes.layered() {
            true => ShaderDef::Switch(name, on),
            false => ShaderDef::Bool(name, on),
        };
        let mut defs: Vec<ShaderDef> = (variant.lighting.shader_defs().into_iter())
            .map(|d| match d {
                ShaderDef::Bool("RELIT_BASE", _) => switch("RELIT_BASE", lobes.relit),
                ShaderDef::Bool("SHEEN_LOBE", _) => switch("SHEEN_LOBE", false),
                other => other,
            })
            .collect();
        if lobes.layered() {
            defs.push(ShaderDef::Bool("BLENDED_SHEEN", lobes.sheen));
            defs.push(ShaderDef::Bool("BLENDED_COAT", lobes.coat));
        } else {
            defs.push(ShaderDef::Import("blended_layers", "blended_layers_none"));
        }
        defs.extend(unit_defs(MAPS_GROUP, units));
        defs.push(ShaderDef::Bool("TRANSMISSION", variant.transmission));
        defs
    }
}

/// The transparent pass's pipeline of `variant` into `format`. Sorted: premultiplied
/// "over" into the HDR target; weighted: the sums. Either in front of the opaque surface.
fn transparent_shape(variant: TransparentVariant, format: wgpu::TextureFormat) -> ForwardShape {
    ForwardShape {
        entry: if variant.weighted {
            "fs_weighted"
        } else {
            "fs_main"
        },
        targets: if variant.weighted {
            weighted::accumulate_targets().to_vec()
        } else {
            vec![Some(wgpu::ColorTargetState {
                format,
                blend: Some(OVER),
                write_mask: wgpu::ColorWrites::ALL,
            })]
        },
        depth: wgpu::DepthStencilState {
            format: targets::DEPTH_FORMAT,
            depth_write_enabled: Some(false),
            // Reversed Z: in front of the opaque surface.
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        },
    }
}

/// Compiles the pipelines this frame's blended and transmissive batches need and rebuilds the view group
/// when the scene buffers were recreated.
pub fn prepare_transparent(mut p: Prepare<TransparentPass>, inputs: PrepareInputs) -> Result<()> {
    let PrepareInputs {
        frame,
        buffers,
        targets,
    } = inputs;
    let (Some(Some(variant)), Some(t)) = (
        p.plan.variant::<TransparentPass>().copied(),
        targets.current.as_ref(),
    ) else {
        return Ok(());
    };
    let units = p.pass.units;
    for lobes in BlendedLobes::all() {
        (p.pass.pipelines.ensure(
            &p.gpu,
            (
                TransparentShader {
                    variant,
                    lobes,
                    units,
                },
                t.hdr_format,
            ),
            frame
                .transparent_batches()
                .filter(|b| BlendedLobes::of(&frame, b) == lobes),
            "transparent.wgsl",
            &|format| transparent_shape(variant, format),
        ))?;
    }
    p.pass.tables.write_for(&p.gpu, &frame);
    if variant.weighted {
        let Some([accum, reveal]) = t.views([OIT_ACCUM, OIT_REVEAL]) else {
            return Ok(());
        };
        let pass = &mut *p.pass;
        (pass
            .resolve
            .ensure(&p.gpu, (), &[t.hdr_format])
            .and_then(|()| {
                pass.resolve.bind(
                    &p.gpu,
                    vec![
                        wgpu::BindingResource::TextureView(accum),
                        wgpu::BindingResource::TextureView(reveal),
                    ],
                )
            }))?;
    }
    let TransparentPass {
        pipelines,
        view_group,
        no_frame,
        sampler,
        tables,
        ..
    } = &mut *p.pass;
    let chain = t.view(TRANSMISSION_SOURCE).filter(|_| variant.transmission);
    let resources = vec![
        buffers.view.as_entire_binding(),
        wgpu::BindingResource::TextureView(chain.unwrap_or(no_frame)),
        tables.anisotropic_dfg.as_entire_binding(),
        wgpu::BindingResource::Sampler(sampler),
        tables.sheen_albedo.as_entire_binding(),
    ];
    view_group
        .get(&p.gpu, &VIEW, &pipelines.view_layout, resources)
        .map(|_| ())
}

/// Records the blended batches, farthest first, over the HDR target.
pub fn transparent_pass(mut r: Record<TransparentPass>, inputs: ForwardInputs) {
    let targets = &inputs.targets;
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let (Some(encoder), Some(t), Some(Some(variant)), Some(view_group), Some(shared)) = (
        encoder.as_mut(),
        targets.current.as_ref(),
        r.plan.variant::<TransparentPass>().copied(),
        r.pass.view_group.group(),
        inputs.lighting.groups(),
    ) else {
        return;
    };
    let Some([hdr, depth]) = t.views([HDR, DEPTH]) else {
        return;
    };
    // Weighted: the sums' targets, the resolve's group and its pipeline.
    let oit = if variant.weighted {
        match (
            t.views([OIT_ACCUM, OIT_REVEAL]),
            r.pass.resolve.group(),
            r.pass.resolve.pipeline((), &[t.hdr_format]),
        ) {
            (Some(views), Some(group), Some(pipeline)) => Some((views, group, pipeline)),
            _ => return,
        }
    } else {
        None
    };
    let attachment = |view, load| Some(color_attachment(view, load));
    // Sorted: straight over the HDR target; weighted: into the sums, cleared to 0 and 1.
    let color_attachments = match oit {
        Some(([accum, reveal], _, _)) => vec![
            attachment(accum, wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)),
            attachment(reveal, wgpu::LoadOp::Clear(wgpu::Color::WHITE)),
        ],
        None => vec![attachment(hdr, wgpu::LoadOp::Load)],
    };
    let scope = timer.begin_pass(PassId::Transparent);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("transparent"),
            color_attachments: &color_attachments,
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
            inputs.frame.transparent_batches(),
            |batch| {
                let shader = TransparentShader {
                    variant,
                    lobes: BlendedLobes::of(&inputs.frame, batch),
                    units: r.pass.units,
                };
                r.pass
                    .pipelines
                    .get(shader, batch.double_sided, t.hdr_format)
            },
        );
    }
    timer.end_pass(scope);
    if let Some((_, group, pipeline)) = oit {
        draw_fullscreen_with(
            encoder,
            timer,
            "transparent resolve",
            &[hdr],
            pipeline,
            group,
            wgpu::LoadOp::Load,
        );
    }
}

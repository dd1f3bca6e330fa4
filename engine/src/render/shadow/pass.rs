//! The shadow pass: packs the frame's shadow views into one depth atlas and draws each
//! view's casters into its rectangle, all in one render pass. Per view only the depth draws
//! repeat: the casters are culled on the CPU against the view's frustum, and each view
//! selects its matrix with a dynamic offset (no per-view pipeline, pass or target).
//! Casters whose material masks by alpha (glTF `alphaMode: MASK`) draw with a second
//! pipeline that samples their base colour and drops the texels the G-buffer drops, so
//! their shadows have the mask's shape; opaque casters write depth only.

use super::atlas::{AtlasRect, ShadowAtlas, UNIFORM_SHADOW_VIEWS, pack};
use crate::error::Result;
use crate::quality::knob::Value;
use crate::quality::knobs::{SHADOW_CACHE, SHADOWS};
use crate::render::bindings::{BindGroupSpec, Binding, CachedGroup};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::extract::shadow_views::{ShadowView, frustum_planes, sphere_in_frustum};
use crate::render::frame::FrameEncoder;
use crate::render::geometry::deform_pass::DeformedVertices;
use crate::render::geometry::gpu_material_maps::GpuMaterialMaps;
use crate::render::gpu_types::{GpuCasterView, GpuShadowView};
use crate::render::graph::slots::DEFORMED_VERTICES;
use crate::render::graph::slots::SHADOW_ATLAS;
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot};
use crate::render::pass_params::Prepare;
use crate::render::pipelines::{create_module, pipeline_layout};
use crate::render::scene_buffers::{GrowableBuffer, SceneBuffers};
use crate::scene::{MeshHandle, TextureSlot, Vertex};
use bevy_ecs::prelude::*;

pub use super::atlas::ATLAS_FORMAT;

/// Largest atlas side; views are halved until they fit (README, "Shadows").
pub const MAX_ATLAS_SIDE: u32 = 8192;

/// One draw of a view: consecutive visible casters of one mesh and one mask.
struct CasterDraw {
    mesh: MeshHandle,
    /// The deformed instance it draws (index into the frame's deformed instances).
    deformed: Option<u32>,
    /// Index into [`ExtractedFrame::material_maps`] of the casters' alpha mask.
    mask: Option<u32>,
    /// First index into the visible list.
    first: u32,
    count: u32,
}

struct ViewDraws {
    rect: AtlasRect,
    draws: Vec<CasterDraw>,
}

/// One visible caster, as the shadow pass's instance attributes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct CasterInstance {
    /// World from local, column-major.
    world_from_local: [[f32; 4]; 4],
    /// The base colour factor's alpha (x), which the mask reads, and 1 for a blended
    /// caster (y), whose texels are kept in an ordered dither of density α; z and w are 0.
    coverage: [f32; 4],
}

/// What decides a masked or blended caster's shadow besides its mesh and transform: the
/// base colour texture, the cutoff's bits and the coverage's bits (factor alpha, blend).
type MaskKey = (Option<TextureSlot>, u32, [u32; 2]);

/// A caster as the atlas cache compares it: its mesh, transform, mask and, when it is
/// deformed, its pose's hash.
type CasterKey = (MeshHandle, [[f32; 4]; 4], Option<MaskKey>, Option<u64>);

/// The shadow pass's pipelines and per-view draws; the atlas it draws is the
/// [`ShadowAtlas`] resource.
#[derive(Resource)]
pub struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    /// Casters with an alpha mask: samples their base colour (group 1, the material maps).
    masked: wgpu::RenderPipeline,
    caster_layout: wgpu::BindGroupLayout,
    caster_views: wgpu::Buffer,
    visible: GrowableBuffer,
    caster_bind_group: CachedGroup,
    views: Vec<ViewDraws>,
    /// What the atlas holds since the pass last drew it (a frame's or a probe capture's),
    /// `None` after it was recreated: a frame whose views and casters are the same reuses
    /// it instead of drawing it again.
    holds: Option<AtlasContents>,
}

impl ShadowPass {
    /// Forgets what the atlas holds, so that the next frame draws it: for a frame whose
    /// commands were recorded but never submitted (an error after the shadow pass).
    pub fn forget(&mut self) {
        self.holds = None;
    }

    /// Caster draws of this frame's views, summed: an instance counts once per view whose
    /// frustum its bounding sphere touches.
    pub fn caster_draws(&self) -> u32 {
        self.views
            .iter()
            .flat_map(|v| v.draws.iter().map(|d| d.count))
            .sum()
    }
}

/// What the shadow atlas was drawn from: every shadow view, and every caster's mesh,
/// transform and mask (in a canonical order). Meshes and textures are immutable once
/// added, so equal contents draw an equal atlas.
#[derive(Clone, Debug, PartialEq)]
struct AtlasContents {
    views: Vec<ShadowView>,
    casters: Vec<CasterKey>,
}

impl AtlasContents {
    fn caster(frame: &ExtractedFrame, c: &crate::render::extract::Caster) -> CasterKey {
        let instance = caster_instance(frame, c);
        let mask = c.mask.map(|m| {
            let maps = frame.material_maps.get(m as usize).map(|entry| &entry.maps);
            (
                maps.and_then(|maps| maps.base_color),
                maps.and_then(|maps| maps.alpha_cutoff)
                    .unwrap_or(0.0)
                    .to_bits(),
                [
                    instance.coverage[0].to_bits(),
                    instance.coverage[1].to_bits(),
                ],
            )
        });
        let pose = c
            .deformed
            .and_then(|d| frame.deformed.instances.get(d as usize))
            .map(|d| d.pose);
        (c.mesh, instance.world_from_local, mask, pose)
    }

    /// `frame`'s casters in a canonical order (by mesh, then by the transform's bits).
    /// Depth-only draws give the same atlas in any order, and the order of
    /// [`ExtractedFrame::casters`] follows the camera's frustum (instances in view first),
    /// which a probe capture's differs from.
    fn casters_of(frame: &ExtractedFrame) -> Vec<CasterKey> {
        let mut casters: Vec<_> = frame
            .casters
            .iter()
            .map(|c| Self::caster(frame, c))
            .collect();
        casters
            .sort_by_key(|(mesh, m, _, pose)| (*mesh, m.map(|row| row.map(f32::to_bits)), *pose));
        casters
    }

    /// The contents `frame` draws.
    fn of(frame: &ExtractedFrame) -> AtlasContents {
        AtlasContents {
            views: frame.shadow_views.clone(),
            casters: Self::casters_of(frame),
        }
    }

    /// Whether `frame` would draw exactly these contents.
    fn matches(&self, frame: &ExtractedFrame) -> bool {
        self.views == frame.shadow_views
            && self.casters.len() == frame.casters.len()
            && self.casters == Self::casters_of(frame)
    }
}

/// Caster `c`'s instance attributes (zero for an index out of range).
fn caster_instance(frame: &ExtractedFrame, c: &crate::render::extract::Caster) -> CasterInstance {
    frame.instances.get(c.instance as usize).map_or(
        <CasterInstance as bytemuck::Zeroable>::zeroed(),
        |i| CasterInstance {
            world_from_local: i.world_from_local,
            coverage: [i.base_color[3], if c.blend { 1.0 } else { 0.0 }, 0.0, 0.0],
        },
    )
}

/// The shadow pass's bind group: each view's matrix at a dynamic offset.
pub const CASTERS: BindGroupSpec = BindGroupSpec {
    label: "shadow casters",
    visibility: wgpu::ShaderStages::VERTEX,
    bindings: &[("caster_view", Binding::DynamicUniform(64))],
};

#[allow(non_upper_case_globals)]
impl PassId {
    /// Draws shadow casters into the shadow atlas.
    pub const Shadow: PassId = PassId::new("shadow");
}

/// The shadow pass compiles one pipeline for every frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShadowVariant;

impl FramePass for ShadowPass {
    const ID: PassId = PassId::Shadow;
    const CAPTURE: bool = true;
    const READS: &'static [Slot] = &[DEFORMED_VERTICES];
    const WRITES: &'static [Slot] = &[SHADOW_ATLAS];
    type Variant = ShadowVariant;

    fn create(world: &mut World, gpu: &Gpu) -> Result<Self> {
        world.insert_resource(ShadowAtlas::new(gpu));
        ShadowPass::new(gpu, &world.resource::<GpuMaterialMaps>().layout)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<ShadowVariant> {
        let frame = world.resource::<ExtractedFrame>();
        let sc = frame.shadow_counts;
        let views = frame.shadow_views.len();
        let cache = world.resource::<crate::quality::Quality>().shadow_cache;
        let holds = world.resource::<ShadowPass>().holds.as_ref();
        if views > 0 && cache && holds.is_some_and(|h| h.matches(frame)) {
            return PassDecision::new(
                false,
                format!(
                    "cached: the atlas already holds these {views} view(s) and {} caster(s) ({} draws it every frame)",
                    frame.casters.len(),
                    SHADOW_CACHE.setting(Value::Bool(false))
                ),
                ShadowVariant,
            );
        }
        let reason = if views > 0 {
            format!(
                "{views} view(s): {} directional (cascades), {} spot, {} point light(s) (6 faces each); {} caster(s)",
                sc.directional,
                sc.spot,
                sc.point,
                frame.casters.len()
            )
        } else if frame.shadows_disabled {
            format!("shadows are off ({})", SHADOWS.setting(Value::Bool(false)))
        } else if sc.skipped == 0 {
            "no light casts shadows".into()
        } else if frame.casters.is_empty() {
            "no mesh casts shadows".into()
        } else {
            "no mesh receives shadows".into()
        };
        PassDecision::new(views > 0, reason, ShadowVariant)
    }

    crate::pass_systems!(prepare_shadows, shadow_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![ShaderBuild::new(
            "shadow.wgsl",
            vec![crate::render::geometry::gpu_material_maps::group_def(1)],
            &[
                (0, CASTERS),
                (1, crate::render::geometry::gpu_material_maps::CORE_BINDINGS),
            ],
        )]
    }
}

impl ShadowPass {
    /// Compiles the pass (its masked pipeline against the material maps' `maps_layout`)
    /// and creates an empty atlas.
    pub fn new(gpu: &Gpu, maps_layout: &wgpu::BindGroupLayout) -> Result<Self> {
        let source = gpu.shaders.compose(
            "shadow.wgsl",
            &[crate::render::geometry::gpu_material_maps::group_def(1)],
        )?;
        let module = create_module(gpu, "shadow", &source)?;
        let caster_layout = CASTERS.layout(gpu);
        let opaque_layout = pipeline_layout(gpu, "shadow", &[&caster_layout]);
        let masked_layout = pipeline_layout(gpu, "shadow masked", &[&caster_layout, maps_layout]);
        let attribute = |location, format, offset| wgpu::VertexAttribute {
            format,
            offset: offset as u64,
            shader_location: location,
        };
        let position = attribute(0, wgpu::VertexFormat::Float32x3, 0);
        let opaque_vertex = [position];
        let masked_vertex = [
            position,
            attribute(
                6,
                wgpu::VertexFormat::Float32x2,
                std::mem::offset_of!(Vertex, uv),
            ),
            attribute(
                7,
                wgpu::VertexFormat::Float32x2,
                std::mem::offset_of!(Vertex, uv1),
            ),
            attribute(
                8,
                wgpu::VertexFormat::Float32x4,
                std::mem::offset_of!(Vertex, color),
            ),
        ];
        // Each visible caster's world matrix and base colour, per instance (vertex fetch
        // is cheaper than storage reads on lavapipe).
        let instance_attributes = wgpu::vertex_attr_array![
            1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4
        ];
        let opaque_instance = &instance_attributes[..4];
        let pipeline = |label: &str,
                        layout: &wgpu::PipelineLayout,
                        entry: (&str, Option<&str>),
                        vertex: &[wgpu::VertexAttribute],
                        instance: &[wgpu::VertexAttribute]| {
            gpu.checked(label, |device| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(entry.0),
                        compilation_options: Default::default(),
                        buffers: &[
                            Some(wgpu::VertexBufferLayout {
                                array_stride: std::mem::size_of::<Vertex>() as u64,
                                step_mode: wgpu::VertexStepMode::Vertex,
                                attributes: vertex,
                            }),
                            Some(wgpu::VertexBufferLayout {
                                array_stride: std::mem::size_of::<CasterInstance>() as u64,
                                step_mode: wgpu::VertexStepMode::Instance,
                                attributes: instance,
                            }),
                        ],
                    },
                    // Both faces cast: single-sided planes and open meshes must shadow too.
                    primitive: wgpu::PrimitiveState {
                        cull_mode: None,
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: ATLAS_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: Default::default(),
                    fragment: entry.1.map(|fs| wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: Default::default(),
                        targets: &[],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            })
        };
        let opaque = pipeline(
            "shadow pipeline",
            &opaque_layout,
            ("vs_main", None),
            &opaque_vertex,
            opaque_instance,
        )?;
        let masked = pipeline(
            "shadow masked pipeline",
            &masked_layout,
            ("vs_masked", Some("fs_masked")),
            &masked_vertex,
            &instance_attributes,
        )?;
        Ok(ShadowPass {
            pipeline: opaque,
            masked,
            caster_layout,
            caster_views: caster_view_buffer(gpu, 16),
            visible: GrowableBuffer::new(gpu, "shadow visible casters", 1024),
            caster_bind_group: CachedGroup::default(),
            views: Vec::new(),
            holds: None,
        })
    }
}

fn caster_view_buffer(gpu: &Gpu, views: usize) -> wgpu::Buffer {
    gpu.uniform_buffer(
        "shadow caster views",
        (views.max(1) * std::mem::size_of::<GpuCasterView>()) as u64,
    )
}

/// Packs the atlas, uploads the views, culls casters per view and (re)builds bindings.
pub fn prepare_shadows(
    mut p: Prepare<ShadowPass>,
    frame: Res<ExtractedFrame>,
    mut atlas: ResMut<ShadowAtlas>,
) -> Result<()> {
    let pass = &mut *p.pass;
    let atlas = &mut *atlas;
    pass.views.clear();
    let requests: Vec<u32> = frame.shadow_views.iter().map(|v| v.resolution).collect();
    let max_side = MAX_ATLAS_SIDE.min(p.gpu.max_texture_size());
    let (layout, placed) = pack(&requests, max_side);
    if layout.halvings > 0 && atlas.layout.halvings != layout.halvings {
        log::warn!(
            "{} shadow views do not fit a {max_side}² atlas: every view was halved {} time(s)",
            requests.len(),
            layout.halvings
        );
    }
    if placed.iter().any(Option::is_none) {
        log::warn!(
            "some shadow views do not fit the atlas even at 64²: their lights are unshadowed"
        );
    }
    // Whatever the atlas held, this frame draws it again.
    pass.holds = None;
    if !frame.shadow_views.is_empty() {
        atlas.fit(&p.gpu, layout.side);
    }
    let side = atlas.atlas.texture.width() as f32;
    let gpu_views: Vec<GpuShadowView> = frame
        .shadow_views
        .iter()
        .zip(&layout.rects)
        .zip(&placed)
        .map(|((v, r), p)| GpuShadowView {
            clip_from_world: v.clip_from_world.to_cols_array_2d(),
            rect: if p.is_some() {
                [
                    r.x as f32 / side,
                    r.y as f32 / side,
                    r.size as f32 / side,
                    r.size as f32 / side,
                ]
            } else {
                [0.0; 4]
            },
            texel: [
                v.texel * v.resolution as f32 / r.size.max(1) as f32,
                if v.perspective { 1.0 } else { 0.0 },
                v.near_or_depth_range,
                v.far,
            ],
        })
        .collect();
    let data: &[u8] = if gpu_views.is_empty() {
        &[0; std::mem::size_of::<GpuShadowView>()]
    } else {
        bytemuck::cast_slice(&gpu_views)
    };
    atlas.gpu_views.write(&p.gpu, data);
    let in_uniform = data
        .len()
        .min(UNIFORM_SHADOW_VIEWS as usize * std::mem::size_of::<GpuShadowView>());
    p.gpu
        .queue
        .write_buffer(&atlas.views_uniform, 0, &data[..in_uniform]);

    // Per view: the casters whose bounding sphere touches its frustum, grouped by mesh
    // and mask.
    let mut visible: Vec<CasterInstance> = Vec::new();
    let mut caster_views: Vec<GpuCasterView> = Vec::new();
    for ((view, rect), p) in frame.shadow_views.iter().zip(&layout.rects).zip(&placed) {
        if p.is_none() {
            continue;
        }
        let planes = frustum_planes(&view.clip_from_world);
        let mut draws: Vec<CasterDraw> = Vec::new();
        for caster in &frame.casters {
            if !sphere_in_frustum(&planes, caster.center, caster.radius) {
                continue;
            }
            let index = visible.len() as u32;
            match draws.last_mut() {
                Some(d)
                    if d.mesh == caster.mesh
                        && d.mask == caster.mask
                        && d.deformed.is_none()
                        && caster.deformed.is_none() =>
                {
                    d.count += 1
                }
                _ => draws.push(CasterDraw {
                    mesh: caster.mesh,
                    deformed: caster.deformed,
                    mask: caster.mask,
                    first: index,
                    count: 1,
                }),
            }
            visible.push(caster_instance(&frame, caster));
        }
        caster_views.push(GpuCasterView {
            clip_from_world: view.clip_from_world.to_cols_array_2d(),
            pad: [[0.0; 4]; 12],
        });
        pass.views.push(ViewDraws { rect: *rect, draws });
    }
    atlas.layout = layout;
    if caster_views.is_empty() {
        return Ok(());
    }
    let needed = (caster_views.len() * std::mem::size_of::<GpuCasterView>()) as u64;
    if needed > pass.caster_views.size() {
        pass.caster_views = caster_view_buffer(&p.gpu, caster_views.len().next_power_of_two());
    }
    p.gpu
        .queue
        .write_buffer(&pass.caster_views, 0, bytemuck::cast_slice(&caster_views));
    if visible.is_empty() {
        visible.push(<CasterInstance as bytemuck::Zeroable>::zeroed());
    }
    pass.visible.write(&p.gpu, bytemuck::cast_slice(&visible));
    let resources = vec![wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer: &pass.caster_views,
        offset: 0,
        size: wgpu::BufferSize::new(64),
    })];
    pass.caster_bind_group
        .get(&p.gpu, &CASTERS, &pass.caster_layout, resources)
        .map(|_| ())
}

/// Records the shadow pass: one render pass over the atlas, one viewport per view.
pub fn shadow_pass(
    mut pass: ResMut<ShadowPass>,
    atlas: Res<ShadowAtlas>,
    buffers: Res<SceneBuffers>,
    maps: Res<GpuMaterialMaps>,
    frame: Res<ExtractedFrame>,
    deform: Res<DeformedVertices>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let pass = &mut *pass;
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(bind_group)) = (encoder.as_mut(), pass.caster_bind_group.group())
    else {
        return;
    };
    pass.holds = Some(AtlasContents::of(&frame));
    let scope = timer.begin_pass(PassId::Shadow);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &atlas.atlas.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(&pass.pipeline);
        let mut masked = false;
        rp.set_vertex_buffer(1, pass.visible.buffer.slice(..));
        for (i, view) in pass.views.iter().enumerate() {
            let r = view.rect;
            rp.set_viewport(
                r.x as f32,
                r.y as f32,
                r.size as f32,
                r.size as f32,
                0.0,
                1.0,
            );
            rp.set_scissor_rect(r.x, r.y, r.size, r.size);
            let offset = (i * std::mem::size_of::<GpuCasterView>()) as u32;
            rp.set_bind_group(0, bind_group, &[offset]);
            for draw in &view.draws {
                let Some(gpu_mesh) = buffers.meshes.get(&draw.mesh) else {
                    continue;
                };
                let Some(vertices) = deform.draw_vertices(&frame, gpu_mesh, draw.deformed) else {
                    continue;
                };
                // A mask whose maps have no bind group (not uploaded) casts its whole
                // outline, as an opaque caster.
                let group = draw.mask.and_then(|m| maps.group(m));
                if group.is_some() != masked {
                    masked = group.is_some();
                    rp.set_pipeline(if masked { &pass.masked } else { &pass.pipeline });
                }
                if let Some(group) = group {
                    rp.set_bind_group(1, group, &[]);
                }
                rp.set_vertex_buffer(0, vertices.slice(..));
                rp.set_index_buffer(gpu_mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                rp.draw_indexed(
                    0..gpu_mesh.index_count,
                    0,
                    draw.first..draw.first + draw.count,
                );
            }
        }
    }
    timer.end_pass(scope);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::shaders::struct_layout;

    #[test]
    fn a_caster_view_is_its_shader_struct_padded_to_a_dynamic_offset_step() {
        let defs = [crate::render::geometry::gpu_material_maps::group_def(1)];
        let layout = struct_layout("shadow.wgsl", &defs, "CasterView").expect("CasterView");
        assert_eq!(
            layout.members,
            vec![(
                "clip_from_world".to_string(),
                std::mem::offset_of!(GpuCasterView, clip_from_world) as u32
            )]
        );
        assert_eq!(std::mem::size_of::<GpuCasterView>(), 256);
        assert!(layout.size <= 256);
    }
}

//! The shadow pass: packs the frame's shadow views into one depth atlas and draws each
//! view's casters into its rectangle, all in one render pass. Per view only the depth draws
//! repeat: the casters are culled on the CPU against the view's frustum, and each view
//! selects its matrix with a dynamic offset (no per-view pipeline, pass or target).

use super::atlas::{AtlasLayout, AtlasRect, pack};
use crate::error::Result;
use crate::render::bindings::{BindGroupSpec, Binding};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameEncoder, FrameErrors};
use crate::render::gpu_types::{GpuCasterView, GpuShadowView};
use crate::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use crate::render::pipelines::create_module;
use crate::render::scene_buffers::{GrowableBuffer, SceneBuffers};
use crate::render::shadow_views::{ShadowView, frustum_planes, sphere_in_frustum};
use crate::render::targets::Target;
use crate::scene::{MeshHandle, Vertex};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

/// Format of the shadow atlas.
pub const ATLAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Largest atlas side; views are halved until they fit (README, "Shadows").
pub const MAX_ATLAS_SIDE: u32 = 8192;

struct ViewDraws {
    rect: AtlasRect,
    /// (mesh, first index into the visible list, count).
    draws: Vec<(MeshHandle, u32, u32)>,
}

/// The shadow pass's pipeline, atlas and buffers.
#[derive(Resource)]
pub struct ShadowPass {
    pipeline: wgpu::RenderPipeline,
    caster_layout: wgpu::BindGroupLayout,
    caster_views: wgpu::Buffer,
    visible: GrowableBuffer,
    /// [`GpuShadowView`] per view, read by the lighting pass.
    pub gpu_views: GrowableBuffer,
    /// The first [`UNIFORM_SHADOW_VIEWS`] views again, as a uniform buffer the lighting
    /// pass reads when every view fits (uniform loads are cheaper on lavapipe, as for
    /// the lights).
    pub views_uniform: wgpu::Buffer,
    /// The depth atlas (1×1 until a frame has shadows).
    pub atlas: Target,
    /// A comparison sampler (less-equal, bilinear: hardware 2×2 PCF) for the atlas.
    pub sampler: wgpu::Sampler,
    caster_bind_group: Option<(u64, wgpu::BindGroup)>,
    caster_generation: u64,
    views: Vec<ViewDraws>,
    /// This frame's atlas layout.
    pub layout: AtlasLayout,
    /// Bumped whenever the atlas or the view buffer is recreated.
    pub generation: u64,
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
            .flat_map(|v| v.draws.iter().map(|d| d.2))
            .sum()
    }
}

/// What the shadow atlas was drawn from: every shadow view, and every caster's mesh and
/// transform (in a canonical order). Meshes are immutable once added, so equal contents
/// draw an equal atlas.
#[derive(Clone, Debug, PartialEq)]
struct AtlasContents {
    views: Vec<ShadowView>,
    casters: Vec<(MeshHandle, [[f32; 4]; 4])>,
}

impl AtlasContents {
    fn caster(
        frame: &ExtractedFrame,
        c: &crate::render::extract::Caster,
    ) -> (MeshHandle, [[f32; 4]; 4]) {
        let world = frame
            .instances
            .get(c.instance as usize)
            .map_or([[0.0; 4]; 4], |i| i.world_from_local);
        (c.mesh, world)
    }

    /// `frame`'s casters in a canonical order (by mesh, then by the transform's bits).
    /// Depth-only draws give the same atlas in any order, and the order of
    /// [`ExtractedFrame::casters`] follows the camera's frustum (instances in view first),
    /// which a probe capture's differs from.
    fn casters_of(frame: &ExtractedFrame) -> Vec<(MeshHandle, [[f32; 4]; 4])> {
        let mut casters: Vec<_> = frame
            .casters
            .iter()
            .map(|c| Self::caster(frame, c))
            .collect();
        casters.sort_by_key(|(mesh, m)| (*mesh, m.map(|row| row.map(f32::to_bits))));
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

/// The shadow pass's bind group: each view's matrix at a dynamic offset.
pub const CASTERS: BindGroupSpec = BindGroupSpec {
    label: "shadow casters",
    visibility: wgpu::ShaderStages::VERTEX,
    bindings: &[("caster_view", Binding::DynamicUniform(64))],
};

/// The shadow atlas: every shadow view's depth (owned by [`ShadowPass`]).
pub const SHADOW_ATLAS: Slot = Slot::owned("shadow atlas");

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
    const READS: &'static [Slot] = &[];
    const WRITES: &'static [Slot] = &[SHADOW_ATLAS];
    type Variant = ShadowVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        ShadowPass::new(gpu)
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
                    "cached: the atlas already holds these {views} view(s) and {} caster(s) (--no-shadow-cache draws it every frame)",
                    frame.casters.len()
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
            "shadows are off (--no-shadows)".into()
        } else if sc.skipped == 0 {
            "no light casts shadows".into()
        } else if frame.casters.is_empty() {
            "no mesh casts shadows".into()
        } else {
            "no mesh receives shadows".into()
        };
        PassDecision::new(views > 0, reason, ShadowVariant)
    }

    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        Some(prepare_shadows.into_configs())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        shadow_pass.into_configs()
    }
}

/// Shadow views the uniform copy holds (96 bytes each: 12 KiB).
pub const UNIFORM_SHADOW_VIEWS: u32 = 128;

fn atlas_target(gpu: &Gpu, side: u32) -> Target {
    Target::new(gpu, "shadow atlas", (side, side), ATLAS_FORMAT)
}

impl ShadowPass {
    /// Compiles the pass and creates an empty atlas.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let source = gpu.shaders.compose("shadow.wgsl", &[])?;
        let module = create_module(gpu, "shadow", &source)?;
        let caster_layout = CASTERS.layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("shadow"),
                bind_group_layouts: &[Some(&caster_layout)],
                immediate_size: 0,
            });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3];
        // Each visible caster's world matrix, per instance (vertex fetch is cheaper than
        // storage reads on lavapipe).
        let instance_attributes = wgpu::vertex_attr_array![
            1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4
        ];
        let pipeline = gpu.checked("shadow pipeline", |device| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("shadow"),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[
                        Some(wgpu::VertexBufferLayout {
                            array_stride: std::mem::size_of::<Vertex>() as u64,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &attributes,
                        }),
                        Some(wgpu::VertexBufferLayout {
                            array_stride: 64,
                            step_mode: wgpu::VertexStepMode::Instance,
                            attributes: &instance_attributes,
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
                fragment: None,
                multiview_mask: None,
                cache: None,
            })
        })?;
        Ok(ShadowPass {
            pipeline,
            caster_layout,
            caster_views: caster_view_buffer(gpu, 16),
            visible: GrowableBuffer::new(gpu, "shadow visible casters", 1024),
            gpu_views: GrowableBuffer::new(
                gpu,
                "shadow views",
                16 * std::mem::size_of::<GpuShadowView>() as u64,
            ),
            views_uniform: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("shadow views (uniform)"),
                size: u64::from(UNIFORM_SHADOW_VIEWS) * std::mem::size_of::<GpuShadowView>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            atlas: atlas_target(gpu, 1),
            sampler: gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            }),
            caster_bind_group: None,
            caster_generation: 0,
            views: Vec::new(),
            layout: AtlasLayout {
                side: 1,
                rects: Vec::new(),
                halvings: 0,
            },
            generation: 0,
            holds: None,
        })
    }
}

fn caster_view_buffer(gpu: &Gpu, views: usize) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("shadow caster views"),
        size: (views.max(1) * std::mem::size_of::<GpuCasterView>()) as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Packs the atlas, uploads the views, culls casters per view and (re)builds bindings.
pub fn prepare_shadows(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    mut pass: ResMut<ShadowPass>,
    mut errors: ResMut<FrameErrors>,
) {
    let pass = &mut *pass;
    pass.views.clear();
    let requests: Vec<u32> = frame.shadow_views.iter().map(|v| v.resolution).collect();
    let max_side = MAX_ATLAS_SIDE.min(gpu.max_texture_size());
    let (layout, placed) = pack(&requests, max_side);
    if layout.halvings > 0 && pass.layout.halvings != layout.halvings {
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
    if !frame.shadow_views.is_empty() && pass.atlas.texture.width() != layout.side {
        pass.atlas = atlas_target(&gpu, layout.side);
        pass.generation += 1;
    }
    let side = pass.atlas.texture.width() as f32;
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
    if pass.gpu_views.write(&gpu, data) {
        pass.generation += 1;
    }
    let in_uniform = data
        .len()
        .min(UNIFORM_SHADOW_VIEWS as usize * std::mem::size_of::<GpuShadowView>());
    gpu.queue
        .write_buffer(&pass.views_uniform, 0, &data[..in_uniform]);

    // Per view: the casters whose bounding sphere touches its frustum, grouped by mesh.
    let mut visible: Vec<[[f32; 4]; 4]> = Vec::new();
    let mut caster_views: Vec<GpuCasterView> = Vec::new();
    for ((view, rect), p) in frame.shadow_views.iter().zip(&layout.rects).zip(&placed) {
        if p.is_none() {
            continue;
        }
        let planes = frustum_planes(&view.clip_from_world);
        let mut draws: Vec<(MeshHandle, u32, u32)> = Vec::new();
        for caster in &frame.casters {
            if !sphere_in_frustum(&planes, caster.center, caster.radius) {
                continue;
            }
            let index = visible.len() as u32;
            match draws.last_mut() {
                Some(d) if d.0 == caster.mesh => d.2 += 1,
                _ => draws.push((caster.mesh, index, 1)),
            }
            visible.push(AtlasContents::caster(&frame, caster).1);
        }
        caster_views.push(GpuCasterView {
            clip_from_world: view.clip_from_world.to_cols_array_2d(),
            pad: [[0.0; 4]; 12],
        });
        pass.views.push(ViewDraws { rect: *rect, draws });
    }
    pass.layout = layout;
    if caster_views.is_empty() {
        return;
    }
    let needed = (caster_views.len() * std::mem::size_of::<GpuCasterView>()) as u64;
    if needed > pass.caster_views.size() {
        pass.caster_views = caster_view_buffer(&gpu, caster_views.len().next_power_of_two());
        pass.caster_generation += 1;
    }
    gpu.queue
        .write_buffer(&pass.caster_views, 0, bytemuck::cast_slice(&caster_views));
    if visible.is_empty() {
        visible.push([[0.0; 4]; 4]);
    }
    if pass.visible.write(&gpu, bytemuck::cast_slice(&visible)) {
        pass.caster_generation += 1;
    }
    let key = pass.caster_generation;
    if pass
        .caster_bind_group
        .as_ref()
        .is_none_or(|(k, _)| *k != key)
    {
        let group = match CASTERS.group(
            &gpu,
            &pass.caster_layout,
            vec![wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &pass.caster_views,
                offset: 0,
                size: wgpu::BufferSize::new(64),
            })],
        ) {
            Ok(group) => group,
            Err(e) => {
                errors.0.push(e);
                return;
            }
        };
        pass.caster_bind_group = Some((key, group));
    }
}

/// Records the shadow pass: one render pass over the atlas, one viewport per view.
pub fn shadow_pass(
    mut pass: ResMut<ShadowPass>,
    buffers: Res<SceneBuffers>,
    frame: Res<ExtractedFrame>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let pass = &mut *pass;
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some((_, bind_group))) =
        (encoder.as_mut(), pass.caster_bind_group.as_ref())
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
                view: &pass.atlas.view,
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
            for &(mesh, first, count) in &view.draws {
                let Some(gpu_mesh) = buffers.meshes.get(&mesh) else {
                    continue;
                };
                rp.set_vertex_buffer(0, gpu_mesh.vertices.slice(..));
                rp.set_index_buffer(gpu_mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                rp.draw_indexed(0..gpu_mesh.index_count, 0, first..first + count);
            }
        }
    }
    timer.end_pass(scope);
}

//! The frame graph: a pass added from outside the engine is one type and one line of
//! registration (`app.add_pass::<Dim>()`), and the graph derives the rest: its place in
//! the order, its run condition, its timer label, its `--explain` line and the lifetime of
//! what it touches. Declarations the graph cannot order are refused.

use crate::common;

use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use lumen::App;
use lumen::render::device::Gpu;
use lumen::render::frame::FrameEncoder;
use lumen::render::graph::slots::{GBUFFER_SPECULAR_LEVEL, HDR};
use lumen::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use lumen::render::targets::RenderTargets;

const SIZE: (u32, u32) = (64, 48);

/// Whether [`Dim`] runs: a resource a test flips.
#[derive(Resource, Clone, Copy)]
struct DimOn(bool);

/// A toy pass: halves the HDR target by multiplicative blending of a constant 0.5.
#[derive(Resource)]
struct Dim {
    pipeline: wgpu::RenderPipeline,
}

/// Dim's one variant.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DimVariant {
    factor: f32,
}

const DIM_WGSL: &str = "
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(0.5, 0.5, 0.5, 1.0); }
";

impl FramePass for Dim {
    const ID: PassId = PassId::new("dim");
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = DimVariant;

    fn create(world: &mut World, gpu: &Gpu) -> lumen::Result<Self> {
        world.insert_resource(DimOn(true));
        let format = world
            .resource::<lumen::quality::Quality>()
            .hdr_precision
            .format();
        let module = gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("dim"),
                source: wgpu::ShaderSource::Wgsl(DIM_WGSL.into()),
            });
        let multiply = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::Src,
            operation: wgpu::BlendOperation::Add,
        };
        let pipeline = gpu
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("dim"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState {
                            color: multiply,
                            alpha: multiply,
                        }),
                        write_mask: wgpu::ColorWrites::COLOR,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            });
        Ok(Dim { pipeline })
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<DimVariant> {
        let on = world.resource::<DimOn>().0;
        PassDecision::new(
            on,
            if on {
                "halves the HDR image"
            } else {
                "turned off"
            },
            DimVariant { factor: 0.5 },
        )
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        record_dim.into_configs()
    }
}

fn record_dim(pass: Res<Dim>, targets: Res<RenderTargets>, mut encoder: ResMut<FrameEncoder>) {
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some(hdr)) = (
        encoder.as_mut(),
        targets.current.as_ref().and_then(|t| t.view(HDR)),
    ) else {
        return;
    };
    let scope = timer.begin_pass(Dim::ID);
    {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("dim"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timer.render_writes(&scope),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(&pass.pipeline);
        rp.draw(0..3, 0..1);
    }
    timer.end_pass(scope);
}

fn hdr_luminance(app: &mut App) -> Vec<f32> {
    app.render_headless(SIZE).expect("frame");
    app.read_hdr_image()
        .expect("hdr")
        .pixels()
        .map(common::lum)
        .collect()
}

#[test]
fn a_pass_added_with_one_line_runs_in_order_and_is_planned_timed_and_explained() {
    let mut app = common::app_with("spheres");
    let before = hdr_luminance(&mut app);
    app.add_pass::<Dim>().expect("the toy pass registers");
    let after = hdr_luminance(&mut app);
    let report = app.render_headless(SIZE).expect("frame");
    // It ran after everything else that touches HDR (tone mapping reads it first).
    let (last, _) = report.plan.passes.last().expect("passes");
    assert_eq!(*last, Dim::ID);
    assert!(report.plan.runs(Dim::ID));
    assert!(
        report
            .plan
            .explain()
            .contains("dim         run  halves the HDR image"),
        "{}",
        report.plan.explain()
    );
    assert_eq!(
        report.plan.variant::<Dim>(),
        Some(&DimVariant { factor: 0.5 })
    );
    let hdr = report
        .plan
        .lifetimes
        .iter()
        .find(|l| l.slot == HDR)
        .expect("HDR has a lifetime");
    assert_eq!((hdr.first.name(), hdr.last.name()), ("lighting", "dim"));
    assert_eq!(
        report.passes.last().map(|p| p.name),
        Some("dim"),
        "the timer label is the pass's name"
    );
    // Halved exactly (0.5 is exact in f16 and f32), pixel by pixel, and something is lit.
    assert!(before.iter().any(|&l| l > 0.01));
    for (b, a) in before.iter().zip(&after) {
        assert!((a - 0.5 * b).abs() <= 1e-6 * b.max(1.0), "{a} vs {b}");
    }
    // Its decision is its run condition.
    app.world_mut().insert_resource(DimOn(false));
    assert_eq!(hdr_luminance(&mut app), before);
    let report = app.render_headless(SIZE).expect("frame");
    assert!(!report.plan.runs(Dim::ID));
    assert!(report.passes.iter().all(|p| p.name != "dim"));
}

/// Reads a slot nobody writes.
#[derive(Resource)]
struct Orphan;

const NOWHERE: Slot = Slot::owned("nowhere");

impl FramePass for Orphan {
    const ID: PassId = PassId::new("orphan");
    const READS: &'static [Slot] = &[NOWHERE];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = ();

    fn create(_: &mut World, _: &Gpu) -> lumen::Result<Self> {
        Ok(Orphan)
    }

    fn decide(_: &World, _: &FramePlan) -> PassDecision<()> {
        PassDecision::new(true, "always", ())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        (|| {}).into_configs()
    }
}

#[test]
fn a_read_no_pass_writes_and_a_taken_name_are_refused() {
    let mut app = common::app_with("plane");
    let before = app.render_headless(SIZE).expect("frame").plan;
    let err = app
        .add_pass::<Orphan>()
        .expect_err("nothing writes 'nowhere'");
    let message = err.to_string();
    assert!(
        message.contains("'orphan'") && message.contains("'nowhere'"),
        "{message}"
    );
    app.add_pass::<Dim>().expect("dim registers");
    let err = app.add_pass::<Dim>().expect_err("two passes named dim");
    assert!(err.to_string().contains("'dim'"), "{err}");
    // The frame still renders, with the built-in passes and dim only.
    let after = app.render_headless(SIZE).expect("frame").plan;
    assert_eq!(after.passes.len(), before.passes.len() + 1);
}

/// The resource line of `explain` that holds `slots` (its slot list, exactly).
fn resource_line<'a>(explain: &'a str, slots: &str) -> Option<&'a str> {
    explain
        .lines()
        .find(|l| l.trim_end().ends_with(&format!("MiB  {slots}")))
}

/// The reflection pass reads the specular level from a target of its own, so lighting is
/// G-buffer 2's last reader and the reflections' copy of the lit frame takes its memory;
/// a frame without reflections has neither the target nor the sharing.
#[test]
fn the_reflections_copy_of_the_lit_frame_takes_gbuffer2s_memory() {
    let mut app = common::app_with("spheres");
    let with = app.render_headless(SIZE).expect("frame").plan;
    assert!(with.runs(PassId::Reflections), "{}", with.explain());
    let explain = with.explain();
    assert!(
        resource_line(
            &explain,
            "gbuffer2 emissive + specular level, ssr lit frame"
        )
        .is_some(),
        "{explain}"
    );
    let level = resource_line(&explain, "specular level").expect("the level's target");
    assert!(level.contains("R16Float 64x48"), "{level}");
    let life = with
        .lifetimes
        .iter()
        .find(|l| l.slot == GBUFFER_SPECULAR_LEVEL)
        .expect("the level has a lifetime");
    assert_eq!((life.first.name(), life.last.name()), ("gbuffer", "ssr"));
    // The copy (64×48 Rgba16Float, 8 bytes a texel) is one of the shared textures.
    let memory = with.memory();
    assert!(
        memory.texture_bytes_unaliased - memory.texture_bytes >= 64 * 48 * 8,
        "{memory:?}"
    );

    app.world_mut()
        .resource_mut::<lumen::quality::Quality>()
        .ssr
        .enabled = false;
    let without = app.render_headless(SIZE).expect("frame").plan;
    let explain = without.explain();
    assert!(!without.runs(PassId::Reflections));
    assert!(
        without
            .lifetimes
            .iter()
            .all(|l| l.slot != GBUFFER_SPECULAR_LEVEL),
        "{explain}"
    );
    assert!(
        resource_line(&explain, "gbuffer2 emissive + specular level").is_some(),
        "{explain}"
    );
    assert!(
        explain.contains("specular level target  off only screen-space reflections read it"),
        "{explain}"
    );
}

//! A toy knob and a toy half-resolution pass, declared in this file alone and registered
//! with one line each (`app.add_knob(&TOY_STRENGTH)`, `app.add_pass::<Toy>()`): the knob
//! reaches `--help`, the JSON, the tradeoff sweep and `quality show`; the pass gets its
//! half-resolution texture from the graph, which sizes, plans and explains it, and its
//! strength from the knob.

use crate::common;

use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;
use lumen::App;
use lumen::quality::knob::{Acts, Group, Kind, Knob, Value};
use lumen::quality::{Knobs, Quality, QualityPreset};
use lumen::render::device::Gpu;
use lumen::render::frame::FrameEncoder;
use lumen::render::graph::slots::HDR;
use lumen::render::graph::{
    Extent, FramePass, FramePlan, PassDecision, PassId, Sizing, Slot, TargetFormat, TextureDesc,
};
use lumen::render::targets::RenderTargets;

const SIZE: (u32, u32) = (64, 48);

/// The toy's knob: how much of the HDR image it keeps.
static TOY_STRENGTH: Knob = Knob {
    name: "toy-strength",
    path: "extensions.toy-strength",
    group: Group::CAMERA,
    doc: "How much of the image the toy pass keeps",
    kind: Kind::Float { min: 0.0, max: 4.0 },
    default: Value::Float(1.0),
    passes: &[PassId::new("toy")],
    acts: Acts::FRAME,
    sweep: &[Value::Float(0.25), Value::Float(2.0)],
    sweep_with: &[],
};

/// The toy's half-resolution texture: the strength, written once per 2×2 pixels.
const TOY_HALF: Slot = Slot::texture(
    "toy half",
    TextureDesc::full(TargetFormat::Fixed(wgpu::TextureFormat::R16Float)).at(Some(Extent::HALF)),
);

/// Writes the strength into [`TOY_HALF`], then multiplies the HDR image by it.
#[derive(Resource)]
struct Toy {
    fill: wgpu::RenderPipeline,
    apply: wgpu::RenderPipeline,
    params: wgpu::Buffer,
}

const FILL_WGSL: &str = "
@group(0) @binding(0) var<uniform> strength: vec4<f32>;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
@fragment fn fs() -> @location(0) vec4<f32> { return vec4<f32>(strength.x, 0.0, 0.0, 1.0); }
";

const APPLY_WGSL: &str = "
@group(0) @binding(0) var half_texture: texture_2d<f32>;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}
@fragment fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let s = textureLoad(half_texture, vec2<i32>(p.xy) / 2, 0).r;
    return vec4<f32>(s, s, s, 1.0);
}
";

fn pipeline(
    gpu: &Gpu,
    source: &str,
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> wgpu::RenderPipeline {
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("toy"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
    gpu.device
        .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("toy"),
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
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
}

impl FramePass for Toy {
    const ID: PassId = PassId::new("toy");
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[HDR, TOY_HALF];
    type Variant = ();

    fn create(world: &mut World, gpu: &Gpu) -> lumen::Result<Self> {
        let hdr = world.resource::<Quality>().hdr_precision.format();
        let multiply = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::Src,
            operation: wgpu::BlendOperation::Add,
        };
        let blend = wgpu::BlendState {
            color: multiply,
            alpha: wgpu::BlendComponent::REPLACE,
        };
        Ok(Toy {
            fill: pipeline(gpu, FILL_WGSL, wgpu::TextureFormat::R16Float, None),
            apply: pipeline(gpu, APPLY_WGSL, hdr, Some(blend)),
            params: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("toy strength"),
                size: 16,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        })
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        let strength = TOY_STRENGTH.get(world.resource::<Quality>());
        PassDecision::new(
            strength != Value::Float(1.0),
            format!("keeps {} of the image", TOY_STRENGTH.format(strength)),
            (),
        )
        .sized(TOY_HALF, Sizing::Texture(Extent::HALF, None))
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        record_toy.into_configs()
    }
}

fn record_toy(
    pass: Res<Toy>,
    gpu: Res<Gpu>,
    quality: Res<Quality>,
    targets: Res<RenderTargets>,
    mut encoder: ResMut<FrameEncoder>,
) {
    let strength = TOY_STRENGTH.get(&quality).as_f32().unwrap_or(1.0);
    gpu.queue.write_buffer(
        &pass.params,
        0,
        bytemuck::cast_slice(&[strength, 0.0, 0.0, 0.0]),
    );
    let FrameEncoder { encoder, timer } = &mut *encoder;
    let (Some(encoder), Some([hdr, half])) = (
        encoder.as_mut(),
        targets
            .current
            .as_ref()
            .and_then(|t| t.views([HDR, TOY_HALF])),
    ) else {
        return;
    };
    let group = |pipeline: &wgpu::RenderPipeline, resource| {
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("toy"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource,
            }],
        })
    };
    let fill = group(&pass.fill, pass.params.as_entire_binding());
    let apply = group(&pass.apply, wgpu::BindingResource::TextureView(half));
    let scope = timer.begin_pass(Toy::ID);
    for (target, pipeline, group) in [(half, &pass.fill, &fill), (hdr, &pass.apply, &apply)] {
        let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("toy"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        rp.set_pipeline(pipeline);
        rp.set_bind_group(0, group, &[]);
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
fn a_toy_knob_and_a_toy_half_resolution_pass_register_with_one_line_each() {
    let mut app = common::app_with("spheres");
    let before = hdr_luminance(&mut app);
    app.add_knob(&TOY_STRENGTH).expect("a new knob");
    app.add_pass::<Toy>().expect("a new pass");
    // At its default the pass does not run, and nothing changes.
    assert_eq!(hdr_luminance(&mut app), before);
    TOY_STRENGTH
        .set(
            &mut app.world_mut().resource_mut::<Quality>(),
            Value::Float(0.25),
        )
        .expect("in range");
    let after = hdr_luminance(&mut app);
    assert!(before.iter().any(|&l| l > 0.01));
    for (b, a) in before.iter().zip(&after) {
        assert!((a - 0.25 * b).abs() <= 1e-3 * b.max(1.0), "{a} vs {b}");
    }
    // The graph gave it its half-resolution texture, and says so.
    let plan = app.render_headless(SIZE).expect("frame").plan;
    let half = plan.resources.get(TOY_HALF).expect("planned");
    assert_eq!(half.passes, (Toy::ID, Toy::ID));
    assert_eq!(
        half.shape,
        lumen::render::graph::resources::Shape::Texture(
            lumen::render::graph::resources::TextureClass {
                format: wgpu::TextureFormat::R16Float,
                size: (32, 24),
            },
            1,
            wgpu::TextureUsages::empty(),
        )
    );
    let explained = plan.explain();
    assert!(
        explained.contains("toy         run  keeps 0.25 of the image"),
        "{explained}"
    );
    assert!(explained.contains("R16Float 32x24"), "{explained}");
    // The knob, in every place the front end derives from its declaration.
    let knobs: Knobs = app.world().resource::<Knobs>().clone();
    let help = lumen_game::cli::command(&knobs)
        .find_subcommand_mut("render")
        .expect("render")
        .render_long_help()
        .to_string();
    assert!(help.contains("--toy-strength <X>"), "{help}");
    let quality = app.world().resource::<Quality>().clone();
    assert_eq!(
        knobs.json(&quality)["toy-strength"],
        serde_json::json!(0.25)
    );
    let rows: Vec<String> = lumen_game::commands::tradeoff::configurations(
        &lumen_game::cli::SceneArgs::default(),
        &knobs,
    )
    .into_iter()
    .filter(|(kind, _, _)| kind == "--toy-strength")
    .map(|(_, setting, _)| setting)
    .collect();
    assert_eq!(rows, ["0.25", "2"]);
    let shown = lumen_game::commands::quality::show(&knobs, QualityPreset::High);
    assert!(shown.contains("toy-strength = 1.0"), "{shown}");
}

//! Temporal anti-aliasing: motion vectors against the analytic motion of a moving cube,
//! history hygiene (a camera cut and a resize reset it, a NaN never enters it) and
//! ghosting behind a moving sphere.

use crate::common;

use bevy_ecs::schedule::{IntoScheduleConfigs, ScheduleConfigs};
use bevy_ecs::system::ScheduleSystem;
use lumen::FrameTarget;
use lumen::assets::procedural::{cube, plane, uv_sphere};
use lumen::prelude::*;
use lumen::quality::AaMethod;
use lumen::render::device::Gpu;
use lumen::render::frame::FrameEncoder;
use lumen::render::graph::registry::Registry;
use lumen::render::graph::slots::HDR;
use lumen::render::graph::{FramePass, FramePlan, PassDecision, PassId, Slot};
use lumen::render::targets::RenderTargets;

/// TAA on, frame by frame; probes, AO and reflections off.
fn taa_quality(app: &mut App) {
    app.set_progressive_taa(true);
    common::indirect_off(app);
    app.world_mut().resource_mut::<Quality>().aa.method = AaMethod::Taa;
}

fn camera_at(world: &mut World, from: Vec3, to: Vec3) -> Entity {
    world
        .spawn((
            Camera {
                exposure: Exposure::Linear(1.0),
                tonemapper: lumen::shading::color::Tonemapper::None,
                ..Camera::default()
            },
            Transform::from_translation(from).looking_at(to, Vec3::Y),
        ))
        .id()
}

fn taa_reason(report: &FrameReport) -> String {
    report
        .plan
        .passes
        .iter()
        .find(|(id, _)| *id == PassId::Taa)
        .map(|(_, d)| d.reason.clone())
        .expect("the plan decides on TAA")
}

#[test]
fn motion_vectors_match_the_analytic_motion_of_a_moving_cube() {
    let size = (128u32, 128u32);
    let mut app = App::headless().expect("a GPU adapter");
    let mesh = app.add_mesh(cube(1.0)).expect("mesh");
    taa_quality(&mut app);
    app.keep_target(FrameTarget::Motion);
    app.keep_target(FrameTarget::Depth);
    let before = Transform::from_translation(Vec3::new(-0.3, 0.0, 0.0));
    let after = Transform::from_translation(Vec3::new(0.0, 0.1, 0.0))
        .with_rotation(Quat::from_rotation_y(10f32.to_radians()));
    let world = app.world_mut();
    let cube_entity = world
        .spawn((
            Mesh3d(mesh),
            Material {
                emissive: Vec3::ONE,
                ..Material::new(Vec3::ZERO, 0.0, 1.0)
            },
            before,
        ))
        .id();
    camera_at(world, Vec3::new(1.0, 1.5, 4.0), Vec3::ZERO);
    app.render_headless(size).expect("first frame");
    app.world_mut().entity_mut(cube_entity).insert(after);
    let report = app.render_headless(size).expect("second frame");
    // The G-buffer pass writes them, TAA reads them.
    let lifetime = report
        .plan
        .lifetimes
        .iter()
        .find(|l| l.slot == lumen::render::graph::slots::MOTION)
        .expect("motion vectors are planned");
    assert_eq!(
        (lifetime.first, lifetime.last),
        (PassId::GBuffer, PassId::Taa)
    );
    let motion = app.read_target(FrameTarget::Motion).expect("motion");
    let depth = app.read_target(FrameTarget::Depth).expect("depth");
    let frame = app
        .world()
        .resource::<lumen::render::extract::ExtractedFrame>();
    let world_from_clip = glam::Mat4::from_cols_array_2d(&frame.view.world_from_clip);
    let clip_from_world = frame.temporal.clip_from_world;
    let to_pixel = |p: Vec3| {
        let c = clip_from_world * p.extend(1.0);
        Vec2::new(
            (c.x / c.w * 0.5 + 0.5) * size.0 as f32,
            (0.5 - c.y / c.w * 0.5) * size.1 as f32,
        )
    };
    let (m_before, m_after) = (before.to_matrix(), after.to_matrix());
    let (mut checked, mut worst, mut background_worst) = (0, 0.0f32, 0.0f32);
    for y in 1..size.1 - 1 {
        for x in 1..size.0 - 1 {
            // Pixels whose 3 × 3 neighbourhood is all cube, or all background.
            let ds: Vec<f32> = (0..9)
                .map(|k| depth.get_pixel(x + k % 3 - 1, y + k / 3 - 1).0[0])
                .collect();
            let got = Vec2::new(motion.get_pixel(x, y).0[0], motion.get_pixel(x, y).0[1]);
            if ds.iter().all(|d| *d == 0.0) {
                background_worst = background_worst.max(got.length());
                continue;
            }
            if ds.contains(&0.0) {
                continue;
            }
            let ndc = Vec2::new(
                (x as f32 + 0.5) / size.0 as f32 * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / size.1 as f32 * 2.0,
            );
            let h = world_from_clip * glam::Vec4::new(ndc.x, ndc.y, ds[4], 1.0);
            let now = h.truncate() / h.w;
            let local = m_after.inverse().transform_point3(now);
            let then = m_before.transform_point3(local);
            let want = to_pixel(now) - to_pixel(then);
            worst = worst.max((got - want).length());
            checked += 1;
        }
    }
    eprintln!(
        "{checked} cube pixels, worst error {worst:.4} px; background {background_worst:.4} px"
    );
    assert!(checked > 1000, "{checked} cube pixels");
    assert!(worst < 0.1, "worst motion error {worst} px");
    assert!(
        background_worst < 0.01,
        "background moved {background_worst} px"
    );
}

/// An emissive sphere in front of an emissive backdrop, TAA frame by frame; returns the
/// camera.
fn spawn_sphere_scene(app: &mut App) -> Entity {
    let ball = app.add_mesh(uv_sphere(0.6, 48, 24)).expect("mesh");
    let wall = app.add_mesh(plane(10.0, 10.0)).expect("mesh");
    taa_quality(app);
    let world = app.world_mut();
    world.spawn((
        Mesh3d(ball),
        Material {
            emissive: Vec3::new(1.0, 0.8, 0.3),
            ..Material::new(Vec3::ZERO, 0.0, 1.0)
        },
        Transform::IDENTITY,
    ));
    world.spawn((
        Mesh3d(wall),
        Material {
            emissive: Vec3::splat(0.1),
            ..Material::new(Vec3::ZERO, 0.0, 1.0)
        },
        Transform::from_translation(Vec3::new(0.0, 0.0, -1.0))
            .with_rotation(Quat::from_rotation_x(std::f32::consts::FRAC_PI_2)),
    ));
    camera_at(world, Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO)
}

/// [`spawn_sphere_scene`] in a headless app.
fn sphere_app() -> (App, Entity) {
    let mut app = App::headless().expect("a GPU adapter");
    let camera = spawn_sphere_scene(&mut app);
    (app, camera)
}

#[test]
fn a_camera_cut_and_a_resize_reset_the_history() {
    let size = (64, 64);
    let (mut fresh, _) = sphere_app();
    let report = fresh.render_headless(size).expect("frame");
    assert!(
        taa_reason(&report).contains("history reset"),
        "{}",
        taa_reason(&report)
    );
    let no_history = fresh.read_hdr_image().expect("hdr");

    let (mut app, camera) = sphere_app();
    for _ in 0..5 {
        app.render_headless(size).expect("frame");
    }
    let settled = taa_reason(&app.render_headless(size).expect("frame"));
    assert!(settled.contains("frame 6 since"), "{settled}");
    // A cut: the camera jumps elsewhere and back; the history must not be reprojected.
    app.world_mut().entity_mut(camera).insert(
        Transform::from_translation(Vec3::new(0.0, 0.0, 3.0)).looking_at(Vec3::ZERO, Vec3::Y),
    );
    app.camera_cut();
    let report = app.render_headless(size).expect("frame after the cut");
    assert!(
        taa_reason(&report).contains("camera cut"),
        "{}",
        taa_reason(&report)
    );
    let after_cut = app.read_hdr_image().expect("hdr");
    assert_eq!(
        after_cut.as_raw(),
        no_history.as_raw(),
        "the first frame after a cut equals a frame without history"
    );

    // A resize: the first frame at the new size has no history either.
    for _ in 0..3 {
        app.render_headless(size).expect("frame");
    }
    let report = app.render_headless((48, 48)).expect("resized frame");
    assert!(
        taa_reason(&report).contains("resized"),
        "{}",
        taa_reason(&report)
    );
    let resized = app.read_hdr_image().expect("hdr");
    let (mut small, _) = sphere_app();
    small.render_headless((48, 48)).expect("frame");
    assert_eq!(
        resized.as_raw(),
        small.read_hdr_image().expect("hdr").as_raw()
    );
}

#[test]
fn a_moving_sphere_leaves_no_trail() {
    // The sphere moves 8 px per frame to the right over 8 frames.
    let size = (128, 64);
    let (mut app, _) = sphere_app();
    let ball = {
        let world = app.world_mut();
        let mut q = world.query::<(Entity, &Material)>();
        q.iter(world)
            .find(|(_, m)| m.emissive.x == 1.0)
            .map(|(e, _)| e)
            .expect("the sphere")
    };
    // 3 m away with a 45° field of view: 64 px span 2 × 3 × tan 22.5° = 2.485 m.
    let metres_per_px = 2.0 * 3.0 * (22.5f32).to_radians().tan() / 64.0;
    let mut x = -1.5f32;
    for _ in 0..8 {
        app.world_mut()
            .entity_mut(ball)
            .insert(Transform::from_translation(Vec3::new(x, 0.0, 0.0)));
        app.render_headless(size).expect("frame");
        x += 8.0 * metres_per_px;
    }
    let with_history = app.read_hdr_image().expect("hdr");
    // The same frame without history (and so at the first jitter position).
    app.camera_cut();
    app.render_headless(size).expect("frame");
    let alone = app.read_hdr_image().expect("hdr");
    // The sphere's left edge on the middle row, in the frame without history.
    let row = size.1 / 2;
    let left = (0..size.0)
        .find(|&c| alone.get_pixel(c, row).0[0] > 0.5)
        .expect("the sphere is in view");
    let mut worst = 0.0f32;
    for y in row - 8..row + 8 {
        for c in 0..left.saturating_sub(2) {
            let d = with_history.get_pixel(c, y).0[0] - alone.get_pixel(c, y).0[0];
            worst = worst.max(d);
        }
    }
    eprintln!("sphere's left edge at x = {left}; brightest trail behind it: {worst:.4}");
    // The backdrop is 0.1 and the sphere 1.0: a trail of 0.05 is a twentieth of it.
    assert!(worst < 0.05, "trail {worst}");
}

/// Writes a NaN into one pixel of the lit frame (before TAA) while `on`.
#[derive(Resource)]
struct Poison {
    on: bool,
    nan: wgpu::Buffer,
}

/// Where the NaN goes.
const POISONED: (u32, u32) = (20, 20);

impl FramePass for Poison {
    const ID: PassId = PassId::new("poison");
    const READS: &'static [Slot] = &[HDR];
    const WRITES: &'static [Slot] = &[HDR];
    type Variant = ();

    fn create(_: &mut World, gpu: &Gpu) -> lumen::Result<Self> {
        // One f16 RGBA texel of NaNs (0x7e00), padded to a row of 256 bytes.
        let mut bytes = vec![0u8; 256];
        for c in 0..4 {
            bytes[2 * c..2 * c + 2].copy_from_slice(&0x7e00u16.to_le_bytes());
        }
        let nan = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("nan"),
            size: 256,
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue.write_buffer(&nan, 0, &bytes);
        Ok(Poison { on: false, nan })
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<()> {
        PassDecision::new(world.resource::<Poison>().on, "test", ())
    }

    fn record() -> ScheduleConfigs<ScheduleSystem> {
        poison.into_configs()
    }
}

fn poison(pass: Res<Poison>, targets: Res<RenderTargets>, mut encoder: ResMut<FrameEncoder>) {
    let (Some(encoder), Some(hdr)) = (
        encoder.encoder.as_mut(),
        targets.current.as_ref().and_then(|t| t.texture(HDR)),
    ) else {
        return;
    };
    encoder.copy_buffer_to_texture(
        wgpu::TexelCopyBufferInfo {
            buffer: &pass.nan,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(256),
                rows_per_image: None,
            },
        },
        wgpu::TexelCopyTextureInfo {
            texture: hdr,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: POISONED.0,
                y: POISONED.1,
                z: 0,
            },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
    );
}

#[test]
fn a_nan_in_the_lit_frame_never_reaches_the_history() {
    use lumen::render::post::antialias::{accumulate::AccumulatePass, taa::TaaPass};
    use lumen::render::{
        geometry::gbuffer::GBufferPass, indirect::depth_pyramid::DepthPyramidPass,
        indirect::gtao::AoPass, indirect::reflections::SsrPass,
        indirect::volume_irradiance::VolumeIrradiancePass, lighting::LightingPass,
        lighting::light_culling::LightCullingPass, lighting::sky::SkyPass,
        post::debug_view::DebugViewPass, post::dof::DofPass, post::exposure::ExposurePass,
        post::tonemap::TonemapPass, shadow::mask::ShadowMaskPass, shadow::pass::ShadowPass,
    };
    // The built-in frame with the poison between the sky and TAA.
    let registry = Registry::new()
        .with::<lumen::render::geometry::deform_pass::DeformPass>()
        .with::<ShadowPass>()
        .with::<GBufferPass>()
        .with::<AoPass>()
        .with::<DepthPyramidPass>()
        .with::<LightCullingPass>()
        .with::<ShadowMaskPass>()
        .with::<VolumeIrradiancePass>()
        .with::<LightingPass>()
        .with::<SsrPass>()
        .with::<SkyPass>()
        .with::<Poison>()
        .with::<AccumulatePass>()
        .with::<TaaPass>()
        .with::<ExposurePass>()
        .with::<DofPass>()
        .with::<TonemapPass>()
        .with::<DebugViewPass>()
        .ordered()
        .expect("registry");
    let mut app = App::new();
    app.world_mut().insert_resource(registry);
    app.attach_gpu(common::gpu()).expect("gpu");
    let size = (64, 64);
    let (mut reference, _) = sphere_app();
    // The same scene in the poisoned app.
    spawn_sphere_scene(&mut app);
    for _ in 0..4 {
        app.render_headless(size).expect("frame");
        reference.render_headless(size).expect("frame");
    }
    app.world_mut().resource_mut::<Poison>().on = true;
    let report = app.render_headless(size).expect("poisoned frame");
    reference.render_headless(size).expect("frame");
    assert!(report.plan.runs(PassId::new("poison")));
    common::assert_finite(&app);
    app.world_mut().resource_mut::<Poison>().on = false;
    app.render_headless(size).expect("next frame");
    reference.render_headless(size).expect("frame");
    common::assert_finite(&app);
    // The poisoned pixel's history was left out for one frame: within a few per cent of
    // the unpoisoned run.
    let got = app.read_hdr_image().expect("hdr");
    let want = reference.read_hdr_image().expect("hdr");
    let (g, w) = (
        got.get_pixel(POISONED.0, POISONED.1).0,
        want.get_pixel(POISONED.0, POISONED.1).0,
    );
    for c in 0..3 {
        assert!(
            (g[c] - w[c]).abs() <= 0.05 * w[c].abs().max(0.1),
            "{g:?} vs {w:?}"
        );
    }
}

/// A camera at the origin turned `yaw_deg` about +Y, under a sky of vertical stripes
/// (radiance 0.5 ± 0.5, 10 periods around the horizon, about 25 px apart at 64 px and
/// 90°) and no mesh: every pixel is background.
fn striped_sky_app(yaw_deg: f32) -> (App, Entity) {
    use lumen::scene::environment::EquirectImage;
    let mut app = App::headless().expect("a GPU adapter");
    common::indirect_off(&mut app);
    let (w, h) = (512u32, 256u32);
    let texels = (0..w * h)
        .map(|i| {
            let longitude = (i % w) as f32 / w as f32 * std::f32::consts::TAU;
            [0.5 + 0.5 * (10.0 * longitude).sin(); 3]
        })
        .collect();
    let sky = EquirectImage::from_texels(w, h, texels).expect("sky");
    let world = app.world_mut();
    world.spawn(Environment::image(std::sync::Arc::new(sky), 1.0));
    let camera = world
        .spawn((
            Camera {
                projection: Projection {
                    fov_y_rad: std::f32::consts::FRAC_PI_2,
                    ..Projection::default()
                },
                exposure: Exposure::Linear(1.0),
                tonemapper: lumen::shading::color::Tonemapper::None,
                ..Camera::default()
            },
            Transform::IDENTITY.with_rotation(Quat::from_rotation_y(yaw_deg.to_radians())),
        ))
        .id();
    (app, camera)
}

#[test]
fn a_turning_camera_reprojects_the_sky() {
    // The camera turns 3° (about 2 px) per frame for 12 frames. The sky is infinitely far:
    // its motion is the camera's rotation, which TAA derives from the view direction (the
    // G-buffer draws nothing there). Against 64 jittered renders at the last orientation
    // the TAA frame's mean error is measured 0.014; read in place (the sky's motion left
    // at 0), the history lags and it is 0.14. Without history it is 0.0012: what is left
    // is the softening of a history resampled bilinearly every frame.
    let size = (64u32, 64u32);
    let (steps, step_deg) = (12, 3.0f32);
    let (mut app, camera) = striped_sky_app(0.0);
    taa_quality(&mut app);
    for i in 0..=steps {
        app.world_mut().entity_mut(camera).insert(
            Transform::IDENTITY
                .with_rotation(Quat::from_rotation_y((i as f32 * step_deg).to_radians())),
        );
        app.render_headless(size).expect("frame");
    }
    let taa = app.read_hdr_image().expect("hdr");
    let last = steps as f32 * step_deg;
    let (mut fresh, _) = striped_sky_app(last);
    taa_quality(&mut fresh);
    fresh.render_headless(size).expect("frame");
    let no_history = fresh.read_hdr_image().expect("hdr");
    let (mut accumulated, _) = striped_sky_app(last);
    {
        let mut q = accumulated.world_mut().resource_mut::<Quality>();
        q.aa.method = AaMethod::None;
        q.aa.accumulate = 64;
    }
    accumulated.render_headless(size).expect("frame");
    let truth = accumulated.read_hdr_image().expect("hdr");
    let error = |img: &image::Rgba32FImage| {
        img.pixels()
            .zip(truth.pixels())
            .map(|(a, b)| (a.0[0] - b.0[0]).abs())
            .sum::<f32>()
            / (size.0 * size.1) as f32
    };
    let (taa, none) = (error(&taa), error(&no_history));
    eprintln!("sky after turning: TAA {taa:.4}, no history {none:.4}");
    assert!(none < 0.005, "no history: {none}");
    assert!(taa < 0.03, "TAA {taa} (no history {none})");
}

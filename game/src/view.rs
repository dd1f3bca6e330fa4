//! `lumen view`: the scene in a window with an orbit camera.
//!
//! Drag with the left mouse button to orbit, scroll to zoom, `S` saves a screenshot to
//! `out/`, `Esc` quits. Resizing (down to a minimised 0×0 window) and lost or outdated
//! surfaces are handled; errors end the viewer with a message, never a panic.

use crate::bench::report::FrameSample;
use crate::cli::ViewArgs;
use crate::setup::{build_scene, check_scene_args};
use anyhow::{Context, Result, anyhow};
use lumen::App;
use lumen::assets::image_io::{OutputFormat, save_exr, save_png};
use lumen::prelude::*;
use lumen::render::device::{Gpu, GpuRequest};
use lumen::wgpu;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

/// Whether a windowing system seems to be available.
pub fn display_available() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// An orbit camera around a target point.
#[derive(Clone, Copy, Debug)]
struct Orbit {
    target: Vec3,
    distance: f32,
    yaw: f32,
    pitch: f32,
}

impl Orbit {
    fn from_transform(t: &Transform, target: Vec3) -> Orbit {
        let offset = t.translation - target;
        let distance = offset.length().max(1e-3);
        Orbit {
            target,
            distance,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
        }
    }

    fn transform(&self) -> Transform {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        Transform::from_translation(self.target + dir * self.distance)
            .looking_at(self.target, Vec3::Y)
    }
}

struct Running {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    app: App,
    orbit: Orbit,
    camera: Entity,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    frames: u64,
    last_title: Instant,
}

/// A measured run in the window (`lumen bench --window`).
struct Measure {
    warmup: u32,
    frames: u32,
    samples: Vec<FrameSample>,
    seen: u32,
    last_start: Option<Instant>,
    pending: Option<FrameSample>,
    progress: Box<dyn FnMut(u32)>,
}

struct Viewer {
    args: ViewArgs,
    running: Option<Running>,
    error: Option<anyhow::Error>,
    screenshots: u32,
    measure: Option<Measure>,
}

/// Opens the viewer and runs until the window closes.
pub fn run(args: ViewArgs) -> Result<()> {
    check_scene_args(&args.scene)?;
    let event_loop = EventLoop::new().context("cannot open a window (no display?)")?;
    let mut viewer = Viewer {
        args,
        running: None,
        error: None,
        screenshots: 0,
        measure: None,
    };
    event_loop
        .run_app(&mut viewer)
        .context("window event loop")?;
    match viewer.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Renders `warmup + frames` frames into a window without vsync and returns the
/// measured frames and the app. A frame's time is the wall time from its start to the
/// next frame's start (update, record, submit, GPU, present). `progress(done)` is called
/// after every frame.
pub fn run_measured(
    args: ViewArgs,
    warmup: u32,
    frames: u32,
    progress: Box<dyn FnMut(u32)>,
) -> Result<(Vec<FrameSample>, App)> {
    check_scene_args(&args.scene)?;
    let event_loop = EventLoop::new().context("cannot open a window (no display?)")?;
    let mut viewer = Viewer {
        args,
        running: None,
        error: None,
        screenshots: 0,
        measure: Some(Measure {
            warmup,
            frames,
            samples: Vec::new(),
            seen: 0,
            last_start: None,
            pending: None,
            progress,
        }),
    };
    event_loop
        .run_app(&mut viewer)
        .context("window event loop")?;
    if let Some(e) = viewer.error {
        return Err(e);
    }
    let samples = viewer.measure.map(|m| m.samples).unwrap_or_default();
    let app = viewer
        .running
        .map(|r| r.app)
        .ok_or_else(|| anyhow!("the window never opened"))?;
    if samples.len() < frames as usize {
        return Err(anyhow!(
            "the window closed after {} of {frames} measured frames",
            samples.len()
        ));
    }
    Ok((samples, app))
}

fn pick_format(caps: &wgpu::SurfaceCapabilities) -> Option<wgpu::TextureFormat> {
    // A non-sRGB 8-bit format lets the tone mapping pass apply the exact sRGB curve.
    let preferred = [
        wgpu::TextureFormat::Bgra8Unorm,
        wgpu::TextureFormat::Rgba8Unorm,
    ];
    preferred
        .iter()
        .find(|f| caps.formats.contains(f))
        .copied()
        .or_else(|| caps.formats.first().copied())
}

impl Viewer {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<Running> {
        let (w, h) = self.args.size;
        let window = Arc::new(
            event_loop
                .create_window(
                    Window::default_attributes()
                        .with_title("lumen")
                        .with_inner_size(PhysicalSize::new(w, h)),
                )
                .context("cannot create a window")?,
        );
        let display = event_loop.owned_display_handle();
        let surface_window = window.clone();
        let (gpu, surface) = Gpu::new(
            &GpuRequest::from_env()?,
            Some(&move |instance: &wgpu::Instance| {
                instance
                    .create_surface(surface_window.clone())
                    .map_err(|e| e.to_string())
            }),
            Some(&move || Box::new(display.clone())),
        )?;
        let surface = surface.ok_or_else(|| anyhow!("no window surface"))?;
        let caps = surface.get_capabilities(&gpu.adapter);
        let format =
            pick_format(&caps).ok_or_else(|| anyhow!("the window surface supports no format"))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: if self.measure.is_some() {
                wgpu::PresentMode::AutoNoVsync
            } else {
                wgpu::PresentMode::AutoVsync
            },
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
            color_space: wgpu::SurfaceColorSpace::Auto,
        };
        surface.configure(&gpu.device, &config);
        eprintln!(
            "lumen view: {} ({}, {})",
            gpu.summary.name, gpu.summary.backend, gpu.summary.device_type
        );

        let mut app = App::new();
        app.attach_gpu(gpu)?;
        crate::progress::show_ibl_progress(&mut app);
        build_scene(&mut app, &self.args.scene)?;
        let world = app.world_mut();
        let mut cams = world.query::<(Entity, &Camera, &Transform)>();
        let (camera, transform) = cams
            .iter(world)
            .filter(|(_, c, _)| c.active)
            .min_by_key(|(e, _, _)| *e)
            .map(|(e, _, t)| (e, *t))
            .ok_or_else(|| anyhow!("the scene has no active camera"))?;
        let forward = transform.rotation * Vec3::NEG_Z;
        // Orbit around the point the camera looks at, at the distance of the origin.
        let target = transform.translation + forward * transform.translation.length().max(1.0);
        Ok(Running {
            window,
            surface,
            config,
            app,
            orbit: Orbit::from_transform(&transform, target),
            camera,
            dragging: false,
            cursor: None,
            frames: 0,
            last_title: Instant::now(),
        })
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error = Some(e);
        event_loop.exit();
    }

    fn screenshot(&mut self, path: &Path) -> Result<()> {
        let r = self.running.as_mut().ok_or_else(|| anyhow!("no window"))?;
        let size = (r.config.width, r.config.height);
        r.app.render_headless(size)?;
        match OutputFormat::from_path(path)? {
            OutputFormat::Png => save_png(path, &r.app.read_display_image()?)?,
            OutputFormat::Exr => save_exr(path, &r.app.read_hdr_image()?)?,
        }
        eprintln!("saved {}", path.display());
        Ok(())
    }
}

/// Draws one frame; returns its report and the ECS update time (ms), or `None` when no
/// frame could be drawn (minimised, surface lost).
fn redraw(r: &mut Running) -> Result<Option<(lumen::FrameReport, f64)>> {
    if r.config.width == 0 || r.config.height == 0 {
        return Ok(None);
    }
    if let Some(mut t) = r.app.world_mut().get_mut::<Transform>(r.camera) {
        *t = r.orbit.transform();
    }
    let update = Instant::now();
    r.app.update();
    let update_ms = update.elapsed().as_secs_f64() * 1e3;
    let frame = match r.surface.get_current_texture() {
        wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
        wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
            return Ok(None);
        }
        wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
            let gpu = r.app.world().resource::<Gpu>().clone();
            r.surface.configure(&gpu.device, &r.config);
            return Ok(None);
        }
        wgpu::CurrentSurfaceTexture::Validation => {
            return Err(anyhow!("the window surface reported a validation error"));
        }
    };
    let view = frame
        .texture
        .create_view(&wgpu::TextureViewDescriptor::default());
    let report = r.app.render_to_view(
        Some(view),
        r.config.format,
        (r.config.width, r.config.height),
    )?;
    r.window.pre_present_notify();
    r.app.world().resource::<Gpu>().queue.present(frame);
    r.frames += 1;
    if r.last_title.elapsed().as_secs_f32() > 0.5 {
        r.window
            .set_title(&format!("lumen — {:.1} ms/frame", report.frame_ms));
        r.last_title = Instant::now();
    }
    Ok(Some((report, update_ms)))
}

impl Measure {
    /// Records a frame that started at `start`; the previous frame's time ends here.
    /// Returns true once every measured frame is in.
    fn frame(&mut self, start: Instant, report: lumen::FrameReport, update_ms: f64) -> bool {
        if let (Some(last), Some(mut sample)) = (self.last_start, self.pending.take()) {
            sample.frame_ms = start.duration_since(last).as_secs_f64() * 1e3;
            self.samples.push(sample);
        }
        self.seen += 1;
        (self.progress)(self.seen);
        self.last_start = Some(start);
        if self.seen > self.warmup {
            let mut stages = vec![("update", update_ms)];
            stages.extend(report.stages);
            self.pending = Some(FrameSample {
                frame_ms: 0.0,
                stages,
                passes: report.passes,
            });
        }
        // One frame more than measured closes the last measured frame's interval.
        self.samples.len() >= self.frames as usize
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.start(event_loop) {
            Ok(r) => {
                r.window.request_redraw();
                self.running = Some(r);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else {
            return;
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                r.config.width = size.width;
                r.config.height = size.height;
                if size.width > 0 && size.height > 0 {
                    let gpu = r.app.world().resource::<Gpu>().clone();
                    r.surface.configure(&gpu.device, &r.config);
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                match event.logical_key {
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    Key::Character(c) if c.eq_ignore_ascii_case("s") => {
                        self.screenshots += 1;
                        let path =
                            PathBuf::from(format!("out/screenshot-{}.png", self.screenshots));
                        if let Err(e) = self.screenshot(&path) {
                            eprintln!("screenshot failed: {e:#}");
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => r.dragging = state == ElementState::Pressed,
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y))) = (r.dragging, r.cursor) {
                    r.orbit.yaw -= ((position.x - x) * 0.005) as f32;
                    r.orbit.pitch =
                        (r.orbit.pitch + ((position.y - y) * 0.005) as f32).clamp(-1.5, 1.5);
                }
                r.cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                r.orbit.distance = (r.orbit.distance * 0.9f32.powf(steps)).clamp(0.05, 1e4);
            }
            WindowEvent::RedrawRequested => {
                let start = Instant::now();
                match redraw(r) {
                    Err(e) => {
                        self.fail(event_loop, e);
                        return;
                    }
                    Ok(Some((report, update_ms))) => {
                        if let Some(m) = self.measure.as_mut()
                            && m.frame(start, report, update_ms)
                        {
                            event_loop.exit();
                        }
                    }
                    Ok(None) => {}
                }
                if self.args.frames.is_some_and(|n| r.frames >= n) {
                    event_loop.exit();
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if self.error.is_none()
            && let Some(path) = self.args.screenshot.clone()
            && let Err(e) = self.screenshot(&path)
        {
            self.error = Some(e);
        }
    }
}

//! The viewer's window loop: one window, its GPU and surface, the app rendered into it
//! every frame with the panel on top, input, a lost device replaced, and frames measured
//! for `lumen bench --window`.

use super::controls::CameraControls;
use super::gui::Gui;
use super::open::open_file;
use super::panel::{Action, Panel};
use super::screenshot::screenshot;
use super::surface::{clear, configure, window_gpu};
use super::watch::ShaderWatcher;
use crate::cli::ViewArgs;
use crate::measure::{FrameSample, WindowFrames};
use crate::setup::build_scene;
use anyhow::{Context, Result, anyhow};
use lumen::App;
use lumen::input::InputEvent;
use lumen::prelude::*;
use lumen::render::device::Gpu;
use lumen::wgpu;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// Lines of text your systems want on screen (controls, a score, a state), drawn by
/// the viewer in the window's top-right corner, over the frame, whether the panel is
/// shown or hidden (`Tab`); not with [`WindowOptions::panel`] off (no egui at all), and
/// not in headless images. Insert it as a resource and write its lines from a system.
#[derive(Resource, Clone, Debug, Default, PartialEq, Eq)]
pub struct ScreenText {
    /// One entry per line, top to bottom.
    pub lines: Vec<String>,
}

/// Whether a windowing system seems to be available.
pub fn display_available() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// How [`show`] presents an app.
#[derive(Clone, Debug)]
pub struct WindowOptions {
    /// Window title.
    pub title: String,
    /// Initial size in pixels.
    pub size: (u32, u32),
    /// Show the egui panel (`Tab` toggles it).
    pub panel: bool,
    /// Folder of WGSL files to reload when they change; `None`: no hot reload.
    pub shader_dir: Option<PathBuf>,
    /// Close after this many frames.
    pub frames: Option<u64>,
    /// Save a screenshot (PNG or EXR by extension) when the window closes.
    pub screenshot: Option<PathBuf>,
    /// Test hook: destroy the GPU device after this many frames (the viewer recovers).
    pub lose_device_after: Option<u64>,
    /// The viewer's own keys and mouse: the camera (drag, wheel, `W A S D Q E`, `Shift`,
    /// `F`), `P`/`F12` screenshot, `R` reload and `Esc` close. Off, they are left to your
    /// systems (which see every event either way, through [`lumen::input`]); `Tab`
    /// still shows and hides the panel.
    pub viewer_keys: bool,
}

impl Default for WindowOptions {
    /// 1280×720, panel on, hot reload from [`default_shader_dir`].
    fn default() -> Self {
        WindowOptions {
            title: "lumen".into(),
            size: (1280, 720),
            panel: true,
            shader_dir: default_shader_dir(),
            frames: None,
            screenshot: None,
            lose_device_after: None,
            viewer_keys: true,
        }
    }
}

/// `shaders/` of the working directory if it holds Lumen's WGSL, else that of the
/// source tree this binary was built from, if it still exists.
pub fn default_shader_dir() -> Option<PathBuf> {
    let here = PathBuf::from("shaders");
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders");
    [here, built]
        .into_iter()
        .find(|d| d.join("tonemap.wgsl").is_file())
}

/// Opens a window on `app` and runs it until the window closes: every frame runs the
/// app's [`Update`] systems, renders, and draws the panel. `app` must not have a GPU yet
/// (make it with [`App::new`]): the window picks an adapter that can present to it.
pub fn show(app: App, options: WindowOptions) -> Result<()> {
    if app.adapter().is_some() {
        return Err(anyhow!(
            "lumen_game::view::show needs an App without a GPU (App::new()), not App::headless()"
        ));
    }
    run_window(WindowScene::Ready(Box::new(app)), options, None).map(|_| ())
}

/// Opens a window on `scene` and runs it until it closes; with `measure`, without vsync,
/// measuring frames until all are in. Returns the measured frames (none without
/// `measure`) and the app, if the window opened.
pub(crate) fn run_window(
    scene: WindowScene,
    options: WindowOptions,
    measure: Option<WindowFrames>,
) -> Result<(Vec<FrameSample>, Option<App>)> {
    let event_loop = EventLoop::new().context("cannot open a window (no display?)")?;
    let mut viewer = Viewer {
        scene: Some(scene),
        options,
        running: None,
        error: None,
        measure,
    };
    event_loop
        .run_app(&mut viewer)
        .context("window event loop")?;
    if let Some(e) = viewer.error {
        return Err(e);
    }
    let samples = viewer
        .measure
        .map(WindowFrames::into_samples)
        .unwrap_or_default();
    Ok((samples, viewer.running.map(|r| r.app)))
}

/// Where the window's scene comes from.
pub(crate) enum WindowScene {
    /// Built from the command line once the GPU exists.
    Args(Box<ViewArgs>),
    /// A script's app, GPU attached by the window.
    Ready(Box<App>),
}

struct Running {
    /// Test hook: destroy the device once this many frames were drawn.
    lose_device_after: Option<u64>,
    /// [`WindowOptions::viewer_keys`].
    viewer_keys: bool,
    window: Arc<Window>,
    display: winit::event_loop::OwnedDisplayHandle,
    /// `None` only while a lost device is being replaced.
    surface: Option<wgpu::Surface<'static>>,
    config: wgpu::SurfaceConfiguration,
    app: App,
    camera: Entity,
    controls: CameraControls,
    gui: Option<Gui>,
    panel: Panel,
    watcher: Option<ShaderWatcher>,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    frames: u64,
    screenshots: u32,
    last_title: Instant,
    last_frame: Instant,
}

impl Running {
    /// Saves the current view at the window's size: as `path`, or as the next
    /// `out/screenshot-N.png` and `.exr`. Returns the log line.
    fn screenshot(&mut self, path: Option<&Path>) -> Result<String> {
        let size = (self.config.width.max(1), self.config.height.max(1));
        screenshot(&mut self.app, size, path, &mut self.screenshots)
    }
}

struct Viewer {
    scene: Option<WindowScene>,
    options: WindowOptions,
    running: Option<Running>,
    error: Option<anyhow::Error>,
    measure: Option<WindowFrames>,
}

/// After the device was lost: a new GPU, surface and panel renderer, and the app's
/// renderer rebuilt on them (the scene is kept). Returns the log line.
fn recover_device(r: &mut Running, reason: &str) -> Result<String> {
    // The old surface goes first: GL gives a window one surface at a time.
    r.surface = None;
    let (gpu, surface, config) = window_gpu(&r.window, &r.display, r.config.present_mode)?;
    if r.gui.is_some() {
        r.gui = Some(Gui::new(&r.window, &gpu.device, config.format));
    }
    let line = format!(
        "the GPU device was lost ({reason}); recreated it on {} ({})",
        gpu.summary.name, gpu.summary.backend
    );
    r.surface = Some(surface);
    r.config = config;
    r.app.attach_gpu(gpu)?;
    crate::progress::show_ibl_progress(&mut r.app);
    Ok(line)
}

/// The active camera with the lowest entity id, and controls that start at it, orbiting
/// the point it looks at (at the distance of the origin).
fn find_camera(app: &mut App) -> Result<(Entity, CameraControls)> {
    let world = app.world_mut();
    let mut cams = world.query::<(Entity, &Camera, &Transform)>();
    let (camera, transform) = cams
        .iter(world)
        .filter(|(_, c, _)| c.active)
        .min_by_key(|(e, _, _)| *e)
        .map(|(e, _, t)| (e, *t))
        .ok_or_else(|| anyhow!("the scene has no active camera"))?;
    let distance = transform.translation.length().max(1.0);
    Ok((camera, CameraControls::new(&transform, distance)))
}

impl Viewer {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<Running> {
        let (w, h) = self.options.size;
        let window = Arc::new(
            event_loop
                .create_window(
                    Window::default_attributes()
                        .with_title(self.options.title.clone())
                        .with_inner_size(PhysicalSize::new(w, h)),
                )
                .context("cannot create a window")?,
        );
        let display = event_loop.owned_display_handle();
        let present_mode = if self.measure.is_some() {
            wgpu::PresentMode::AutoNoVsync
        } else {
            wgpu::PresentMode::AutoVsync
        };
        let (gpu, surface, config) = window_gpu(&window, &display, present_mode)?;
        let adapter = format!(
            "{} ({}, {})",
            gpu.summary.name, gpu.summary.backend, gpu.summary.device_type
        );
        eprintln!("lumen view: {adapter}");
        let gui = self
            .options
            .panel
            .then(|| Gui::new(&window, &gpu.device, config.format));

        let mut panel = Panel::new(adapter);
        let (mut app, open) = match self.scene.take() {
            Some(WindowScene::Ready(app)) => {
                let mut app = *app;
                app.set_progressive_probes(true);
                app.set_progressive_taa(true);
                (app, Vec::new())
            }
            Some(WindowScene::Args(args)) => {
                let mut app = App::new();
                app.attach_gpu(gpu.clone())?;
                app.set_progressive_probes(true);
                app.set_progressive_taa(true);
                build_scene(&mut app, &args.scene)?;
                (app, args.open.clone())
            }
            None => return Err(anyhow!("the window was started twice")),
        };
        if app.adapter().is_none() {
            app.attach_gpu(gpu)?;
        }
        crate::progress::show_ibl_progress(&mut app);
        for path in &open {
            match open_file(&mut app, path) {
                Ok(line) => panel.message(line),
                Err(e) => panel.set_error(format!("{e:#}")),
            }
        }
        for line in super::animation_panel::animation_lines(app.world_mut()) {
            eprintln!("lumen view: {line}");
        }
        let (camera, controls) = find_camera(&mut app)?;
        let watcher = self
            .options
            .shader_dir
            .clone()
            .map(|d| ShaderWatcher::new(d, Duration::from_millis(500)));
        if let Some(w) = &watcher {
            // Files already edited before the start count too.
            reload_shaders(&mut app, &mut panel, w.dir());
        }
        Ok(Running {
            lose_device_after: self.options.lose_device_after,
            viewer_keys: self.options.viewer_keys,
            window,
            display: event_loop.owned_display_handle(),
            surface: Some(surface),
            config,
            app,
            camera,
            controls,
            gui,
            panel,
            watcher,
            dragging: false,
            cursor: None,
            frames: 0,
            screenshots: 0,
            last_title: Instant::now(),
            last_frame: Instant::now(),
        })
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error = Some(e);
        event_loop.exit();
    }
}

/// Reloads the WGSL in `dir`, reporting the result in the panel.
fn reload_shaders(app: &mut App, panel: &mut Panel, dir: &Path) {
    match app.reload_shaders(dir) {
        Ok(changed) if changed.is_empty() => {}
        Ok(changed) => {
            panel.clear_error();
            panel.message(format!("reloaded {}", changed.join(", ")));
        }
        Err(e) => panel.set_error(format!("shader reload: {e}")),
    }
}

/// Draws one frame; returns its report and the ECS update time (ms), or `None` when no
/// frame was drawn (minimised, surface lost, or the scene failed: then the panel shows
/// the error).
fn redraw(r: &mut Running) -> Result<Option<(lumen::FrameReport, f64)>> {
    if r.config.width == 0 || r.config.height == 0 {
        return Ok(None);
    }
    let dt = r.last_frame.elapsed().as_secs_f32();
    r.last_frame = Instant::now();
    if let Some(w) = r.watcher.as_mut()
        && w.changed()
    {
        let dir = w.dir().to_path_buf();
        reload_shaders(&mut r.app, &mut r.panel, &dir);
    }
    r.controls.advance(dt);
    if let Some(t) = r.controls.take_transform()
        && let Some(mut camera) = r.app.world_mut().get_mut::<Transform>(r.camera)
    {
        *camera = t;
    }

    let mut actions = Vec::new();
    let ui_output = match r.gui.as_mut() {
        Some(gui) => {
            let (panel, app, controls, camera) =
                (&mut r.panel, &mut r.app, &mut r.controls, r.camera);
            Some(gui.run(&r.window, |ui| {
                panel.ui(ui, app, camera, controls, &mut actions);
                screen_text_ui(ui, app);
            }))
        }
        None => None,
    };

    let update = Instant::now();
    r.app.update();
    let update_ms = update.elapsed().as_secs_f64() * 1e3;
    let Some(surface) = r.surface.as_ref() else {
        return Ok(None);
    };
    let frame = match surface.get_current_texture() {
        wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
        wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
            return Ok(None);
        }
        wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
            let gpu = r.app.world().resource::<Gpu>().clone();
            configure(&gpu, surface, &r.config)?;
            return Ok(None);
        }
        wgpu::CurrentSurfaceTexture::Validation => {
            return Err(anyhow!("the window surface reported a validation error"));
        }
    };
    let view = frame
        .texture
        .create_view(&wgpu::TextureViewDescriptor::default());
    let size = (r.config.width, r.config.height);
    let gpu = r.app.world().resource::<Gpu>().clone();
    if r.lose_device_after.is_some_and(|n| r.frames >= n) {
        r.lose_device_after = None;
        gpu.device.destroy();
    }
    let result = r
        .app
        .render_to_view(Some(view.clone()), r.config.format, size);
    if result.is_err()
        && let Some(reason) = gpu.poll_lost()
    {
        drop(view);
        drop(frame);
        match recover_device(r, &reason) {
            Ok(line) => r.panel.message(line),
            Err(e) => {
                return Err(anyhow!(
                    "the GPU device was lost ({reason}) and a new one could not be made: {e:#}"
                ));
            }
        }
        return Ok(None);
    }
    let report = match result {
        Ok(report) => Some(report),
        Err(e) => {
            r.panel.set_error(format!("{e:#}"));
            clear(&gpu, &view);
            None
        }
    };
    if let (Some(gui), Some(output)) = (r.gui.as_mut(), ui_output) {
        gui.paint(&r.window, &gpu.device, &gpu.queue, &view, size, output);
    }
    r.window.pre_present_notify();
    gpu.queue.present(frame);
    r.frames += 1;

    for action in actions {
        act(r, action);
    }
    let Some(report) = report else {
        return Ok(None);
    };
    r.panel.frame(report.clone(), f64::from(dt) * 1e3);
    if r.last_title.elapsed().as_secs_f32() > 0.5 {
        r.window
            .set_title(&format!("lumen — {:.1} ms/frame", report.frame_ms));
        r.last_title = Instant::now();
    }
    Ok(Some((report, update_ms)))
}

/// Carries out a panel button or its key, reporting in the panel.
fn act(r: &mut Running, action: Action) {
    match action {
        Action::Screenshot => match r.screenshot(None) {
            Ok(line) => r.panel.message(line),
            Err(e) => r.panel.set_error(format!("screenshot: {e:#}")),
        },
        Action::ReloadShaders => match r.watcher.as_ref().map(|w| w.dir().to_path_buf()) {
            Some(dir) => reload_shaders(&mut r.app, &mut r.panel, &dir),
            None => r
                .panel
                .set_error("no shader folder is watched (--shaders DIR)".into()),
        },
    }
}

/// The app's view of a window event: key and button presses the panel took are not
/// passed on (their releases are, so nothing stays held), nor is the wheel over it.
fn input_event(event: &WindowEvent, used_by_panel: bool) -> Option<InputEvent> {
    match event {
        WindowEvent::KeyboardInput { event, .. } if !event.repeat => match event.physical_key {
            PhysicalKey::Code(code) => {
                let pressed = event.state == ElementState::Pressed;
                (!pressed || !used_by_panel).then_some(InputEvent::Key { code, pressed })
            }
            PhysicalKey::Unidentified(_) => None,
        },
        WindowEvent::MouseInput { state, button, .. } => {
            let pressed = *state == ElementState::Pressed;
            (!pressed || !used_by_panel).then_some(InputEvent::MouseButton {
                button: *button,
                pressed,
            })
        }
        WindowEvent::CursorMoved { position, .. } => Some(InputEvent::CursorMoved(Vec2::new(
            position.x as f32,
            position.y as f32,
        ))),
        WindowEvent::CursorLeft { .. } => Some(InputEvent::CursorLeft),
        WindowEvent::MouseWheel { delta, .. } if !used_by_panel => {
            Some(InputEvent::Wheel(match delta {
                MouseScrollDelta::LineDelta(x, y) => Vec2::new(*x, *y),
                MouseScrollDelta::PixelDelta(p) => Vec2::new(p.x as f32, p.y as f32) / 40.0,
            }))
        }
        WindowEvent::Focused(false) => Some(InputEvent::FocusLost),
        _ => None,
    }
}

/// Whether the viewer itself would act on `event` (keys, mouse buttons, the cursor's
/// drag, the wheel): [`WindowOptions::viewer_keys`] off leaves these to the app.
fn viewer_input(event: &WindowEvent) -> bool {
    matches!(
        event,
        WindowEvent::KeyboardInput { .. }
            | WindowEvent::MouseInput { .. }
            | WindowEvent::CursorMoved { .. }
            | WindowEvent::MouseWheel { .. }
    )
}

/// Draws the [`ScreenText`] your systems wrote in the window's top-right corner.
fn screen_text_ui(ui: &mut egui::Ui, app: &App) {
    let Some(text) = app.world().get_resource::<ScreenText>() else {
        return;
    };
    if text.lines.is_empty() {
        return;
    }
    egui::Area::new(egui::Id::unique("lumen screen text"))
        .anchor(egui::Align2::RIGHT_TOP, egui::vec2(-8.0, 8.0))
        .show(ui.ctx(), |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                for line in &text.lines {
                    ui.monospace(line);
                }
            });
        });
}

/// Keyboard input outside the panel. Returns true when the viewer should close.
fn key(r: &mut Running, code: KeyCode, pressed: bool) -> bool {
    let k = &mut r.controls.keys;
    match code {
        KeyCode::KeyW => k.forward = pressed,
        KeyCode::KeyS => k.back = pressed,
        KeyCode::KeyA => k.left = pressed,
        KeyCode::KeyD => k.right = pressed,
        KeyCode::KeyE => k.up = pressed,
        KeyCode::KeyQ => k.down = pressed,
        KeyCode::ShiftLeft | KeyCode::ShiftRight => k.fast = pressed,
        _ if !pressed => {}
        KeyCode::Escape => return true,
        KeyCode::KeyF => r.controls.toggle_mode(),
        KeyCode::KeyP | KeyCode::F12 => act(r, Action::Screenshot),
        KeyCode::KeyR => act(r, Action::ReloadShaders),
        _ => {}
    }
    false
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
        // Tab shows and hides the panel whatever has the keyboard (egui would take it
        // for focus navigation).
        if let WindowEvent::KeyboardInput { event: k, .. } = &event
            && k.physical_key == PhysicalKey::Code(KeyCode::Tab)
        {
            if k.state == ElementState::Pressed && !k.repeat {
                r.panel.visible = !r.panel.visible;
            }
            return;
        }
        let used_by_panel = match r.gui.as_mut() {
            Some(gui) if r.panel.visible => gui.on_event(&r.window, &event),
            _ => false,
        };
        if let Some(input) = input_event(&event, used_by_panel) {
            r.app.send_input(input);
        }
        if !r.viewer_keys && viewer_input(&event) {
            return;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                r.config.width = size.width;
                r.config.height = size.height;
                let gpu = r.app.world().resource::<Gpu>().clone();
                if let Some(surface) = r.surface.as_ref()
                    && let Err(e) = configure(&gpu, surface, &r.config)
                {
                    self.fail(event_loop, e);
                }
            }
            WindowEvent::DroppedFile(path) => match open_file(&mut r.app, &path) {
                Ok(line) => {
                    r.panel.message(line);
                    match find_camera(&mut r.app) {
                        Ok((camera, controls)) => (r.camera, r.controls) = (camera, controls),
                        Err(e) => r.panel.set_error(format!("{e:#}")),
                    }
                }
                Err(e) => r.panel.set_error(format!("{e:#}")),
            },
            WindowEvent::KeyboardInput { event, .. } if !used_by_panel => {
                if let PhysicalKey::Code(code) = event.physical_key
                    && key(r, code, event.state == ElementState::Pressed)
                {
                    event_loop.exit();
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => r.dragging = state == ElementState::Pressed && !used_by_panel,
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y))) = (r.dragging, r.cursor) {
                    r.controls
                        .drag((position.x - x) as f32, (position.y - y) as f32);
                }
                r.cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } if !used_by_panel => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                r.controls.scroll(steps);
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
                if self.options.frames.is_some_and(|n| r.frames >= n) {
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
            && let Some(path) = self.options.screenshot.clone()
            && let Some(r) = self.running.as_mut()
        {
            match r.screenshot(Some(&path)) {
                Ok(line) => eprintln!("{line}"),
                Err(e) => self.error = Some(e),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use winit::dpi::PhysicalPosition;
    use winit::event::{DeviceId, TouchPhase};

    const DEVICE: DeviceId = DeviceId::dummy();

    fn button(state: ElementState) -> WindowEvent {
        WindowEvent::MouseInput {
            device_id: DEVICE,
            state,
            button: MouseButton::Left,
        }
    }

    fn wheel(delta: MouseScrollDelta) -> WindowEvent {
        WindowEvent::MouseWheel {
            device_id: DEVICE,
            delta,
            phase: TouchPhase::Moved,
        }
    }

    #[test]
    fn window_events_become_the_apps_input_unless_the_panel_took_them() {
        let press = button(ElementState::Pressed);
        let release = button(ElementState::Released);
        let down = InputEvent::MouseButton {
            button: MouseButton::Left,
            pressed: true,
        };
        let up = InputEvent::MouseButton {
            button: MouseButton::Left,
            pressed: false,
        };
        assert_eq!(input_event(&press, false), Some(down));
        // A press on the panel is the panel's; its release still reaches the app, so
        // nothing stays held.
        assert_eq!(input_event(&press, true), None);
        assert_eq!(input_event(&release, true), Some(up));
        let lines = wheel(MouseScrollDelta::LineDelta(0.0, 2.0));
        assert_eq!(
            input_event(&lines, false),
            Some(InputEvent::Wheel(Vec2::new(0.0, 2.0)))
        );
        assert_eq!(input_event(&lines, true), None);
        // Pixels of a touchpad count 40 to a line.
        let pixels = wheel(MouseScrollDelta::PixelDelta(PhysicalPosition::new(
            20.0, -80.0,
        )));
        assert_eq!(
            input_event(&pixels, false),
            Some(InputEvent::Wheel(Vec2::new(0.5, -2.0)))
        );
        let moved = WindowEvent::CursorMoved {
            device_id: DEVICE,
            position: PhysicalPosition::new(12.5, 30.0),
        };
        // The cursor's position is followed over the panel too.
        assert_eq!(
            input_event(&moved, true),
            Some(InputEvent::CursorMoved(Vec2::new(12.5, 30.0)))
        );
        assert_eq!(
            input_event(&WindowEvent::CursorLeft { device_id: DEVICE }, false),
            Some(InputEvent::CursorLeft)
        );
        assert_eq!(
            input_event(&WindowEvent::Focused(false), false),
            Some(InputEvent::FocusLost)
        );
        assert_eq!(input_event(&WindowEvent::Focused(true), false), None);
        assert_eq!(input_event(&WindowEvent::RedrawRequested, false), None);
    }

    #[test]
    fn the_viewer_acts_on_keys_buttons_the_cursor_and_the_wheel_only() {
        assert!(viewer_input(&button(ElementState::Pressed)));
        assert!(viewer_input(&wheel(MouseScrollDelta::LineDelta(0.0, 1.0))));
        assert!(viewer_input(&WindowEvent::CursorMoved {
            device_id: DEVICE,
            position: PhysicalPosition::new(1.0, 1.0),
        }));
        assert!(!viewer_input(&WindowEvent::Focused(false)));
        assert!(!viewer_input(&WindowEvent::CursorLeft {
            device_id: DEVICE
        }));
        assert!(!viewer_input(&WindowEvent::Resized(PhysicalSize::new(
            8, 8
        ))));
    }
}

//! The viewer's panel (egui): frame time, per-pass timings, debug views, every quality
//! knob and preset, the camera's exposure and depth of field, and the lights.

use super::animation_panel::animation_ui;
use super::controls::{CameraControls, CameraMode};
use super::knob_panel::quality_ui;
use lumen::choice::Choice;
use lumen::prelude::*;
use lumen::scene::{AutoExposure, Vignette};
use lumen::shading::color::Tonemapper;
use lumen::{App, FrameReport};
use std::collections::VecDeque;

/// Frames kept for the frame-time graph.
const HISTORY: usize = 240;
/// Lights of each kind listed with controls.
const LISTED_LIGHTS: usize = 8;

/// What the panel asks the viewer to do after the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Save a PNG and an EXR of the current view.
    Screenshot,
    /// Reload the WGSL in the shader folder now.
    ReloadShaders,
}

/// The panel's own state.
pub struct Panel {
    /// Shown or hidden (`Tab`).
    pub visible: bool,
    history: VecDeque<f32>,
    last: Option<FrameReport>,
    /// The error shown (a failed frame, a shader that does not compile, a bad file).
    error: Option<String>,
    log: VecDeque<String>,
    adapter: String,
}

impl Panel {
    /// An empty panel for `adapter` (shown in its title).
    pub fn new(adapter: String) -> Panel {
        Panel {
            visible: true,
            history: VecDeque::with_capacity(HISTORY),
            last: None,
            error: None,
            log: VecDeque::new(),
            adapter,
        }
    }

    /// Records a frame's report and its wall time (ms, start to start).
    pub fn frame(&mut self, report: FrameReport, wall_ms: f64) {
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(wall_ms as f32);
        self.last = Some(report);
    }

    /// Shows `message` as the current error; printed on stderr when it is new.
    pub fn set_error(&mut self, message: String) {
        if self.error.as_deref() != Some(message.as_str()) {
            eprintln!("lumen view: {message}");
        }
        self.error = Some(message);
    }

    /// Clears the current error.
    pub fn clear_error(&mut self) {
        self.error = None;
    }

    /// Adds a line to the message log (also printed on stderr).
    pub fn message(&mut self, line: String) {
        eprintln!("{line}");
        if self.log.len() == 6 {
            self.log.pop_front();
        }
        self.log.push_back(line);
    }

    /// The panel's UI for this frame.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        app: &mut App,
        camera: Entity,
        controls: &mut CameraControls,
        actions: &mut Vec<Action>,
    ) {
        if !self.visible {
            return;
        }
        egui::Panel::left("lumen panel")
            .resizable(true)
            .default_size(330.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.heading("lumen");
                    ui.label(&self.adapter);
                    self.errors_ui(ui);
                    egui::CollapsingHeader::new("Frame")
                        .default_open(true)
                        .show(ui, |ui| self.timing_ui(ui));
                    egui::CollapsingHeader::new("View")
                        .default_open(true)
                        .show(ui, |ui| view_ui(ui, app, controls, actions));
                    egui::CollapsingHeader::new("Quality")
                        .default_open(false)
                        .show(ui, |ui| {
                            // Written back only when a knob moved: a write marks the
                            // quality changed, which recaptures probes and resets TAA.
                            let world = app.world();
                            let next = quality_ui(
                                ui,
                                world.resource::<lumen::quality::Knobs>(),
                                world.resource::<Quality>(),
                            );
                            if let Some(q) = next {
                                *app.world_mut().resource_mut::<Quality>() = q;
                            }
                        });
                    egui::CollapsingHeader::new("Camera")
                        .default_open(true)
                        .show(ui, |ui| {
                            let metered = self.last.as_ref().map(|r| r.ev100);
                            if let Some(before) = app.world().get::<Camera>(camera).copied() {
                                let mut c = before;
                                camera_ui(ui, &mut c, metered);
                                if c != before
                                    && let Some(mut stored) =
                                        app.world_mut().get_mut::<Camera>(camera)
                                {
                                    *stored = c;
                                }
                            }
                        });
                    egui::CollapsingHeader::new("Lights")
                        .default_open(false)
                        .show(ui, |ui| lights_ui(ui, app.world_mut()));
                    let world = app.world_mut();
                    if world
                        .query::<&AnimationPlayer>()
                        .iter(world)
                        .next()
                        .is_some()
                    {
                        egui::CollapsingHeader::new("Animation")
                            .default_open(true)
                            .show(ui, |ui| animation_ui(ui, world));
                    }
                });
            });
    }

    fn errors_ui(&mut self, ui: &mut egui::Ui) {
        if let Some(e) = &self.error {
            ui.separator();
            ui.colored_label(egui::Color32::from_rgb(255, 90, 90), e);
            if ui.button("dismiss").clicked() {
                self.error = None;
            }
        }
        for line in &self.log {
            ui.small(line);
        }
        ui.separator();
    }

    fn timing_ui(&self, ui: &mut egui::Ui) {
        let mut sorted: Vec<f32> = self.history.iter().copied().collect();
        sorted.sort_by(f32::total_cmp);
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        let worst = sorted.last().copied().unwrap_or(0.0);
        ui.label(format!(
            "frame {median:.1} ms median, {worst:.1} ms worst (last {} frames)",
            sorted.len()
        ));
        frame_graph(ui, &self.history, worst);
        let Some(report) = &self.last else {
            return;
        };
        egui::Grid::new("passes").striped(true).show(ui, |ui| {
            ui.strong("pass");
            ui.strong("GPU ms");
            ui.strong("CPU ms");
            ui.end_row();
            for p in &report.passes {
                ui.label(p.name);
                ui.label(p.gpu_ms.map_or("–".into(), |g| format!("{g:.2}")));
                ui.label(format!("{:.2}", p.cpu_ms));
                ui.end_row();
            }
            for (name, ms) in &report.stages {
                ui.label(format!("({name})"));
                ui.label("");
                ui.label(format!("{ms:.2}"));
                ui.end_row();
            }
        });
        let s = report.stats;
        ui.small(format!(
            "{} instances, {} draws, {} triangles, {} lights; EV100 {:.2}",
            s.instances, s.draws, s.triangles, s.lights, report.ev100
        ));
    }
}

/// The last frame times as a line graph, scaled to the worst.
fn frame_graph(ui: &mut egui::Ui, history: &VecDeque<f32>, worst: f32) {
    let width = ui.available_width().max(100.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 60.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(24));
    if history.len() < 2 || worst <= 0.0 {
        return;
    }
    let scale = worst * 1.1;
    let points: Vec<egui::Pos2> = history
        .iter()
        .enumerate()
        .map(|(i, ms)| {
            egui::pos2(
                rect.left() + rect.width() * i as f32 / (HISTORY - 1) as f32,
                rect.bottom() - rect.height() * (ms / scale).clamp(0.0, 1.0),
            )
        })
        .collect();
    painter.add(egui::Shape::line(
        points,
        egui::Stroke::new(1.5, egui::Color32::from_rgb(120, 200, 255)),
    ));
    painter.text(
        rect.left_top() + egui::vec2(4.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{scale:.1} ms"),
        egui::FontId::monospace(10.0),
        egui::Color32::GRAY,
    );
}

fn view_ui(
    ui: &mut egui::Ui,
    app: &mut App,
    controls: &mut CameraControls,
    actions: &mut Vec<Action>,
) {
    let mut view = *app.world().resource::<DebugView>();
    egui::ComboBox::from_label("debug view")
        .selected_text(view.name())
        .show_ui(ui, |ui| {
            for &v in DebugView::ALL {
                ui.selectable_value(&mut view, v, v.name());
            }
        });
    if view != *app.world().resource::<DebugView>() {
        app.world_mut().insert_resource(view);
    }
    ui.horizontal(|ui| {
        let mut mode = controls.mode;
        ui.radio_value(&mut mode, CameraMode::Orbit, "orbit");
        ui.radio_value(&mut mode, CameraMode::Fly, "fly");
        if mode != controls.mode {
            controls.toggle_mode();
        }
        if controls.mode == CameraMode::Fly {
            ui.add(
                egui::DragValue::new(&mut controls.speed_m_s)
                    .range(0.01..=1000.0)
                    .speed(0.05)
                    .suffix(" m/s"),
            );
        }
    });
    ui.horizontal(|ui| {
        if ui.button("screenshot (P)").clicked() {
            actions.push(Action::Screenshot);
        }
        if ui.button("reload shaders (R)").clicked() {
            actions.push(Action::ReloadShaders);
        }
    });
    ui.small(
        "drag: orbit/look · scroll: zoom/speed · F: orbit or fly · WASD QE Shift: fly · \
         Tab: panel · drop a .gltf/.glb/.hdr/.exr to open it",
    );
}

/// Exposure, tone mapping, depth of field and vignetting of the camera.
fn camera_ui(ui: &mut egui::Ui, camera: &mut Camera, metered_ev100: Option<f32>) {
    let mut c = *camera;
    let modes = ["EV100", "physical", "auto", "linear"];
    let mut mode = match c.exposure {
        Exposure::Ev100(_) => 0,
        Exposure::Physical => 1,
        Exposure::Auto(_) => 2,
        Exposure::Linear(_) => 3,
    };
    egui::ComboBox::from_label("exposure")
        .selected_text(modes[mode])
        .show_ui(ui, |ui| {
            for (i, m) in modes.iter().enumerate() {
                ui.selectable_value(&mut mode, i, *m);
            }
        });
    let ev = metered_ev100.unwrap_or(12.0);
    c.exposure = match (mode, c.exposure) {
        (0, Exposure::Ev100(e)) => Exposure::Ev100(e),
        (0, _) => Exposure::Ev100(ev),
        (1, _) => Exposure::Physical,
        (2, Exposure::Auto(a)) => Exposure::Auto(a),
        (2, _) => Exposure::Auto(AutoExposure::default()),
        (_, Exposure::Linear(k)) => Exposure::Linear(k),
        (_, _) => Exposure::Linear(1.0),
    };
    match &mut c.exposure {
        Exposure::Ev100(e) => {
            ui.add(egui::Slider::new(e, -6.0..=20.0).text("EV100"));
        }
        Exposure::Linear(k) => {
            ui.add(
                egui::Slider::new(k, 1e-6..=10.0)
                    .logarithmic(true)
                    .text("× luminance"),
            );
        }
        Exposure::Auto(a) => {
            ui.add(egui::Slider::new(&mut a.rate_per_s, 0.1..=10.0).text("adaptation /s"));
        }
        Exposure::Physical => {}
    }
    ui.add(
        egui::Slider::new(&mut c.lens.aperture_f_stops, 0.7..=32.0)
            .logarithmic(true)
            .text("aperture f/"),
    );
    let mut shutter_inv = 1.0 / c.lens.shutter_s;
    ui.add(
        egui::Slider::new(&mut shutter_inv, 1.0 / 30.0..=8000.0)
            .logarithmic(true)
            .text("shutter 1/s"),
    );
    c.lens.shutter_s = 1.0 / shutter_inv;
    ui.add(
        egui::Slider::new(&mut c.lens.iso, 50.0..=25600.0)
            .logarithmic(true)
            .text("ISO"),
    );
    ui.add(
        egui::Slider::new(&mut c.exposure_compensation, -5.0..=5.0).text("compensation (stops)"),
    );
    egui::ComboBox::from_label("tone mapper")
        .selected_text(c.tonemapper.name())
        .show_ui(ui, |ui| {
            for &t in Tonemapper::ALL {
                ui.selectable_value(&mut c.tonemapper, t, t.name());
            }
        });
    let mut dof = c.depth_of_field.is_some();
    ui.checkbox(&mut dof, "depth of field");
    let mut d = c.depth_of_field.unwrap_or_default();
    if dof {
        ui.add(
            egui::Slider::new(&mut c.lens.focus_distance_m, 0.1..=1000.0)
                .logarithmic(true)
                .text("focus m"),
        );
        ui.add(egui::Slider::new(&mut d.rings, 1..=5).text("rings"));
        ui.add(egui::Slider::new(&mut d.max_coc_px, 1.0..=64.0).text("max CoC px"));
    }
    c.depth_of_field = dof.then_some(d);
    let mut vignette = c.vignette.map_or(0.0, |v| v.strength);
    ui.add(egui::Slider::new(&mut vignette, 0.0..=1.0).text("vignetting"));
    c.vignette = (vignette > 0.0).then_some(Vignette { strength: vignette });
    if c != *camera {
        *camera = c;
    }
}

fn intensity_ui(ui: &mut egui::Ui, intensity: &mut lumen::scene::LuminousIntensity) {
    let (value, unit) = match intensity {
        lumen::scene::LuminousIntensity::Lumens(v) => (v, "lm"),
        lumen::scene::LuminousIntensity::Candela(v) => (v, "cd"),
    };
    ui.add(
        egui::Slider::new(value, 0.0..=1e6)
            .logarithmic(true)
            .suffix(format!(" {unit}")),
    );
}

/// Intensity, shadows and (for suns) direction of the first lights of each kind.
fn lights_ui(ui: &mut egui::Ui, world: &mut World) {
    let mut suns = world.query::<(Entity, &mut DirectionalLight, &mut Transform)>();
    for (i, (e, mut light, mut t)) in suns.iter_mut(world).take(LISTED_LIGHTS).enumerate() {
        ui.push_id(e, |ui| {
            ui.label(format!("sun {i}"));
            let mut l = *light;
            ui.add(
                egui::Slider::new(&mut l.illuminance_lux, 0.0..=150_000.0)
                    .logarithmic(true)
                    .suffix(" lx"),
            );
            ui.checkbox(&mut l.cast_shadows, "casts shadows");
            if l != *light {
                *light = l;
            }
            // Direction the light travels, as azimuth and elevation of where it comes from.
            let to_light = -(t.rotation * Vec3::NEG_Z);
            let mut elevation = to_light.y.clamp(-1.0, 1.0).asin().to_degrees();
            let mut azimuth = to_light.x.atan2(to_light.z).to_degrees();
            let e0 = (elevation, azimuth);
            ui.add(egui::Slider::new(&mut elevation, 1.0..=90.0).text("elevation °"));
            ui.add(egui::Slider::new(&mut azimuth, -180.0..=180.0).text("azimuth °"));
            if (elevation, azimuth) != e0 {
                let (el, az) = (elevation.to_radians(), azimuth.to_radians());
                let dir = Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
                *t = Transform::from_translation(t.translation).looking_at(
                    t.translation - dir,
                    if el.cos() < 1e-3 { Vec3::Z } else { Vec3::Y },
                );
            }
        });
    }
    punctual_ui::<PointLight>(ui, world, "point");
    punctual_ui::<SpotLight>(ui, world, "spot");
}

/// What the panel edits on point and spot lights.
trait Punctual: Component<Mutability = bevy_ecs::component::Mutable> + Copy + PartialEq {
    fn edit(&mut self) -> (&mut lumen::scene::LuminousIntensity, &mut bool);
}

impl Punctual for PointLight {
    fn edit(&mut self) -> (&mut lumen::scene::LuminousIntensity, &mut bool) {
        (&mut self.intensity, &mut self.cast_shadows)
    }
}

impl Punctual for SpotLight {
    fn edit(&mut self) -> (&mut lumen::scene::LuminousIntensity, &mut bool) {
        (&mut self.intensity, &mut self.cast_shadows)
    }
}

/// Intensity and shadows of the first lights of kind `L`.
fn punctual_ui<L: Punctual>(ui: &mut egui::Ui, world: &mut World, kind: &str) {
    let mut lights = world.query::<(Entity, &mut L)>();
    for (i, (e, mut light)) in lights.iter_mut(world).take(LISTED_LIGHTS).enumerate() {
        ui.push_id(e, |ui| {
            let mut l = *light;
            ui.label(format!("{kind} {i}"));
            let (intensity, shadows) = l.edit();
            intensity_ui(ui, intensity);
            ui.checkbox(shadows, "casts shadows");
            if l != *light {
                *light = l;
            }
        });
    }
}

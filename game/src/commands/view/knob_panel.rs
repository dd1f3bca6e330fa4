//! The panel's quality section, derived from the knobs' declarations: the presets, then
//! every knob of the app's [`Knobs`] under its heading, each with the widget its kind asks
//! for (a checkbox, a slider, a list of names) and its doc line as a tooltip.

use lumen::choice::Choice;
use lumen::quality::knob::{Kind, Knob, Knobs, Settings, Value};
use lumen::quality::{Quality, QualityPreset};

/// Slider ranges wider than this ratio are logarithmic.
const LOG_RATIO: f64 = 100.0;

/// The presets and every knob of `knobs`; returns the quality with what the user changed
/// (`None` when nothing moved).
pub fn quality_ui(ui: &mut egui::Ui, knobs: &Knobs, q: &Quality) -> Option<Quality> {
    let mut chosen = None;
    ui.horizontal(|ui| {
        for &p in QualityPreset::ALL {
            if ui.selectable_label(p.quality() == *q, p.name()).clicked() {
                chosen = Some(p.quality());
            }
        }
    });
    let values = knobs.values(q);
    let mut changed = Settings::default();
    for group in knobs.groups() {
        egui::CollapsingHeader::new(group.0)
            .default_open(false)
            .show(ui, |ui| {
                for &(knob, value) in values.iter().filter(|(k, _)| k.group == group) {
                    if let Some(v) = knob_ui(ui, knob, value) {
                        changed.set(knob, v);
                    }
                }
            });
    }
    if chosen.is_some() {
        return chosen;
    }
    if changed.is_empty() {
        return None;
    }
    let mut next = q.clone();
    changed.apply(&mut next).ok()?;
    Some(next)
}

/// One knob's widget; the new value when the user moved it.
fn knob_ui(ui: &mut egui::Ui, knob: &'static Knob, value: Value) -> Option<Value> {
    let mut next = value;
    let response = match (knob.kind, value) {
        (Kind::Switch { on, .. }, Value::Bool(mut b)) => {
            let r = ui.checkbox(&mut b, format!("{} ({on})", knob.name));
            next = Value::Bool(b);
            r
        }
        (Kind::Choice(names), Value::Name(current)) => {
            let mut picked = current;
            let r = egui::ComboBox::from_label(knob.name)
                .selected_text(current)
                .show_ui(ui, |ui| {
                    for &n in names {
                        ui.selectable_value(&mut picked, n, n);
                    }
                })
                .response;
            next = Value::Name(picked);
            r
        }
        (Kind::Int { min, max }, Value::Int(mut v)) => {
            let r = ui.add(slider(&mut v, min, max, knob.name));
            next = Value::Int(v);
            r
        }
        (Kind::Float { min, max }, Value::Float(mut v)) => {
            let r = ui.add(slider(&mut v, min, max, knob.name));
            next = Value::Float(v);
            r
        }
        (Kind::OptionalInt { none, min, max }, _) => {
            let mut set = value != Value::None;
            let mut v = value.as_i64().unwrap_or(min);
            let r = ui
                .horizontal(|ui| {
                    ui.checkbox(&mut set, "")
                        .on_hover_text(format!("off: {none}"));
                    if set {
                        ui.add(slider(&mut v, min, max, knob.name));
                    } else {
                        ui.label(format!("{} ({none})", knob.name));
                    }
                })
                .response;
            next = if set { Value::Int(v) } else { Value::None };
            r
        }
        (Kind::OptionalFloat { none, min, max }, _) => {
            let mut set = value != Value::None;
            let mut v = value.as_f32().unwrap_or(min);
            let r = ui
                .horizontal(|ui| {
                    ui.checkbox(&mut set, "")
                        .on_hover_text(format!("off: {none}"));
                    if set {
                        ui.add(slider(&mut v, min, max, knob.name));
                    } else {
                        ui.label(format!("{} ({none})", knob.name));
                    }
                })
                .response;
            next = if set { Value::Float(v) } else { Value::None };
            r
        }
        _ => ui.label(format!("{}: {}", knob.name, knob.format(value))),
    };
    response.on_hover_text(knob.doc);
    (next != value).then_some(next)
}

/// A slider over `min..=max`, logarithmic when the range spans more than [`LOG_RATIO`].
fn slider<'a, N: egui::emath::Numeric>(
    value: &'a mut N,
    min: N,
    max: N,
    text: &str,
) -> egui::Slider<'a> {
    let wide = min.to_f64() > 0.0 && max.to_f64() / min.to_f64() > LOG_RATIO;
    egui::Slider::new(value, min..=max)
        .logarithmic(wide)
        .text(text)
}

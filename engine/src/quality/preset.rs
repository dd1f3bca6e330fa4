//! Presets as data: a preset is a TOML file of knob names and values.
//!
//! ```toml
//! # start from `medium` (without this line: from the defaults, which are `high`)
//! preset = "medium"
//! ao = "full"
//! ssr-max-roughness = 0.5
//! dof-rings = "camera"
//! ```
//!
//! A key is a knob's name ([`super::Knob::name`]) and a value is written as the knob's
//! kind reads it ([`super::Knob::from_toml`]): a boolean (or the switch's names, such as
//! `"half"`/`"full"`), a number, or a name. The built-in presets are such files, embedded
//! from `engine/src/quality/presets/`: each names only what differs from the defaults.
//! [`show`] writes every knob of a quality as such a file, which [`parse`] reads back to
//! the same quality. An unknown key or a value out of range is an error that names the
//! file, the line and the key.

use super::knob::{Kind, Knob, Knobs, Settings};
use super::{Quality, QualityPreset};
use crate::choice::Choice;
use crate::error::{Error, Result};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::LazyLock;

/// The key that names the preset a file starts from.
pub const BASE_KEY: &str = "preset";

/// The text of each built-in preset's file.
pub fn builtin_text(preset: QualityPreset) -> &'static str {
    match preset {
        QualityPreset::Low => include_str!("presets/low.toml"),
        QualityPreset::Medium => include_str!("presets/medium.toml"),
        QualityPreset::High => include_str!("presets/high.toml"),
        QualityPreset::Ultra => include_str!("presets/ultra.toml"),
    }
}

/// The built-in presets, each read once from its embedded file.
static BUILTIN: LazyLock<Vec<Quality>> = LazyLock::new(|| {
    let knobs = Knobs::default();
    QualityPreset::ALL
        .iter()
        .map(|&p| {
            let name = format!("presets/{}.toml", p.name());
            parse_from(Quality::default(), builtin_text(p), &name, &knobs)
                .unwrap_or_else(|e| panic!("the built-in preset {name} is wrong: {e}"))
        })
        .collect()
});

/// The built-in preset `preset`.
pub fn builtin(preset: QualityPreset) -> &'static Quality {
    let i = QualityPreset::ALL
        .iter()
        .position(|p| *p == preset)
        .unwrap_or(0);
    &BUILTIN[i]
}

/// Reads a preset file's text (`source` names it in errors): the preset its `preset` key
/// names (else the defaults), with every other key's knob set.
pub fn parse(text: &str, source: &str, knobs: &Knobs) -> Result<Quality> {
    let base = base_of(text, source)?;
    parse_from(base.quality(), text, source, knobs)
}

/// Reads a preset file from disk (see [`parse`]).
pub fn load(path: &Path, knobs: &Knobs) -> Result<Quality> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse(&text, &path.display().to_string(), knobs)
}

/// The line (from 1) of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// An error at the key of `text` that starts at byte `offset`.
fn error_at(source: &str, text: &str, offset: usize, message: impl std::fmt::Display) -> Error {
    Error::InvalidArgument(format!("{source}:{}: {message}", line_of(text, offset)))
}

type Entries = BTreeMap<toml::Spanned<String>, toml::Spanned<toml::Value>>;

/// The file's entries with their places, or the TOML syntax error with its line.
fn entries(text: &str, source: &str) -> Result<Entries> {
    toml::from_str::<Entries>(text).map_err(|e| match e.span() {
        Some(span) => error_at(source, text, span.start, e.message()),
        None => Error::InvalidArgument(format!("{source}: {}", e.message())),
    })
}

/// The preset a file's `preset` key names (`high` without one).
fn base_of(text: &str, source: &str) -> Result<QualityPreset> {
    for (key, value) in entries(text, source)? {
        if key.get_ref() == BASE_KEY {
            return match value.get_ref().as_str().map(QualityPreset::parse) {
                Some(Ok(p)) => Ok(p),
                Some(Err(e)) => Err(error_at(source, text, key.span().start, e)),
                None => Err(error_at(
                    source,
                    text,
                    key.span().start,
                    format!(
                        "{BASE_KEY} must be a preset's name (use {})",
                        QualityPreset::NAMES.join(", ")
                    ),
                )),
            };
        }
    }
    Ok(QualityPreset::High)
}

/// `base` with every knob the file names set (its `preset` key is [`parse`]'s).
fn parse_from(base: Quality, text: &str, source: &str, knobs: &Knobs) -> Result<Quality> {
    let mut settings = Settings::default();
    for (key, value) in entries(text, source)? {
        if key.get_ref() == BASE_KEY {
            continue;
        }
        let at = key.span().start;
        let knob = knobs
            .lookup(key.get_ref())
            .map_err(|e| error_at(source, text, at, e))?;
        let v = knob
            .from_toml(value.get_ref())
            .map_err(|e| error_at(source, text, at, e))?;
        settings.set(knob, v);
    }
    let mut quality = base;
    settings
        .apply(&mut quality)
        .map_err(|e| Error::InvalidArgument(format!("{source}: {e}")))?;
    Ok(quality)
}

/// Every knob of `quality` as a preset file, grouped under its headings, each with its doc
/// line and range; `title` is its first comment line.
pub fn show(quality: &Quality, knobs: &Knobs, title: &str) -> String {
    let mut out = format!(
        "# {title}\n# A quality file may start from a preset (`{BASE_KEY} = \"medium\"`) and name only\n# the knobs it changes.\n"
    );
    let values = knobs.values(quality);
    for group in knobs.groups() {
        out.push_str(&format!("\n# {}\n", group.0));
        for (knob, value) in values.iter().filter(|(k, _)| k.group == group) {
            out.push_str(&line(knob, *value));
        }
    }
    out
}

/// One knob's line of [`show`]: `name = value  # doc (range)`.
fn line(knob: &Knob, value: super::knob::Value) -> String {
    let mut table = toml::Table::new();
    table.insert(knob.name.to_string(), knob.to_toml(value));
    let assignment = toml::to_string(&table).unwrap_or_default();
    let range = match knob.kind {
        Kind::Switch { .. } | Kind::Choice(_) => String::new(),
        kind => format!(" ({})", kind.range()),
    };
    format!("{:<36} # {}{range}\n", assignment.trim_end(), knob.doc)
}

impl QualityPreset {
    /// Every knob of this preset: the defaults with the preset's file applied.
    pub fn quality(self) -> Quality {
        builtin(self).clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quality::knob::{Acts, Group, Value};
    use crate::quality::knobs::{AO, AO_SLICES, SSR_MAX_ROUGHNESS};

    #[test]
    fn every_builtin_preset_round_trips_through_show() {
        let knobs = Knobs::default();
        for &p in QualityPreset::ALL {
            let quality = p.quality();
            let text = show(&quality, &knobs, p.name());
            let back = parse(&text, "shown", &knobs).expect("parse what show wrote");
            assert_eq!(back, quality, "{} round trip:\n{text}", p.name());
        }
    }

    #[test]
    fn the_presets_differ_where_their_files_say() {
        assert_eq!(QualityPreset::High.quality(), Quality::default());
        let low = QualityPreset::Low.quality();
        assert_eq!(low.ao.resolution, crate::quality::AoResolution::Off);
        assert!(!low.ssr.enabled && !low.gi.enabled && !low.energy_compensation);
        let ultra = QualityPreset::Ultra.quality();
        assert_eq!(ultra.aa.method, crate::quality::AaMethod::Taa);
        assert_eq!(ultra.ssr.rays, 8);
        assert!(!ultra.gi.half_resolution);
    }

    #[test]
    fn a_file_starts_from_its_preset_and_overrides_knobs() {
        let knobs = Knobs::default();
        let q = parse(
            "preset = \"medium\"\nao = \"full\"\nssr-max-roughness = 0.5\n",
            "mine.toml",
            &knobs,
        )
        .expect("valid");
        let medium = QualityPreset::Medium.quality();
        assert_eq!(AO.get(&q), Value::Name("full"));
        assert_eq!(q.ssr.max_roughness, 0.5);
        assert_eq!(AO_SLICES.get(&q), AO_SLICES.get(&medium));
        assert_eq!(q.gi, medium.gi);
        assert_eq!(SSR_MAX_ROUGHNESS.get(&medium), Value::Float(0.2));
    }

    #[test]
    fn errors_name_the_file_the_line_and_the_key() {
        let knobs = Knobs::default();
        let err = |text: &str| {
            parse(text, "mine.toml", &knobs)
                .expect_err("invalid")
                .to_string()
        };
        let unknown = err("ao = \"half\"\n\nssr-max-rougness = 0.3\n");
        assert!(unknown.starts_with("mine.toml:3:"), "{unknown}");
        assert!(unknown.contains("ssr-max-rougness"), "{unknown}");
        assert!(
            unknown.contains("did you mean 'ssr-max-roughness'"),
            "{unknown}"
        );
        let range = err("# a comment\nao-slices = 12\n");
        assert!(range.starts_with("mine.toml:2:"), "{range}");
        assert!(
            range.contains("ao-slices") && range.contains("1..=8"),
            "{range}"
        );
        let name = err("ao = \"quarter\"\n");
        assert!(
            name.starts_with("mine.toml:1:") && name.contains("off, half, full"),
            "{name}"
        );
        let kind = err("ssr = 3\n");
        assert!(
            kind.starts_with("mine.toml:1:") && kind.contains("ssr"),
            "{kind}"
        );
        let base = err("\npreset = \"extreme\"\n");
        assert!(
            base.starts_with("mine.toml:2:") && base.contains("low, medium, high, ultra"),
            "{base}"
        );
        let syntax = err("ao = \n");
        assert!(syntax.starts_with("mine.toml:1:"), "{syntax}");
    }

    #[test]
    fn a_plugins_knob_lives_in_the_extensions_and_reads_its_default_until_set() {
        static STRENGTH: Knob = Knob {
            name: "toy-strength",
            path: "extensions.toy-strength",
            group: Group::CAMERA,
            doc: "test",
            kind: Kind::Float { min: 0.0, max: 2.0 },
            default: Value::Float(0.5),
            passes: &[],
            acts: Acts::FRAME,
            sweep: &[Value::Float(1.5)],
            sweep_with: &[],
        };
        let knobs = crate::quality::knobs::builtin()
            .with(&STRENGTH)
            .expect("a new name");
        let mut q = Quality::default();
        assert_eq!(STRENGTH.get(&q), Value::Float(0.5));
        STRENGTH.set(&mut q, Value::Float(1.5)).expect("in range");
        assert_eq!(STRENGTH.get(&q), Value::Float(1.5));
        let text = show(&q, &knobs, "with a plugin");
        assert!(text.contains("toy-strength = 1.5"), "{text}");
        let back = parse(&text, "shown", &knobs).expect("parse");
        assert_eq!(back, q);
        assert_eq!(knobs.json(&q)["toy-strength"], serde_json::json!(1.5));
    }
}

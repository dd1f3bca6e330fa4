//! One declaration per knob.
//!
//! A [`Knob`] is a plain `static` that states everything about one speed/accuracy setting:
//! its name, the field of [`Quality`] it sets (its `path`), a doc line, its type and range
//! ([`Kind`]), its default, the passes that read it, the values `lumen tradeoff` sweeps
//! and what it acts on ([`Acts`]). The built-in knobs are listed once, in
//! [`super::knobs::builtin`]; a script or plugin registers its own with
//! [`Knobs::with`]. Everything else is derived from the declarations:
//! - [`Quality::default`] is the defaults, applied to the typed struct through serde;
//! - the presets are TOML files of knob names and values ([`super::preset`]);
//! - the front end's command-line flags, the viewer's widgets, the JSON of `render --json`
//!   and `bench`, the `lumen tradeoff` rows and the words of `--explain` all iterate a
//!   [`Knobs`] registry.
//!
//! # Why a table of descriptors, not a macro
//!
//! A macro could generate the struct fields and the descriptors from one list, but the
//! settings are nested structs that passes take whole (`&AoSettings`), and scripts set
//! them as typed fields (`quality.ao.slices = 4`). A table keeps those types as they are
//! and ties each descriptor to its field by a path into the struct's serde form, which a
//! unit test checks both ways (every field has exactly one knob, every knob's path is a
//! field). The same table takes knobs that no struct field has: a plugin's knob lives in
//! [`Quality::extensions`] under its name, read and set exactly like a built-in one. It is
//! also the form Bevy's `Reflect`-driven inspectors take: data about fields, walked at run
//! time, not code generated per field.

use super::Quality;
use crate::pass_id::PassId;
use std::collections::BTreeMap;
use std::fmt;

/// The heading a knob is listed under (`--help`, the viewer's panel, `quality show`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Group(pub &'static str);

impl Group {
    /// Shadow maps and their filtering.
    pub const SHADOWS: Group = Group("Shadows");
    /// The BRDF and the light loop.
    pub const SHADING: Group = Group("Shading");
    /// Image-based lighting: the prefiltered environment and the split-sum table.
    pub const ENVIRONMENT: Group = Group("Environment lighting");
    /// Ambient occlusion, reflections, the irradiance volume and reflection probes.
    pub const INDIRECT: Group = Group("Indirect light");
    /// Specular, post-process and temporal anti-aliasing, and accumulation.
    pub const ANTI_ALIASING: Group = Group("Anti-aliasing");
    /// The camera's effects and the HDR target.
    pub const CAMERA: Group = Group("Camera");
    /// Blended surfaces.
    pub const TRANSPARENCY: Group = Group("Transparency");
    /// Memory budgets.
    pub const RESOURCES: Group = Group("Resources");
}

/// What a knob acts on: which of Lumen's renderers read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Acts(u8);

impl Acts {
    /// The rasterized frame (`render`, `view`, `bench`, `tradeoff`).
    pub const FRAME: Acts = Acts(1);
    /// The path tracer (`reference`).
    pub const TRACE: Acts = Acts(2);
    /// Loading assets, whichever renderer draws them.
    pub const LOAD: Acts = Acts(4);

    /// Both sets.
    pub const fn and(self, other: Acts) -> Acts {
        Acts(self.0 | other.0)
    }

    /// Whether `self` and `other` share a renderer.
    pub const fn meets(self, other: Acts) -> bool {
        self.0 & other.0 != 0
    }
}

/// A knob's type and range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// On or off, named `off` and `on` (or, e.g., `scene` and `all`).
    Switch {
        /// The name of `false`.
        off: &'static str,
        /// The name of `true`.
        on: &'static str,
    },
    /// An integer in `min..=max`.
    Int {
        /// Smallest value.
        min: i64,
        /// Largest value.
        max: i64,
    },
    /// A finite number in `min..=max`.
    Float {
        /// Smallest value.
        min: f32,
        /// Largest value.
        max: f32,
    },
    /// One of these names (a [`crate::choice::Choice`]'s `NAMES`).
    Choice(&'static [&'static str]),
    /// An integer in `min..=max`, or none (named `none`: another setting decides).
    OptionalInt {
        /// The name of "none".
        none: &'static str,
        /// Smallest value.
        min: i64,
        /// Largest value.
        max: i64,
    },
    /// A finite number in `min..=max`, or none (named `none`).
    OptionalFloat {
        /// The name of "none".
        none: &'static str,
        /// Smallest value.
        min: f32,
        /// Largest value.
        max: f32,
    },
}

impl Kind {
    /// A switch named `off`/`on`.
    pub const ON_OFF: Kind = Kind::Switch {
        off: "off",
        on: "on",
    };

    /// What the command line shows as the value's placeholder, e.g. `N`, `X`, `on|off`.
    pub fn placeholder(&self) -> String {
        match self {
            Kind::Switch { off, on } => format!("{on}|{off}"),
            Kind::Int { .. } => "N".into(),
            Kind::Float { .. } => "X".into(),
            Kind::Choice(names) => names.join("|"),
            Kind::OptionalInt { none, .. } => format!("N|{none}"),
            Kind::OptionalFloat { none, .. } => format!("X|{none}"),
        }
    }

    /// The range or the names, in words, for help and errors.
    pub fn range(&self) -> String {
        match self {
            Kind::Switch { off, on } => format!("{on} or {off}"),
            Kind::Int { min, max } => format!("{min}..={max}"),
            Kind::Float { min, max } => format!("{min}..={max}"),
            Kind::Choice(names) => names.join(", "),
            Kind::OptionalInt { none, min, max } => format!("{min}..={max} or {none}"),
            Kind::OptionalFloat { none, min, max } => format!("{min}..={max} or {none}"),
        }
    }
}

/// A knob's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A switch.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A number.
    Float(f32),
    /// A choice's name.
    Name(&'static str),
    /// An optional knob left to another setting.
    None,
}

impl Value {
    /// The number, if it is one.
    pub fn as_f32(self) -> Option<f32> {
        match self {
            Value::Float(v) => Some(v),
            Value::Int(v) => Some(v as f32),
            _ => None,
        }
    }

    /// The integer, if it is one.
    pub fn as_i64(self) -> Option<i64> {
        match self {
            Value::Int(v) => Some(v),
            _ => None,
        }
    }

    /// The switch's state, if it is one.
    pub fn as_bool(self) -> Option<bool> {
        match self {
            Value::Bool(b) => Some(b),
            _ => None,
        }
    }
}

/// One speed/accuracy knob (see the [module documentation](self)).
#[derive(Debug)]
pub struct Knob {
    /// Its name: the key in preset files and JSON, and the front end's flag (`--NAME`).
    pub name: &'static str,
    /// The field of [`Quality`] it sets, as a dotted path into its serde form
    /// (`ao.slices`); a plugin's knob uses `extensions.NAME`.
    pub path: &'static str,
    /// Its heading.
    pub group: Group,
    /// One line on what it does and costs.
    pub doc: &'static str,
    /// Its type and range.
    pub kind: Kind,
    /// Its default: the value of the `high` preset, which [`Quality::default`] is.
    pub default: Value,
    /// The passes that read it.
    pub passes: &'static [PassId],
    /// What it acts on.
    pub acts: Acts,
    /// The values `lumen tradeoff` gives it, each in a row of its own with every other
    /// knob at `high`.
    pub sweep: &'static [Value],
    /// Other knobs' values its sweep rows need (a specular AA form matters only with
    /// specular AA on).
    pub sweep_with: &'static [(&'static Knob, Value)],
}

/// A knob's value that does not fit it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct KnobError(pub String);

impl fmt::Display for KnobError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for KnobError {}

impl Knob {
    /// Parses a value as written on a command line (`on`, `3`, `0.5`, `tent`).
    pub fn parse(&self, text: &str) -> Result<Value, KnobError> {
        let t = text.trim();
        let bad = |what: &str| {
            KnobError(format!(
                "{}: '{t}' is not {what} (use {})",
                self.name,
                self.kind.range()
            ))
        };
        let value = match self.kind {
            Kind::Switch { off, on } => {
                if t.eq_ignore_ascii_case(on) {
                    Value::Bool(true)
                } else if t.eq_ignore_ascii_case(off) {
                    Value::Bool(false)
                } else {
                    return Err(bad(&format!("{on} or {off}")));
                }
            }
            Kind::Int { .. } => Value::Int(t.parse().map_err(|_| bad("an integer"))?),
            Kind::Float { .. } => Value::Float(t.parse().map_err(|_| bad("a number"))?),
            Kind::Choice(names) => Value::Name(
                names
                    .iter()
                    .find(|n| n.eq_ignore_ascii_case(t))
                    .ok_or_else(|| {
                        KnobError(format!(
                            "unknown {} '{t}' (use {})",
                            self.name,
                            names.join(", ")
                        ))
                    })?,
            ),
            Kind::OptionalInt { none, .. } if t.eq_ignore_ascii_case(none) => Value::None,
            Kind::OptionalFloat { none, .. } if t.eq_ignore_ascii_case(none) => Value::None,
            Kind::OptionalInt { .. } => Value::Int(t.parse().map_err(|_| bad("an integer"))?),
            Kind::OptionalFloat { .. } => Value::Float(t.parse().map_err(|_| bad("a number"))?),
        };
        self.check(value)
    }

    /// `value` if it has this knob's type and lies in its range.
    pub fn check(&self, value: Value) -> Result<Value, KnobError> {
        let out_of_range = |v: &dyn fmt::Display| {
            KnobError(format!(
                "{}: {v} is out of range (use {})",
                self.name,
                self.kind.range()
            ))
        };
        match (self.kind, value) {
            (Kind::Switch { .. }, Value::Bool(_)) => Ok(value),
            (Kind::Int { min, max } | Kind::OptionalInt { min, max, .. }, Value::Int(v)) => {
                if (min..=max).contains(&v) {
                    Ok(value)
                } else {
                    Err(out_of_range(&v))
                }
            }
            (Kind::Float { min, max } | Kind::OptionalFloat { min, max, .. }, Value::Float(v)) => {
                if v.is_finite() && (min..=max).contains(&v) {
                    Ok(value)
                } else {
                    Err(out_of_range(&v))
                }
            }
            (Kind::Choice(names), Value::Name(n)) => names
                .iter()
                .find(|known| known.eq_ignore_ascii_case(n))
                .map(|known| Value::Name(known))
                .ok_or_else(|| out_of_range(&n)),
            (Kind::OptionalInt { .. } | Kind::OptionalFloat { .. }, Value::None) => Ok(value),
            (kind, value) => Err(KnobError(format!(
                "{}: {value:?} is not a value of its kind (use {})",
                self.name,
                kind.range()
            ))),
        }
    }

    /// `value` as the command line writes it.
    pub fn format(&self, value: Value) -> String {
        match (self.kind, value) {
            (Kind::Switch { on, off }, Value::Bool(b)) => if b { on } else { off }.into(),
            (Kind::OptionalInt { none, .. } | Kind::OptionalFloat { none, .. }, Value::None) => {
                none.into()
            }
            (_, Value::Bool(b)) => b.to_string(),
            (_, Value::Int(v)) => v.to_string(),
            (_, Value::Float(v)) => v.to_string(),
            (_, Value::Name(n)) => n.into(),
            (_, Value::None) => "none".into(),
        }
    }

    /// `name = value`, as `--explain` names a knob's setting.
    pub fn setting(&self, value: Value) -> String {
        format!("{} = {}", self.name, self.format(value))
    }

    /// `value` as a preset file or a JSON report writes it: a switch named on/off is a
    /// boolean, other switches and "none" are their names, numbers are numbers.
    pub fn to_toml(&self, value: Value) -> toml::Value {
        match (self.kind, value) {
            (
                Kind::Switch {
                    off: "off",
                    on: "on",
                },
                Value::Bool(b),
            ) => toml::Value::Boolean(b),
            (_, Value::Int(v)) => toml::Value::Integer(v),
            (_, Value::Float(v)) => toml::Value::Float(round_trip_f32(f64::from(v))),
            _ => toml::Value::String(self.format(value)),
        }
    }

    /// `value` as JSON (the form of [`Knob::to_toml`]).
    pub fn to_json(&self, value: Value) -> serde_json::Value {
        match self.to_toml(value) {
            toml::Value::Boolean(b) => serde_json::Value::Bool(b),
            toml::Value::Integer(v) => serde_json::Value::from(v),
            toml::Value::Float(v) => serde_json::Value::from(v),
            other => serde_json::Value::String(other.as_str().unwrap_or_default().to_string()),
        }
    }

    /// Reads a value as a preset file writes it (a boolean or a switch's name, a number,
    /// a name).
    pub fn from_toml(&self, value: &toml::Value) -> Result<Value, KnobError> {
        let parsed = match (self.kind, value) {
            (_, toml::Value::String(s)) => return self.parse(s),
            (Kind::Switch { .. }, toml::Value::Boolean(b)) => Value::Bool(*b),
            (Kind::Int { .. } | Kind::OptionalInt { .. }, toml::Value::Integer(v)) => {
                Value::Int(*v)
            }
            (Kind::Float { .. } | Kind::OptionalFloat { .. }, toml::Value::Integer(v)) => {
                Value::Float(*v as f32)
            }
            (Kind::Float { .. } | Kind::OptionalFloat { .. }, toml::Value::Float(v)) => {
                Value::Float(*v as f32)
            }
            (kind, other) => {
                return Err(KnobError(format!(
                    "{}: {other} is not a value of this knob (use {})",
                    self.name,
                    kind.range()
                )));
            }
        };
        self.check(parsed)
    }

    /// The value of a field of [`Quality`]'s serde tree (absent: none for an optional
    /// knob, else the default).
    fn read_field(&self, field: Option<&toml::Value>) -> Value {
        let value = match (self.kind, field) {
            (_, None) => {
                return match self.kind {
                    Kind::OptionalInt { .. } | Kind::OptionalFloat { .. } => Value::None,
                    _ => self.default,
                };
            }
            (Kind::Switch { .. }, Some(toml::Value::Boolean(b))) => Value::Bool(*b),
            (_, Some(toml::Value::Integer(v))) => Value::Int(*v),
            (_, Some(toml::Value::Float(v))) => Value::Float(*v as f32),
            (Kind::Choice(names), Some(toml::Value::String(s))) => names
                .iter()
                .find(|n| **n == s.as_str())
                .map_or(self.default, |n| Value::Name(n)),
            _ => self.default,
        };
        self.check(value).unwrap_or(self.default)
    }

    /// This knob's value in `quality`.
    pub fn get(&self, quality: &Quality) -> Value {
        self.read_field(lookup(&quality.to_tree(), self.path))
    }

    /// Sets this knob in `quality` (checked against its kind and range).
    pub fn set(&self, quality: &mut Quality, value: Value) -> Result<(), KnobError> {
        let value = self.check(value)?;
        let mut tree = quality.to_tree();
        store(&mut tree, self.path, to_field(value));
        *quality = Quality::from_tree(tree)
            .map_err(|e| KnobError(format!("{} ({}): {e}", self.name, self.path)))?;
        Ok(())
    }
}

/// An `f64` that came from an `f32`, printed as the `f32` prints (0.35, not
/// 0.3499999940395355).
fn round_trip_f32(v: f64) -> f64 {
    (v as f32).to_string().parse().unwrap_or(v)
}

/// Writes `knob`'s default into `tree` (how [`Quality::default`] is made).
pub(super) fn store_default(tree: &mut toml::Table, knob: &Knob) {
    store(tree, knob.path, to_field(knob.default));
}

/// A value's form in [`Quality`]'s serde tree (`None` leaves the field out).
fn to_field(value: Value) -> Option<toml::Value> {
    match value {
        Value::Bool(b) => Some(toml::Value::Boolean(b)),
        Value::Int(v) => Some(toml::Value::Integer(v)),
        Value::Float(v) => Some(toml::Value::Float(f64::from(v))),
        Value::Name(n) => Some(toml::Value::String(n.into())),
        Value::None => None,
    }
}

/// The field at dotted `path` in `tree`.
fn lookup<'a>(tree: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let (head, rest) = match path.split_once('.') {
        Some((head, rest)) => (head, Some(rest)),
        None => (path, None),
    };
    let value = tree.get(head)?;
    match rest {
        None => Some(value),
        Some(rest) => lookup(value.as_table()?, rest),
    }
}

/// Sets (or, for `None`, removes) the field at dotted `path` in `tree`, making the
/// tables on the way.
fn store(tree: &mut toml::Table, path: &str, value: Option<toml::Value>) {
    match path.split_once('.') {
        None => {
            match value {
                Some(v) => tree.insert(path.into(), v),
                None => tree.remove(path),
            };
        }
        Some((head, rest)) => {
            let entry = tree
                .entry(head.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            if !entry.is_table() {
                *entry = toml::Value::Table(toml::Table::new());
            }
            if let toml::Value::Table(t) = entry {
                store(t, rest, value);
            }
        }
    }
}

/// Knob values given one by one (on a command line, by a tradeoff row), in order; a later
/// value of the same knob replaces the earlier one.
#[derive(Clone, Default)]
pub struct Settings(Vec<(&'static Knob, Value)>);

impl fmt::Debug for Settings {
    /// `name=value` pairs, as a command line gives them.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let pairs: Vec<String> = self
            .0
            .iter()
            .map(|(k, v)| format!("{}={}", k.name, k.format(*v)))
            .collect();
        write!(f, "[{}]", pairs.join(" "))
    }
}

impl Settings {
    /// Sets `knob` to `value`, replacing an earlier value of it.
    pub fn set(&mut self, knob: &'static Knob, value: Value) {
        self.0.retain(|(k, _)| k.name != knob.name);
        self.0.push((knob, value));
    }

    /// The value given to `knob`, if any.
    pub fn get(&self, knob: &Knob) -> Option<Value> {
        self.0
            .iter()
            .find(|(k, _)| k.name == knob.name)
            .map(|(_, v)| *v)
    }

    /// Whether no knob is set.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Every `(knob, value)`, in order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static Knob, Value)> + '_ {
        self.0.iter().copied()
    }

    /// Sets every knob in `quality` (each value checked against its knob).
    pub fn apply(&self, quality: &mut Quality) -> Result<(), KnobError> {
        let mut tree = quality.to_tree();
        for (k, v) in &self.0 {
            let v = k.check(*v)?;
            store(&mut tree, k.path, to_field(v));
        }
        *quality = Quality::from_tree(tree).map_err(|e| KnobError(e.to_string()))?;
        Ok(())
    }
}

/// A set of knobs: the built-in ones and any a script registers.
#[derive(bevy_ecs::prelude::Resource, Clone, Debug)]
pub struct Knobs {
    knobs: Vec<&'static Knob>,
}

impl Knobs {
    /// These knobs, in this order (checked: unique names and paths, defaults in range).
    pub fn new(knobs: Vec<&'static Knob>) -> Result<Knobs, KnobError> {
        let mut set = Knobs { knobs: Vec::new() };
        for k in knobs {
            set = set.with(k)?;
        }
        Ok(set)
    }

    /// The same knobs and `knob` after them. A knob whose path is not a field of
    /// [`Quality`] must live under `extensions.`.
    pub fn with(mut self, knob: &'static Knob) -> Result<Knobs, KnobError> {
        if let Some(other) = self
            .knobs
            .iter()
            .find(|k| k.name == knob.name || k.path == knob.path)
        {
            return Err(KnobError(format!(
                "two knobs are named '{}' or set '{}' (the second: '{}' at '{}')",
                other.name, other.path, knob.name, knob.path
            )));
        }
        let valid_name = !knob.name.is_empty()
            && knob
                .name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
        if !valid_name {
            return Err(KnobError(format!(
                "knob name '{}': use lowercase letters, digits and '-'",
                knob.name
            )));
        }
        knob.check(knob.default)?;
        for v in knob.sweep {
            knob.check(*v)?;
        }
        self.knobs.push(knob);
        Ok(self)
    }

    /// Every knob, in declaration order.
    pub fn iter(&self) -> impl Iterator<Item = &'static Knob> + '_ {
        self.knobs.iter().copied()
    }

    /// The knob called `name`.
    pub fn find(&self, name: &str) -> Option<&'static Knob> {
        self.iter().find(|k| k.name == name)
    }

    /// The knob called `name`, or an error that suggests the nearest name.
    pub fn lookup(&self, name: &str) -> Result<&'static Knob, KnobError> {
        self.find(name).ok_or_else(|| {
            let nearest = self
                .iter()
                .min_by_key(|k| edit_distance(k.name, name))
                .filter(|k| edit_distance(k.name, name) <= 3);
            KnobError(match nearest {
                Some(k) => format!("unknown knob '{name}' (did you mean '{}'?)", k.name),
                None => format!("unknown knob '{name}'"),
            })
        })
    }

    /// Every knob with its value in `quality`, reading `quality` once.
    pub fn values(&self, quality: &Quality) -> Vec<(&'static Knob, Value)> {
        let tree = quality.to_tree();
        self.iter()
            .map(|k| (k, k.read_field(lookup(&tree, k.path))))
            .collect()
    }

    /// The groups of these knobs, in order of first appearance.
    pub fn groups(&self) -> Vec<Group> {
        let mut groups: Vec<Group> = Vec::new();
        for k in self.iter() {
            if !groups.contains(&k.group) {
                groups.push(k.group);
            }
        }
        groups
    }

    /// Every knob's value in `quality` as one JSON object, keyed by knob name.
    pub fn json(&self, quality: &Quality) -> serde_json::Value {
        let object: serde_json::Map<String, serde_json::Value> = self
            .values(quality)
            .into_iter()
            .map(|(k, v)| (k.name.to_string(), k.to_json(v)))
            .collect();
        serde_json::Value::Object(object)
    }

    /// Every knob that reads pass `pass`'s name, with its value in `quality`.
    pub fn of_pass(&self, quality: &Quality, pass: PassId) -> Vec<(&'static Knob, Value)> {
        self.values(quality)
            .into_iter()
            .filter(|(k, _)| k.passes.contains(&pass))
            .collect()
    }

    /// The values of `quality` that differ from `base`, knob by knob.
    pub fn differences(&self, base: &Quality, quality: &Quality) -> Vec<(&'static Knob, Value)> {
        let before: BTreeMap<&str, Value> = self
            .values(base)
            .into_iter()
            .map(|(k, v)| (k.name, v))
            .collect();
        self.values(quality)
            .into_iter()
            .filter(|(k, v)| before.get(k.name) != Some(v))
            .collect()
    }
}

/// Levenshtein distance between two short names.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

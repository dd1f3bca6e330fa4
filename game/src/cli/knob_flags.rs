//! The knobs' command-line flags, derived from their declarations
//! ([`lumen::quality::knob`]): the engine names knobs, this module maps each to the flag
//! `--NAME` with its value placeholder, its help (the knob's doc, range and default), its
//! heading (the knob's group) and its parser (the knob's own). Each subcommand gets the
//! knobs that act on what it runs ([`Acts`]).

use clap::builder::{PossibleValue, TypedValueParser};
use clap::{Arg, ArgAction, ArgMatches, Command};
use lumen::quality::knob::{Acts, Kind, Knob, Knobs, Settings, Value};

/// The flag of `knob`, as `--help` and the messages write it.
pub fn flag(knob: &Knob) -> String {
    format!("--{}", knob.name)
}

/// `--NAME VALUE`, the command line that sets `knob` to `value`.
pub fn setting(knob: &Knob, value: Value) -> String {
    format!("{} {}", flag(knob), knob.format(value))
}

/// A knob's value parser: its own [`Knob::parse`], with its names in `--help`.
#[derive(Clone, Copy)]
struct KnobParser(&'static Knob);

impl TypedValueParser for KnobParser {
    type Value = Value;

    fn parse_ref(
        &self,
        cmd: &Command,
        _: Option<&Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<Value, clap::Error> {
        let text = value.to_string_lossy();
        self.0
            .parse(&text)
            .map_err(|e| super::values::invalid(cmd, None, &e.to_string()))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        match self.0.kind {
            Kind::Switch { off, on } => {
                Some(Box::new([on, off].into_iter().map(PossibleValue::new)))
            }
            Kind::Choice(names) => Some(Box::new(names.iter().map(|&n| PossibleValue::new(n)))),
            _ => None,
        }
    }
}

/// The help line of `knob`: its doc, its range and its default.
fn help(knob: &Knob) -> String {
    let range = match knob.kind {
        Kind::Switch { .. } | Kind::Choice(_) => String::new(),
        kind => format!("; {}", kind.range()),
    };
    format!(
        "{} [default: {}{range}]",
        knob.doc,
        knob.format(knob.default)
    )
}

/// `cmd` with a flag for every knob of `knobs` that acts on `acts`, under its heading.
pub fn augment(mut cmd: Command, knobs: &Knobs, acts: Acts) -> Command {
    for knob in knobs.iter().filter(|k| k.acts.meets(acts)) {
        let (placeholder, list) = match knob.kind {
            Kind::Choice(_) => ("NAME".to_string(), true),
            kind => (kind.placeholder(), false),
        };
        cmd = cmd.arg(
            Arg::new(knob.name)
                .long(knob.name)
                .value_name(placeholder)
                .help(help(knob))
                .help_heading(knob.group.0)
                .hide_possible_values(!list)
                .action(ArgAction::Set)
                .value_parser(KnobParser(knob)),
        );
    }
    cmd
}

/// The knobs `matches` sets, in declaration order.
pub fn settings(matches: &ArgMatches, knobs: &Knobs, acts: Acts) -> Settings {
    let mut out = Settings::default();
    for knob in knobs.iter().filter(|k| k.acts.meets(acts)) {
        if let Ok(Some(v)) = matches.try_get_one::<Value>(knob.name) {
            out.set(knob, *v);
        }
    }
    out
}

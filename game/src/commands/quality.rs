//! `lumen quality show PRESET`: a preset as the TOML file `--quality-file` reads.

use crate::cli::{QualityArgs, QualityCommand};
use lumen::choice::Choice;
use lumen::quality::{Knobs, QualityPreset};

/// The text of `lumen quality show PRESET` with the knobs of `knobs`.
pub fn show(knobs: &Knobs, preset: QualityPreset) -> String {
    lumen::quality::preset::show(
        &preset.quality(),
        knobs,
        &format!(
            "Lumen quality preset `{}`: every knob, as `--quality-file FILE` reads it",
            preset.name()
        ),
    )
}

/// Runs `lumen quality`.
pub fn run(args: &QualityArgs, knobs: &Knobs) -> anyhow::Result<()> {
    match args.command {
        QualityCommand::Show { preset } => crate::output::print(&show(knobs, preset)),
    }
    Ok(())
}

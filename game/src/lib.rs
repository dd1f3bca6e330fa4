//! The `lumen` command's pieces, as a library so the workspace tests can use the built-in
//! scenes and argument parsing.

pub mod bench;
pub mod cli;
pub mod convert_cmd;
pub mod examples;
pub mod materials;
pub mod measure;
pub mod output;
pub mod progress;
pub mod reference_cmd;
pub mod render_cmd;
pub mod scenes;
pub mod setup;
pub mod tradeoff;
pub mod validate_cmd;
pub mod view;

//! The `lumen` command's pieces, as a library so the workspace tests can use the built-in
//! scenes and argument parsing.

pub mod cli;
pub mod commands;
pub mod examples;
pub mod materials;
pub mod measure;
pub mod output;
pub mod progress;
pub mod scenes;
pub mod sequence;
pub mod setup;
pub mod shard;

/// The viewer's window, for scripts ([`view::show`]).
pub use commands::view;

//! The `lumen` subcommands, one module each, named after the command (`lumen bench` is
//! [`mod@bench`]). What several commands share — scene setup, frame measurement, output and
//! progress — lives beside this module.

pub mod bench;
pub mod convert;
pub mod merge;
pub mod quality;
pub mod reference;
pub mod render;
pub mod tradeoff;
pub mod validate;
pub mod view;

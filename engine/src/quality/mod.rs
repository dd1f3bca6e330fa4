//! Speed/accuracy knobs. Each is a field of [`Quality`], declared once as a [`Knob`] (its
//! name, doc, range, default, the passes that read it and its tradeoff sweep: [`knob`],
//! [`knobs`]); [`QualityPreset`] sets them all at once from a TOML file ([`preset`]).

pub mod knob;
pub mod knobs;
pub mod preset;
mod settings;

pub use knob::{Knob, KnobError, Knobs, Settings};
pub use settings::{
    AaMethod, AaSettings, AoResolution, AoSettings, GiSettings, HdrPrecision, MAX_ACCUMULATE,
    Quality, QualityPreset, ReflectionProbeSettings, ShadowFilter, ShadowMask, SpecularAaForm,
    SpecularAaSettings, SsrSettings, Transparency,
};

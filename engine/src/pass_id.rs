//! The names of the frame's passes. Each pass module defines its own
//! (`impl PassId { pub const Shadow: PassId = … }` beside the pass), so adding a pass
//! touches nothing else; knobs name the passes that read them by these
//! ([`crate::quality::Knob::passes`]).

/// A pass's name: how reports, timers, `--explain` and the JSON plan call it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PassId(&'static str);

impl PassId {
    /// A pass named `name`.
    pub const fn new(name: &'static str) -> PassId {
        PassId(name)
    }

    /// Short name used in reports and JSON.
    pub const fn name(self) -> &'static str {
        self.0
    }
}

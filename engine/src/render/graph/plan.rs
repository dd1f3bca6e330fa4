//! This frame's plan: every pass's decision and shader features in execution order, the
//! variants the passes compile, and the lifetimes of the frame's slots.

use super::{FramePass, PassId, Slot};
use bevy_ecs::prelude::*;
use std::any::Any;
use std::sync::Arc;

/// Whether a pass or shader feature is used this frame, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decision {
    /// Pass or feature name.
    pub name: &'static str,
    /// Whether it runs / is compiled in.
    pub enabled: bool,
    /// Why, in a few words.
    pub reason: String,
}

impl Decision {
    /// A decision about `name`.
    pub fn new(name: &'static str, enabled: bool, reason: impl Into<String>) -> Decision {
        Decision {
            name,
            enabled,
            reason: reason.into(),
        }
    }
}

/// What a pass's `decide` returns.
#[derive(Clone, Debug, PartialEq)]
pub struct PassDecision<V> {
    /// Whether it runs, and why.
    pub runs: bool,
    /// The words `--explain` prints.
    pub reason: String,
    /// The shader features it compiles in or leaves out, each with its reason.
    pub features: Vec<Decision>,
    /// Its shader variant.
    pub variant: V,
}

impl<V> PassDecision<V> {
    /// A decision with no shader features.
    pub fn new(runs: bool, reason: impl Into<String>, variant: V) -> Self {
        PassDecision {
            runs,
            reason: reason.into(),
            features: Vec::new(),
            variant,
        }
    }
}

/// The passes that read or write a slot this frame, in execution order: the slot must
/// exist from `first` to `last`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Lifetime {
    /// The slot.
    pub slot: Slot,
    /// The first pass that uses it.
    pub first: PassId,
    /// The last pass that uses it.
    pub last: PassId,
}

/// This frame's plan, made by the registry from every pass's `decide`.
#[derive(Resource, Clone, Debug, Default)]
pub struct FramePlan {
    /// One decision per pass, in execution order.
    pub passes: Vec<(PassId, Decision)>,
    /// Shader features of the passes, in execution order.
    pub features: Vec<Decision>,
    /// The slots the passes that run use, with their lifetimes, in order of first use.
    pub lifetimes: Vec<Lifetime>,
    variants: Vec<(PassId, Arc<dyn Any + Send + Sync>, String)>,
}

impl PartialEq for FramePlan {
    fn eq(&self, other: &Self) -> bool {
        self.passes == other.passes
            && self.features == other.features
            && self.lifetimes == other.lifetimes
            && self
                .variants
                .iter()
                .map(|(id, _, text)| (id, text))
                .eq(other.variants.iter().map(|(id, _, text)| (id, text)))
    }
}

impl FramePlan {
    /// Whether `pass` runs this frame.
    pub fn runs(&self, pass: PassId) -> bool {
        self.passes.iter().any(|(p, d)| *p == pass && d.enabled)
    }

    /// The variant pass `P` decided on this frame.
    pub fn variant<P: FramePass>(&self) -> Option<&P::Variant> {
        self.variants
            .iter()
            .find(|(id, _, _)| *id == P::ID)
            .and_then(|(_, v, _)| v.downcast_ref::<P::Variant>())
    }

    /// Each pass's variant, as `Debug` text, in execution order.
    pub fn variant_texts(&self) -> impl Iterator<Item = (PassId, &str)> {
        self.variants
            .iter()
            .map(|(id, _, text)| (*id, text.as_str()))
    }

    /// Records pass `P`'s decision.
    pub fn push<P: FramePass>(&mut self, decision: PassDecision<P::Variant>) {
        let PassDecision {
            runs,
            reason,
            features,
            variant,
        } = decision;
        self.passes
            .push((P::ID, Decision::new(P::ID.name(), runs, reason)));
        self.features.extend(features);
        let text = format!("{variant:?}");
        self.variants.push((P::ID, Arc::new(variant), text));
    }

    /// A human-readable account of the plan (`lumen render --explain`).
    pub fn explain(&self) -> String {
        let mut out = String::from("passes:\n");
        for (_, d) in &self.passes {
            out.push_str(&format!(
                "  {:<10} {:<4} {}\n",
                d.name,
                if d.enabled { "run" } else { "skip" },
                d.reason
            ));
        }
        out.push_str("shader features:\n");
        for d in &self.features {
            out.push_str(&format!(
                "  {:<22} {:<3} {}\n",
                d.name,
                if d.enabled { "on" } else { "off" },
                d.reason
            ));
        }
        out
    }

    /// The slots and their lifetimes, one line each (the viewer's frame graph panel).
    pub fn explain_lifetimes(&self) -> String {
        let mut out = String::new();
        for l in &self.lifetimes {
            out.push_str(&format!(
                "  {:<40} {} → {}\n",
                l.slot.name,
                l.first.name(),
                l.last.name()
            ));
        }
        out
    }
}

//! The frame graph: every pass describes itself, and the registry derives the frame.
//!
//! A pass is one module behind the [`FramePass`] trait. It gives its [`PassId`] (the name
//! reports, timers and `--explain` use), the frame resources ([`Slot`]s) it reads and
//! writes, a `decide` function (does it run this frame, why, and which shader variant it
//! compiles, as a named struct), and its `prepare` and `record` systems. The built-in
//! passes are registered in one list, [`crate::render::passes::builtin`]; a script adds its
//! own with [`crate::App::add_pass`].
//!
//! From those declarations the [`registry::Registry`] derives everything else:
//! - the execution order: a topological order of the dependencies that the declared reads
//!   and writes imply (see [`registry`]);
//! - the run conditions: each pass's systems run only when its decision says so;
//! - the frame resources: a [`SlotKind::Texture`] or [`SlotKind::Buffer`] exists when a
//!   pass that runs this frame uses it, sized as its description says; the plan records
//!   each one's lifetime (first and last pass that touch it), and textures whose lifetimes
//!   do not overlap share memory (see [`resources`]);
//! - the timer labels (the pass's name), the `--explain` text and the JSON plan
//!   ([`FramePlan`]).
//!
//! # Why this design
//!
//! Two models were studied. Filament's FrameGraph builds a graph every frame: `addPass`
//! declares reads and writes of virtual resources, the graph culls passes whose results
//! nobody reads, allocates transient textures for exactly their lifetimes, and executes
//! the passes in the order they were added. Bevy's render graph (and, since 0.16, its
//! "passes are systems in ordered sets") makes each pass an ECS system and gets the order
//! from explicit edges between them.
//!
//! Lumen takes the declaration side from Filament and the execution side from Bevy. The
//! frame is already a `bevy_ecs` schedule, and passes already keep their pipelines and
//! bindings in ECS resources, so a pass stays a pair of systems and the registry builds the
//! schedule once (not every frame). What changes per frame — which passes run, which
//! variant they compile, which targets exist — is decided by the plan system at the start
//! of the schedule, from the scene, as Filament decides it when it builds its graph. The
//! order is the one Filament uses (registration order, the order of `addPass`), checked
//! and made explicit by the dependencies the declarations imply: a pass that reads a slot
//! no earlier pass writes is refused when the registry is built, with a message that names
//! both. Passes are not culled by the graph itself: "model only what the scene requires"
//! is each pass's `decide`, which can say *why* in words.

pub mod registry;
pub mod resources;
pub mod slots;

use crate::error::Result;
use crate::render::bindings::BindGroupSpec;
use crate::render::device::Gpu;
use crate::render::shaders::ShaderDef;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::{IntoScheduleConfigs, ScheduleConfigs};
use bevy_ecs::system::ScheduleSystem;
use std::any::Any;
use std::marker::PhantomData;
use std::sync::Arc;

pub use resources::{
    Assignment, BufferDesc, Extent, Memory, Mips, Sizing, Slot, SlotKind, TargetFormat, TextureDesc,
};

pub use crate::pass_id::PassId;

/// A fact a pass decides and later passes read in their own decisions (does AO run?
/// which shadow-mask scale?), typed. The pass that decides it declares it in
/// [`FramePass::PUBLISHES`] and gives its value in its decision
/// ([`PassDecision::publishing`]); a pass that reads it declares it in
/// [`FramePass::CONSULTS`], and the registry orders the two and refuses a read that no
/// earlier pass publishes.
pub struct Fact<T> {
    /// Its name.
    pub id: FactId,
    marker: PhantomData<fn() -> T>,
}

impl<T> Fact<T> {
    /// A fact called `name`.
    pub const fn new(name: &'static str) -> Fact<T> {
        Fact {
            id: FactId(name),
            marker: PhantomData,
        }
    }
}

/// A fact's name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FactId(pub &'static str);

/// One pass of the frame. Implemented by a pass's resource (its pipelines and bindings);
/// see the [module documentation](self) for what the registry derives from it.
pub trait FramePass: Resource + Sized {
    /// Its name.
    const ID: PassId;
    /// The slots it reads.
    const READS: &'static [Slot];
    /// The slots it writes (a slot it reads and writes is in both lists).
    const WRITES: &'static [Slot];
    /// The slots it writes only in the frames whose decision names them
    /// ([`PassDecision::writing`]): ordered like [`FramePass::WRITES`], allocated only
    /// in those frames (the G-buffer's motion vectors exist only while TAA runs).
    const OPTIONAL_WRITES: &'static [Slot] = &[];
    /// The facts its decision gives ([`Fact`]).
    const PUBLISHES: &'static [FactId] = &[];
    /// The facts of earlier passes its decision reads.
    const CONSULTS: &'static [FactId] = &[];
    /// Whether it also runs when a probe captures the lit scene around it
    /// ([`crate::render::indirect::probe_volume`]): the passes that make lit HDR
    /// radiance (shadows, G-buffer, light culling, lighting, sky) do; screen-space,
    /// exposure and post-processing passes do not.
    const CAPTURE: bool = false;
    /// Its shader variant key: what `decide` selects for the frame, as a named struct.
    type Variant: std::fmt::Debug + Send + Sync + 'static;

    /// Creates the pass (layouts, the pipelines that do not depend on the scene) from
    /// `world`, which holds the renderer's shared resources.
    fn create(world: &mut World, gpu: &Gpu) -> Result<Self>;

    /// Whether it runs this frame, why, which shader features it compiles in and its
    /// variant. `plan` holds the decisions of the passes before it: it reads their
    /// [`FramePass::CONSULTS`] facts with [`FramePlan::fact`].
    fn decide(world: &World, plan: &FramePlan) -> PassDecision<Self::Variant>;

    /// The systems that compile this frame's variant and update bindings; they run only
    /// when the pass runs.
    fn prepare() -> Option<ScheduleConfigs<ScheduleSystem>> {
        None
    }

    /// The systems that record the pass into the frame's command encoder; they run only
    /// when the pass runs.
    fn record() -> ScheduleConfigs<ScheduleSystem>;

    /// What to record instead when the pass does not run (e.g. clearing what later passes
    /// read); nothing by default.
    fn skipped() -> Option<ScheduleConfigs<ScheduleSystem>> {
        None
    }

    /// The shader builds it compiles: each variant, or where the variants are too many to
    /// list, enough of them that every shader def takes each of its values. The tests
    /// check each build against its WGSL, with no GPU (`tests/bindings.rs`); a built-in
    /// pass with a shader must list it.
    fn shader_builds() -> Vec<ShaderBuild> {
        Vec::new()
    }
}

/// One shader build of a pass: what the tests compose, validate with naga and compare
/// with the bind group lists the pass builds its layouts from.
#[derive(Clone, Debug)]
pub struct ShaderBuild {
    /// The entry file of `shaders/`.
    pub shader: &'static str,
    /// The variant's shader defs.
    pub defs: Vec<ShaderDef>,
    /// Each bind group the pass binds, as (group index, its list); none where the pass
    /// derives its layouts from the shader (the build is then only validated).
    pub groups: Vec<(u32, BindGroupSpec)>,
}

impl ShaderBuild {
    /// `shader` composed with `defs`, binding `groups`.
    pub fn new(
        shader: &'static str,
        defs: Vec<ShaderDef>,
        groups: &[(u32, BindGroupSpec)],
    ) -> ShaderBuild {
        ShaderBuild {
            shader,
            defs,
            groups: groups.to_vec(),
        }
    }
}

/// The systems a pass schedules ([`FramePass::prepare`], [`FramePass::record`],
/// [`FramePass::skipped`]).
pub type PassSystems = ScheduleConfigs<ScheduleSystem>;

/// `system` (a system function, or systems chained) as [`PassSystems`].
pub fn systems<M>(system: impl IntoScheduleConfigs<ScheduleSystem, M>) -> PassSystems {
    system.into_configs()
}

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
#[derive(Clone, Debug)]
pub struct PassDecision<V> {
    /// Whether it runs, and why.
    pub runs: bool,
    /// The words `--explain` prints.
    pub reason: String,
    /// The shader features it compiles in or leaves out, each with its reason.
    pub features: Vec<Decision>,
    /// Its shader variant.
    pub variant: V,
    /// The slots of its [`FramePass::OPTIONAL_WRITES`] it writes this frame.
    pub writes: Vec<Slot>,
    /// The extent, format or bytes of its slots that the frame decides.
    pub sizes: Vec<(Slot, Sizing)>,
    /// The values of its [`FramePass::PUBLISHES`] facts.
    pub facts: Vec<(FactId, Arc<dyn Any + Send + Sync>)>,
}

impl<V> PassDecision<V> {
    /// A decision with no shader features.
    pub fn new(runs: bool, reason: impl Into<String>, variant: V) -> Self {
        PassDecision {
            runs,
            reason: reason.into(),
            features: Vec::new(),
            variant,
            writes: Vec::new(),
            sizes: Vec::new(),
            facts: Vec::new(),
        }
    }

    /// The same decision, giving slot `slot` this frame's extent (and format) or bytes.
    pub fn sized(mut self, slot: Slot, sizing: Sizing) -> Self {
        self.sizes.push((slot, sizing));
        self
    }

    /// The same decision, giving fact `fact` the value `value`.
    pub fn publishing<T: Send + Sync + 'static>(mut self, fact: &Fact<T>, value: T) -> Self {
        self.facts.push((fact.id, Arc::new(value)));
        self
    }

    /// The same decision, writing the optional slot `slot` when `writes` holds.
    pub fn writing(mut self, slot: Slot, writes: bool) -> Self {
        if writes {
            self.writes.push(slot);
        }
        self
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
    /// The frame's textures and buffers, their sizes and the physical resources that hold
    /// them ([`resources`]).
    pub resources: Assignment,
    variants: Vec<(PassId, Arc<dyn Any + Send + Sync>)>,
    /// The optional slots each pass writes this frame.
    optional_writes: Vec<(PassId, Vec<Slot>)>,
    /// The decided sizes of slots.
    sizes: Vec<(Slot, Sizing)>,
    /// The facts the passes decided.
    facts: Vec<(FactId, Arc<dyn Any + Send + Sync>)>,
}

impl FramePlan {
    /// Whether `pass` runs this frame.
    pub fn runs(&self, pass: PassId) -> bool {
        self.passes.iter().any(|(p, d)| *p == pass && d.enabled)
    }

    /// `pass`'s decision this frame (whether it runs, and why), if it is registered.
    pub fn decision(&self, pass: PassId) -> Option<&Decision> {
        self.passes.iter().find(|(p, _)| *p == pass).map(|(_, d)| d)
    }

    /// The variant pass `P` decided on this frame.
    pub fn variant<P: FramePass>(&self) -> Option<&P::Variant> {
        self.variants
            .iter()
            .find(|(id, _)| *id == P::ID)
            .and_then(|(_, v)| v.downcast_ref::<P::Variant>())
    }

    /// Whether `pass` writes `slot`, one of its optional writes, this frame.
    pub fn writes_optional(&self, pass: PassId, slot: Slot) -> bool {
        self.optional_writes
            .iter()
            .any(|(p, slots)| *p == pass && slots.contains(&slot))
    }

    /// The value an earlier pass gave fact `fact` this frame, if it gave one.
    pub fn fact<T: 'static>(&self, fact: &Fact<T>) -> Option<&T> {
        self.facts
            .iter()
            .find(|(id, _)| *id == fact.id)
            .and_then(|(_, v)| v.downcast_ref::<T>())
    }

    /// The sizing a decision gave `slot` this frame.
    pub fn sizing(&self, slot: Slot) -> Option<Sizing> {
        self.sizes.iter().find(|(s, _)| *s == slot).map(|(_, z)| *z)
    }

    /// Bytes this frame's resources take.
    pub fn memory(&self) -> Memory {
        self.resources.memory()
    }

    /// Records pass `P`'s decision. Optional writes, sizes and facts it did not declare
    /// ([`FramePass::OPTIONAL_WRITES`], its slots, [`FramePass::PUBLISHES`]) are dropped.
    pub fn push<P: FramePass>(&mut self, decision: PassDecision<P::Variant>) {
        let PassDecision {
            runs,
            reason,
            features,
            variant,
            writes,
            sizes,
            facts,
        } = decision;
        self.sizes.extend(
            sizes
                .into_iter()
                .filter(|(s, _)| P::WRITES.contains(s) || P::OPTIONAL_WRITES.contains(s)),
        );
        self.facts.extend(
            facts
                .into_iter()
                .filter(|(id, _)| P::PUBLISHES.contains(id)),
        );
        self.passes
            .push((P::ID, Decision::new(P::ID.name(), runs, reason)));
        self.features.extend(features);
        self.variants.push((P::ID, Arc::new(variant)));
        let writes: Vec<Slot> = writes
            .into_iter()
            .filter(|s| P::OPTIONAL_WRITES.contains(s))
            .collect();
        self.optional_writes.push((P::ID, writes));
    }

    /// A human-readable account of the plan (`lumen render --explain`).
    pub fn explain(&self) -> String {
        let mut out = String::from("passes:\n");
        for (_, d) in &self.passes {
            out.push_str(&format!(
                "  {:<11} {:<4} {}\n",
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
        out.push_str(&self.explain_resources());
        out
    }

    /// The `resources:` part of [`FramePlan::explain`]: each physical texture or buffer,
    /// what it holds and the bytes, with and without sharing.
    fn explain_resources(&self) -> String {
        let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
        let mut out = String::from("resources:\n");
        for p in &self.resources.physical {
            let what = match p.shape {
                resources::Shape::Texture(class, levels, _) => format!(
                    "{:?} {}x{}{}",
                    class.format,
                    class.size.0,
                    class.size.1,
                    if levels > 1 {
                        format!(" ({levels} mips)")
                    } else {
                        String::new()
                    }
                ),
                resources::Shape::Buffer(bytes, _) => format!("buffer of {bytes} B"),
            };
            out.push_str(&format!(
                "  {:<36} {:>8.2} MiB  {}{}\n",
                what,
                mib(p.shape.bytes()),
                p.holds.join(", "),
                if p.kept.is_some() { " (kept)" } else { "" }
            ));
        }
        let m = self.memory();
        let saved = if m.texture_bytes_unaliased > 0 {
            100.0 * (1.0 - m.texture_bytes as f64 / m.texture_bytes_unaliased as f64)
        } else {
            0.0
        };
        out.push_str(&format!(
            "  textures {:.2} MiB ({:.2} MiB without aliasing, {saved:.1} % less); buffers {:.2} MiB\n",
            mib(m.texture_bytes),
            mib(m.texture_bytes_unaliased),
            mib(m.buffer_bytes)
        ));
        out
    }
}

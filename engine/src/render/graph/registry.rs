//! The registry: the list of passes, and what it derives from their declarations.
//!
//! # Execution order
//!
//! Registration order is the order of intent, like the order of `addPass` calls in
//! Filament's FrameGraph: when two passes touch the same slot, the one registered first
//! sees it first. From the declared reads and writes the registry derives the
//! dependencies, per slot, walking the passes in registration order:
//! - a pass that reads a slot depends on the last pass before it that wrote it (and a read
//!   with no earlier writer is an error that names the pass and the slot);
//! - a pass that writes a slot depends on the last writer before it and on every reader
//!   since that write (it must not overwrite what they have not read yet).
//!
//! A pass's optional writes ([`FramePass::OPTIONAL_WRITES`]) order it like its writes; its
//! decision says in which frames it makes them, and only then does the slot get a
//! lifetime (and a target).
//!
//! The execution order is a topological order of those dependencies (Kahn's algorithm,
//! ties broken by registration order), and a pass's prepare and record systems are
//! chained in that order in the render schedule.

use super::{FramePass, FramePlan, Lifetime, PassId, Slot};
use crate::error::{Error, Result};
use crate::render::device::Gpu;
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::ScheduleConfigs;
use bevy_ecs::system::ScheduleSystem;

/// Builds a pass's optional systems for a schedule.
type OptionalSystems = fn() -> Option<ScheduleConfigs<ScheduleSystem>>;

/// One registered pass, with its type erased.
#[derive(Clone, Copy)]
pub struct PassEntry {
    /// Its name.
    pub id: PassId,
    /// The slots it reads.
    pub reads: &'static [Slot],
    /// The slots it writes.
    pub writes: &'static [Slot],
    /// The slots it writes in the frames its decision says so.
    pub optional_writes: &'static [Slot],
    /// Whether it runs in probe captures ([`FramePass::CAPTURE`]).
    pub capture: bool,
    create: fn(&mut World, &Gpu) -> Result<()>,
    decide: fn(&World, &mut FramePlan),
    prepare: OptionalSystems,
    record: fn() -> ScheduleConfigs<ScheduleSystem>,
    skipped: OptionalSystems,
}

impl std::fmt::Debug for PassEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassEntry")
            .field("id", &self.id)
            .field("reads", &self.reads)
            .field("writes", &self.writes)
            .field("optional_writes", &self.optional_writes)
            .finish_non_exhaustive()
    }
}

impl PassEntry {
    /// The entry of pass `P`.
    pub fn of<P: FramePass>() -> PassEntry {
        PassEntry {
            id: P::ID,
            reads: P::READS,
            writes: P::WRITES,
            optional_writes: P::OPTIONAL_WRITES,
            capture: P::CAPTURE,
            create: |world, gpu| {
                let pass = P::create(world, gpu)?;
                world.insert_resource(pass);
                Ok(())
            },
            decide: |world, plan| {
                let decision = P::decide(world, plan);
                plan.push::<P>(decision);
            },
            prepare: P::prepare,
            record: P::record,
            skipped: P::skipped,
        }
    }
}

/// The passes of the frame, in execution order once [`Registry::ordered`] has checked
/// them.
#[derive(Resource, Clone, Debug, Default)]
pub struct Registry {
    entries: Vec<PassEntry>,
}

impl Registry {
    /// No passes.
    pub fn new() -> Registry {
        Registry::default()
    }

    /// Registers pass `P` after the passes registered so far.
    pub fn with<P: FramePass>(mut self) -> Registry {
        self.entries.push(PassEntry::of::<P>());
        self
    }

    /// Checks the declarations (unique names, no read before a write) and puts the passes
    /// in execution order (see the [module documentation](self)).
    pub fn ordered(self) -> Result<Registry> {
        let n = self.entries.len();
        for (i, e) in self.entries.iter().enumerate() {
            if let Some(other) = self.entries[..i].iter().find(|o| o.id == e.id) {
                return Err(Error::InvalidArgument(format!(
                    "frame graph: two passes are named '{}' ({:?} and {:?})",
                    e.id.name(),
                    other,
                    e
                )));
            }
        }
        let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut slots: Vec<Slot> = Vec::new();
        for e in &self.entries {
            for s in e.reads.iter().chain(e.writes).chain(e.optional_writes) {
                if !slots.contains(s) {
                    slots.push(*s);
                }
            }
        }
        for slot in slots {
            let mut last_writer: Option<usize> = None;
            let mut readers: Vec<usize> = Vec::new();
            for (i, e) in self.entries.iter().enumerate() {
                if e.reads.contains(&slot) {
                    match last_writer {
                        Some(w) => after[i].push(w),
                        None => {
                            return Err(Error::InvalidArgument(format!(
                                "frame graph: pass '{}' reads '{}', which no pass registered before it writes",
                                e.id.name(),
                                slot.name
                            )));
                        }
                    }
                    readers.push(i);
                }
                if e.writes.contains(&slot) || e.optional_writes.contains(&slot) {
                    after[i].extend(last_writer);
                    after[i].extend(readers.drain(..).filter(|&r| r != i));
                    last_writer = Some(i);
                }
            }
        }
        let mut done = vec![false; n];
        let mut order = Vec::with_capacity(n);
        while order.len() < n {
            let next = (0..n)
                .find(|&i| !done[i] && after[i].iter().all(|&d| done[d]))
                .ok_or_else(|| {
                    Error::InvalidArgument(
                        "frame graph: the passes' reads and writes form a cycle".into(),
                    )
                })?;
            done[next] = true;
            order.push(self.entries[next]);
        }
        Ok(Registry { entries: order })
    }

    /// The passes' names, in order.
    pub fn ids(&self) -> Vec<PassId> {
        self.entries.iter().map(|e| e.id).collect()
    }

    /// The passes that run in probe captures, in the same order.
    pub fn capture_subset(&self) -> Registry {
        Registry {
            entries: self.entries.iter().filter(|e| e.capture).copied().collect(),
        }
    }

    /// Creates every pass's resource in `world`.
    pub fn create_passes(&self, world: &mut World, gpu: &Gpu) -> Result<()> {
        for e in &self.entries {
            (e.create)(world, gpu)?;
        }
        Ok(())
    }

    /// This frame's plan: every pass's decision in execution order, then the lifetimes of
    /// the slots the passes that run use.
    pub fn plan(&self, world: &World) -> FramePlan {
        let mut plan = FramePlan::default();
        for e in &self.entries {
            (e.decide)(world, &mut plan);
        }
        let running: Vec<&PassEntry> = self.entries.iter().filter(|e| plan.runs(e.id)).collect();
        for e in running {
            let optional: Vec<Slot> = e
                .optional_writes
                .iter()
                .copied()
                .filter(|s| plan.writes_optional(e.id, *s))
                .collect();
            for slot in e.reads.iter().chain(e.writes).chain(&optional) {
                match plan.lifetimes.iter_mut().find(|l| l.slot == *slot) {
                    Some(l) => l.last = e.id,
                    None => plan.lifetimes.push(Lifetime {
                        slot: *slot,
                        first: e.id,
                        last: e.id,
                    }),
                }
            }
        }
        plan
    }

    /// Adds the passes' systems to `schedule`, after `before_prepare` (the systems every
    /// pass's preparation needs) and around `begin_frame`: the passes' prepare systems in
    /// execution order, then `begin_frame`, then each pass's record systems (or, when it
    /// does not run, its `skipped` systems), then `after_record`. Every system of a pass
    /// runs only when the plan says the pass runs.
    pub fn add_systems(
        &self,
        schedule: &mut Schedule,
        before_prepare: Vec<ScheduleConfigs<ScheduleSystem>>,
        begin_frame: ScheduleConfigs<ScheduleSystem>,
        after_record: Vec<ScheduleConfigs<ScheduleSystem>>,
    ) {
        let mut steps: Vec<ScheduleConfigs<ScheduleSystem>> = before_prepare;
        for e in &self.entries {
            if let Some(prepare) = (e.prepare)() {
                steps.push(prepare.run_if(pass_runs(e.id)));
            }
        }
        steps.push(begin_frame);
        for e in &self.entries {
            steps.push((e.record)().run_if(pass_runs(e.id)));
            if let Some(skipped) = (e.skipped)() {
                steps.push(skipped.run_if(not(pass_runs(e.id))));
            }
        }
        steps.extend(after_record);
        for (i, step) in steps.into_iter().enumerate() {
            schedule.add_systems(step.in_set(Step(i)));
            if i > 0 {
                schedule.configure_sets(Step(i).after(Step(i - 1)));
            }
        }
    }
}

/// The position of a system in the render schedule's chain.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Step(usize);

/// Run condition: `pass` runs this frame.
pub fn pass_runs(pass: PassId) -> impl Fn(Res<FramePlan>) -> bool + Clone {
    move |plan: Res<FramePlan>| plan.runs(pass)
}

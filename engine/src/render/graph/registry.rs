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
//! A fact ([`super::Fact`]) orders its readers the same way: a pass that consults a fact
//! depends on the last pass before it that publishes it; a fact that only a later pass
//! publishes is an error that names both, and a fact no pass of the registry publishes
//! is absent from every plan (a frame without a shadow mask pass has no mask).
//!
//! The execution order is a topological order of those dependencies (Kahn's algorithm,
//! ties broken by registration order), and a pass's prepare and record systems are
//! chained in that order in the render schedule.
//!
//! # Resources
//!
//! Each frame, [`Registry::plan`] collects the texture and buffer slots the running passes
//! use, with their lifetimes and the sizes their decisions give, and assigns them physical
//! resources ([`super::resources::assign`]); the frame's targets are then allocated from
//! that assignment ([`crate::render::targets`]).

use super::resources::{self, Extent, Planned, Shape, Sizing, TargetFormat, TextureClass};
use super::slots::KeptSlots;
use super::{FactId, FramePass, FramePlan, Lifetime, PassId, ShaderBuild, Slot, SlotKind};
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
    /// The facts it publishes.
    pub publishes: &'static [FactId],
    /// The facts it consults.
    pub consults: &'static [FactId],
    /// Whether it runs in probe captures ([`FramePass::CAPTURE`]).
    pub capture: bool,
    /// Its shader builds ([`FramePass::shader_builds`]).
    pub shader_builds: fn() -> Vec<ShaderBuild>,
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
            publishes: P::PUBLISHES,
            consults: P::CONSULTS,
            capture: P::CAPTURE,
            shader_builds: P::shader_builds,
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
        for (i, e) in self.entries.iter().enumerate() {
            for fact in e.consults {
                match self.entries[..i]
                    .iter()
                    .rposition(|p| p.publishes.contains(fact))
                {
                    Some(publisher) => after[i].push(publisher),
                    None => {
                        if let Some(later) = self.entries[i..]
                            .iter()
                            .find(|p| p.publishes.contains(fact))
                        {
                            return Err(Error::InvalidArgument(format!(
                                "frame graph: pass '{}' consults fact '{}', which only '{}', registered after it, publishes",
                                e.id.name(),
                                fact.0,
                                later.id.name()
                            )));
                        }
                    }
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

    /// Each pass's name and shader builds ([`FramePass::shader_builds`]), in order.
    pub fn shader_builds(&self) -> Vec<(PassId, Vec<ShaderBuild>)> {
        self.entries
            .iter()
            .map(|e| (e.id, (e.shader_builds)()))
            .collect()
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
    /// the slots the passes that run use, and the textures and buffers among them, sized
    /// for an output of `output` pixels with HDR colour in `hdr_format`, with the physical
    /// resources that hold them.
    pub fn plan(
        &self,
        world: &World,
        output: (u32, u32),
        hdr_format: wgpu::TextureFormat,
    ) -> FramePlan {
        let mut plan = FramePlan::default();
        for e in &self.entries {
            (e.decide)(world, &mut plan);
        }
        // Per slot: its lifetime, by pass and by index among the running passes, and
        // whether a write comes before every read.
        let mut uses: Vec<(Slot, usize, usize, bool)> = Vec::new();
        let running: Vec<&PassEntry> = self.entries.iter().filter(|e| plan.runs(e.id)).collect();
        for (index, e) in running.iter().enumerate() {
            let optional: Vec<Slot> = e
                .optional_writes
                .iter()
                .copied()
                .filter(|s| plan.writes_optional(e.id, *s))
                .collect();
            for slot in e.reads.iter().chain(e.writes).chain(&optional) {
                let writes = !e.reads.contains(slot);
                match plan.lifetimes.iter_mut().find(|l| l.slot == *slot) {
                    Some(l) => l.last = e.id,
                    None => plan.lifetimes.push(Lifetime {
                        slot: *slot,
                        first: e.id,
                        last: e.id,
                    }),
                }
                match uses.iter_mut().find(|u| u.0 == *slot) {
                    Some(u) => u.2 = index,
                    None => uses.push((*slot, index, index, writes)),
                }
            }
        }
        let kept = world
            .get_resource::<KeptSlots>()
            .cloned()
            .unwrap_or_default();
        let planned = uses
            .into_iter()
            .filter_map(|(slot, first, last, written_first)| {
                let (shape, history) = shape_of(&plan, slot, output, hdr_format)?;
                let history = history || kept.0.contains(&slot);
                Some(Planned {
                    slot,
                    shape,
                    first,
                    last,
                    passes: (running[first].id, running[last].id),
                    written_first,
                    history,
                    physical: usize::MAX,
                })
            })
            .collect();
        plan.resources = resources::assign(planned);
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

/// The shape of a texture or buffer slot this frame, and whether it is a history; `None`
/// for other slots, for a buffer whose size no decision gave and for a texture whose
/// format no decision gave.
fn shape_of(
    plan: &FramePlan,
    slot: Slot,
    output: (u32, u32),
    hdr_format: wgpu::TextureFormat,
) -> Option<(Shape, bool)> {
    match slot.kind {
        SlotKind::Texture(desc) => {
            let decided = match plan.sizing(slot) {
                Some(Sizing::Texture(extent, format)) => Some((extent, format)),
                _ => None,
            };
            // A slot no decision sized (its writer is not registered, as in a probe
            // capture, or does not run) is one texel for the passes that bind it.
            let extent = desc
                .extent
                .or(decided.map(|d| d.0))
                .unwrap_or(Extent::Fixed(1, 1));
            let format = match desc.format {
                TargetFormat::Fixed(f) => f,
                TargetFormat::Hdr => hdr_format,
                TargetFormat::Decided => decided.and_then(|d| d.1)?,
            };
            let size = extent.texels(output);
            let class = TextureClass { format, size };
            Some((
                Shape::Texture(class, desc.mips.levels(size), desc.usage),
                desc.history,
            ))
        }
        SlotKind::Buffer(desc) => match plan.sizing(slot) {
            Some(Sizing::Buffer(bytes)) => {
                Some((Shape::Buffer(bytes.max(16), desc.usage), desc.history))
            }
            _ => None,
        },
        SlotKind::Owned | SlotKind::Output => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::graph::{Extent, Fact, PassDecision, SlotKind, TargetFormat, TextureDesc};
    use bevy_ecs::schedule::IntoScheduleConfigs;

    const RGBA8: TargetFormat = TargetFormat::Fixed(wgpu::TextureFormat::Rgba8Unorm);
    const X: Slot = Slot::texture("x", TextureDesc::full(RGBA8));
    const Y: Slot = Slot::texture("y", TextureDesc::full(RGBA8).at(None));
    const Z: Slot = Slot::texture("z", TextureDesc::full(RGBA8));
    const DIVISOR: Fact<u32> = Fact::new("divisor");

    macro_rules! test_pass {
        ($name:ident, $id:literal, $reads:expr, $writes:expr, $publishes:expr, $consults:expr, $decide:expr) => {
            #[derive(Resource)]
            struct $name;
            impl FramePass for $name {
                const ID: PassId = PassId::new($id);
                const READS: &'static [Slot] = $reads;
                const WRITES: &'static [Slot] = $writes;
                const PUBLISHES: &'static [FactId] = $publishes;
                const CONSULTS: &'static [FactId] = $consults;
                type Variant = u32;
                fn create(_: &mut World, _: &Gpu) -> Result<Self> {
                    Ok($name)
                }
                fn decide(_: &World, plan: &FramePlan) -> PassDecision<u32> {
                    $decide(plan)
                }
                fn record() -> ScheduleConfigs<ScheduleSystem> {
                    (|| {}).into_configs()
                }
            }
        };
    }

    test_pass!(
        Writer,
        "writer",
        &[],
        &[X],
        &[DIVISOR.id],
        &[],
        |_: &FramePlan| { PassDecision::new(true, "writes x", 0).publishing(&DIVISOR, 4) }
    );
    test_pass!(
        Reader,
        "reader",
        &[X],
        &[Y],
        &[],
        &[DIVISOR.id],
        |plan: &FramePlan| {
            let d = plan.fact(&DIVISOR).copied().unwrap_or(1);
            PassDecision::new(true, "reads x", d)
                .sized(Y, Sizing::Texture(Extent::Divided(d), None))
        }
    );
    test_pass!(
        Consumer,
        "consumer",
        &[],
        &[Z],
        &[],
        &[DIVISOR.id],
        |plan: &FramePlan| {
            PassDecision::new(
                true,
                "reads the divisor",
                plan.fact(&DIVISOR).copied().unwrap_or(1),
            )
        }
    );
    test_pass!(Late, "late", &[], &[Z], &[], &[], |_: &FramePlan| {
        PassDecision::new(true, "writes z", 0)
    });
    test_pass!(Idle, "idle", &[Z], &[Z], &[], &[], |_: &FramePlan| {
        PassDecision::new(false, "never", 0)
    });

    #[test]
    fn a_fact_orders_its_reader_after_its_publisher_and_only_a_later_publisher_is_refused() {
        let ordered = Registry::new()
            .with::<Writer>()
            .with::<Reader>()
            .ordered()
            .expect("in order");
        assert_eq!(ordered.ids(), [Writer::ID, Reader::ID]);
        let err = Registry::new()
            .with::<Consumer>()
            .with::<Writer>()
            .ordered()
            .expect_err("the consumer comes first");
        let message = err.to_string();
        assert!(
            message.contains("'consumer' consults fact 'divisor'") && message.contains("'writer'"),
            "{message}"
        );
        // No publisher at all: the fact is absent, and the consumer decides without it.
        let alone = Registry::new().with::<Consumer>().ordered().expect("alone");
        let plan = alone.plan(&World::new(), (8, 8), wgpu::TextureFormat::Rgba16Float);
        assert_eq!(plan.variant::<Consumer>(), Some(&1));
    }

    #[test]
    fn the_plan_sizes_resources_from_decisions_and_shares_memory_between_lifetimes() {
        let registry = Registry::new()
            .with::<Writer>()
            .with::<Reader>()
            .with::<Late>()
            .with::<Idle>()
            .ordered()
            .expect("in order");
        let plan = registry.plan(&World::new(), (64, 48), wgpu::TextureFormat::Rgba16Float);
        assert_eq!(
            plan.variant::<Reader>(),
            Some(&4),
            "the fact reached the reader"
        );
        let y = plan.resources.get(Y).expect("y is planned");
        assert!(
            matches!(y.shape, Shape::Texture(c, 1, _) if c.size == (16, 12)),
            "{y:?}"
        );
        let lifetime = |slot: Slot| {
            let l = plan
                .lifetimes
                .iter()
                .find(|l| l.slot == slot)
                .expect("lifetime");
            (l.first, l.last)
        };
        assert_eq!(lifetime(X), (Writer::ID, Reader::ID));
        assert_eq!(lifetime(Z), (Late::ID, Late::ID));
        // x ends at the reader, z starts after it: one texture holds both; y is smaller.
        let x = plan.resources.get(X).expect("x");
        let z = plan.resources.get(Z).expect("z");
        assert_eq!(x.physical, z.physical);
        assert_ne!(x.physical, y.physical);
        let m = plan.memory();
        assert_eq!(m.texture_bytes_unaliased, 64 * 48 * 4 * 2 + 16 * 12 * 4);
        assert_eq!(m.texture_bytes, 64 * 48 * 4 + 16 * 12 * 4);
        // A pass that does not run uses nothing: its slot's lifetime is the others'.
        assert!(plan.explain().contains("idle        skip never"));
        assert!(matches!(Z.kind, SlotKind::Texture(_)));
        // Kept for the application after the frame, x holds its texture alone.
        let mut world = World::new();
        world.insert_resource(crate::render::graph::slots::KeptSlots(vec![X]));
        let kept = registry.plan(&world, (64, 48), wgpu::TextureFormat::Rgba16Float);
        let (x, z) = (
            kept.resources.get(X).expect("x"),
            kept.resources.get(Z).expect("z"),
        );
        assert_ne!(x.physical, z.physical);
        assert_eq!(kept.memory().texture_bytes, m.texture_bytes_unaliased);
    }
}

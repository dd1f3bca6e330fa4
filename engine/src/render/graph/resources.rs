//! What the graph allocates: the textures and buffers passes declare, and how their
//! memory is shared.
//!
//! A slot declares a texture ([`TextureDesc`]: a format, an extent relative to the output
//! or fixed, one mip or a full chain, transient or history) or a buffer ([`BufferDesc`]).
//! A pass whose slot's extent, format or byte size depends on the frame says so in its
//! decision ([`super::PassDecision::sized`]). From the plan's lifetimes the graph derives,
//! without a GPU, each resource's size and the physical texture or buffer that holds it
//! ([`assign`]):
//! - a **transient** resource lives from the first to the last pass that uses it this
//!   frame, and shares its physical texture with other transient resources of the same
//!   format and size whose lifetimes do not overlap: Filament's FrameGraph aliasing, done
//!   with whole textures because wgpu has no placed resources. A single-mip resource may
//!   live in level 0 of a physical texture that another resource needs with a mip chain;
//! - a resource that the frame reads before any pass writes it, a **history** (a
//!   resource that lives across frames, such as TAA's) and a texture the application reads
//!   after the frame ([`super::slots::KeptSlots`]) get a physical texture of their own;
//! - buffers are never shared (their sizes rarely match).
//!
//! The greedy assignment (each resource, in order of first use, takes the first physical
//! texture of its class that is free over its lifetime) is optimal for interval graphs:
//! a class needs as many physical textures as resources of it are alive at once.

use crate::pass_id::PassId;

/// How a [`Slot`] comes to exist.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SlotKind {
    /// A texture the graph allocates while a pass that runs this frame uses it
    /// (this module).
    Texture(TextureDesc),
    /// A buffer the graph allocates while a pass that runs this frame uses it.
    Buffer(BufferDesc),
    /// A resource a pass keeps to itself between frames (the deformed vertices of each
    /// skinned entity); the graph only orders its users.
    Owned,
    /// The frame's output view, given to the renderer from outside.
    Output,
}

/// A frame resource that passes read and write: a G-buffer channel, depth, HDR colour,
/// the shadow atlas, a half-resolution mask, … Its constant is the typed handle passes
/// get the resource by ([`crate::render::targets::FrameTargets::view`],
/// [`crate::render::targets::FrameTargets::buffer`]). The core slots are in [`super::slots`]; a
/// pass that brings a resource of its own defines its slot in its module.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Slot {
    /// Name, as `--explain`'s lifetimes and error messages give it.
    pub name: &'static str,
    /// How it is allocated.
    pub kind: SlotKind,
}

impl Slot {
    /// A transient texture of `format` at the output's size.
    pub const fn target(name: &'static str, format: TargetFormat) -> Slot {
        Slot::texture(name, TextureDesc::full(format))
    }

    /// A texture the graph allocates as `desc` says.
    pub const fn texture(name: &'static str, desc: TextureDesc) -> Slot {
        Slot {
            name,
            kind: SlotKind::Texture(desc),
        }
    }

    /// A buffer the graph allocates as `desc` says (its size is the decision's).
    pub const fn buffer(name: &'static str, desc: BufferDesc) -> Slot {
        Slot {
            name,
            kind: SlotKind::Buffer(desc),
        }
    }

    /// A resource its pass owns.
    pub const fn owned(name: &'static str) -> Slot {
        Slot {
            name,
            kind: SlotKind::Owned,
        }
    }
}

/// The size of a graph texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Extent {
    /// The output's size.
    Full,
    /// The output's size divided by this (rounded up), e.g. 2 for half resolution.
    Divided(u32),
    /// A fixed size in texels.
    Fixed(u32, u32),
}

impl Extent {
    /// Half the output's size.
    pub const HALF: Extent = Extent::Divided(2);
    /// A quarter of the output's size.
    pub const QUARTER: Extent = Extent::Divided(4);

    /// The size in texels for an output of `output` pixels (at least 1×1).
    pub fn texels(self, output: (u32, u32)) -> (u32, u32) {
        let (w, h) = match self {
            Extent::Full => output,
            Extent::Divided(d) => (output.0.div_ceil(d.max(1)), output.1.div_ceil(d.max(1))),
            Extent::Fixed(w, h) => (w, h),
        };
        (w.max(1), h.max(1))
    }
}

/// The format of a graph texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TargetFormat {
    /// Always this format.
    Fixed(wgpu::TextureFormat),
    /// The HDR colour format that [`crate::quality::Quality::hdr_precision`] selects.
    Hdr,
    /// The format the writing pass's decision gives ([`super::PassDecision::sized`]).
    Decided,
}

/// How many mip levels a graph texture has.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mips {
    /// Level 0 only.
    One,
    /// Every level down to 1×1.
    Chain,
}

impl Mips {
    /// The level count of a texture of `size` texels.
    pub fn levels(self, size: (u32, u32)) -> u32 {
        match self {
            Mips::One => 1,
            Mips::Chain => 32 - size.0.max(size.1).max(1).leading_zeros(),
        }
    }
}

/// A texture the graph allocates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureDesc {
    /// Its format.
    pub format: TargetFormat,
    /// Its size; `None` when the writing pass's decision gives it.
    pub extent: Option<Extent>,
    /// Its mip levels.
    pub mips: Mips,
    /// Whether it lives across frames (a history): never shared, kept while a pass that
    /// uses it runs.
    pub history: bool,
    /// Usages beyond rendering to it, sampling it and copying it.
    pub usage: wgpu::TextureUsages,
}

impl TextureDesc {
    /// A transient single-mip texture of `format` at the output's size.
    pub const fn full(format: TargetFormat) -> TextureDesc {
        TextureDesc {
            format,
            extent: Some(Extent::Full),
            mips: Mips::One,
            history: false,
            usage: wgpu::TextureUsages::empty(),
        }
    }

    /// The same at `extent` (`None`: decided per frame).
    pub const fn at(self, extent: Option<Extent>) -> TextureDesc {
        TextureDesc { extent, ..self }
    }

    /// The same with a full mip chain.
    pub const fn with_mips(self) -> TextureDesc {
        TextureDesc {
            mips: Mips::Chain,
            ..self
        }
    }

    /// The same, kept across frames.
    pub const fn history(self) -> TextureDesc {
        TextureDesc {
            history: true,
            ..self
        }
    }

    /// The same, also bindable as a storage texture.
    pub const fn storage(self) -> TextureDesc {
        TextureDesc {
            usage: wgpu::TextureUsages::STORAGE_BINDING,
            ..self
        }
    }
}

/// A buffer the graph allocates; its size in bytes is the writing pass's decision.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BufferDesc {
    /// Its usages (copies to and from it are always allowed).
    pub usage: wgpu::BufferUsages,
    /// Whether it lives across frames.
    pub history: bool,
}

/// What a decision says about one of its pass's slots this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sizing {
    /// A texture's extent and, for a [`TargetFormat::Decided`] slot, its format.
    Texture(Extent, Option<wgpu::TextureFormat>),
    /// A buffer's size in bytes.
    Buffer(u64),
}

/// A resource's class: resources of one class can share a physical texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureClass {
    /// Texel format.
    pub format: wgpu::TextureFormat,
    /// Size of level 0 in texels.
    pub size: (u32, u32),
}

impl TextureClass {
    /// Bytes of `levels` mip levels (block-compressed and depth-stencil formats count their
    /// copy size; a depth format without one counts 4 bytes a texel).
    pub fn bytes(self, levels: u32) -> u64 {
        let texel = u64::from(self.format.block_copy_size(None).unwrap_or(4));
        (0..levels)
            .map(|l| {
                let w = u64::from((self.size.0 >> l).max(1));
                let h = u64::from((self.size.1 >> l).max(1));
                w * h * texel
            })
            .sum()
    }
}

/// One resource of this frame: a slot that a running pass uses, with what the plan
/// decided about it.
#[derive(Clone, Debug, PartialEq)]
pub struct Planned {
    /// The slot.
    pub slot: Slot,
    /// Its texture class and levels, or its buffer's bytes.
    pub shape: Shape,
    /// Index of the first and last running pass that use it, in execution order.
    pub first: usize,
    /// See `first`.
    pub last: usize,
    /// The first pass that uses it, and the last.
    pub passes: (PassId, PassId),
    /// Whether a pass writes it before any reads it this frame (else it must keep what
    /// the previous frame left and is not shared).
    pub written_first: bool,
    /// Whether it lives across frames.
    pub history: bool,
    /// Index of its physical resource in [`Assignment::physical`].
    pub physical: usize,
}

/// A resource's shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shape {
    /// A texture of this class and this many mip levels, with these extra usages.
    Texture(TextureClass, u32, wgpu::TextureUsages),
    /// A buffer of this many bytes and these usages.
    Buffer(u64, wgpu::BufferUsages),
}

impl Shape {
    /// Its size in bytes.
    pub fn bytes(self) -> u64 {
        match self {
            Shape::Texture(class, levels, _) => class.bytes(levels),
            Shape::Buffer(bytes, _) => bytes,
        }
    }
}

/// One physical texture or buffer, and the resources it holds this frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Physical {
    /// Its shape: the class, the most mip levels and the union of the usages of what it
    /// holds.
    pub shape: Shape,
    /// The slot it is kept for across frames, if it holds a history or a resource that
    /// the frame reads before it writes it: such a resource is found again under its
    /// name next frame, and never shared.
    pub kept: Option<&'static str>,
    /// The slots it holds, in order of use.
    pub holds: Vec<&'static str>,
}

/// The frame's resources and where each lives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Assignment {
    /// Every resource, in order of first use.
    pub resources: Vec<Planned>,
    /// The physical textures and buffers.
    pub physical: Vec<Physical>,
}

/// Bytes a frame's resources take.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Memory {
    /// Texture bytes as allocated (shared physical textures counted once).
    pub texture_bytes: u64,
    /// Texture bytes if every resource had its own texture.
    pub texture_bytes_unaliased: u64,
    /// Buffer bytes.
    pub buffer_bytes: u64,
}

impl Assignment {
    /// The bytes, with and without sharing.
    pub fn memory(&self) -> Memory {
        let mut m = Memory::default();
        for r in &self.resources {
            match r.shape {
                Shape::Texture(..) => m.texture_bytes_unaliased += r.shape.bytes(),
                Shape::Buffer(b, _) => m.buffer_bytes += b,
            }
        }
        m.texture_bytes = self
            .physical
            .iter()
            .filter(|p| matches!(p.shape, Shape::Texture(..)))
            .map(|p| p.shape.bytes())
            .sum();
        m
    }

    /// The planned resource of `slot`, if this frame has it.
    pub fn get(&self, slot: Slot) -> Option<&Planned> {
        self.resources.iter().find(|r| r.slot == slot)
    }
}

/// Assigns each resource of `resources` (with `physical` unset) a physical texture or
/// buffer (see the [module documentation](self)).
pub fn assign(mut resources: Vec<Planned>) -> Assignment {
    resources.sort_by_key(|r| r.first);
    let mut physical: Vec<Physical> = Vec::new();
    // The intervals each physical texture is busy over.
    let mut busy: Vec<Vec<(usize, usize)>> = Vec::new();
    for r in &mut resources {
        let shareable = r.written_first && !r.history && matches!(r.shape, Shape::Texture(..));
        let free = |p: usize, physical: &[Physical], busy: &[Vec<(usize, usize)>]| {
            let same_class = match (physical[p].shape, r.shape) {
                (Shape::Texture(a, ..), Shape::Texture(b, ..)) => a == b,
                _ => false,
            };
            same_class
                && physical[p].kept.is_none()
                && busy[p].iter().all(|&(f, l)| l < r.first || f > r.last)
        };
        let found = if shareable {
            (0..physical.len()).find(|&p| free(p, &physical, &busy))
        } else {
            None
        };
        let p = match found {
            Some(p) => {
                if let (Shape::Texture(class, levels, usage), Shape::Texture(_, l, u)) =
                    (physical[p].shape, r.shape)
                {
                    physical[p].shape = Shape::Texture(class, levels.max(l), usage | u);
                }
                p
            }
            None => {
                let kept = r.history || (!r.written_first && matches!(r.shape, Shape::Texture(..)));
                physical.push(Physical {
                    shape: r.shape,
                    kept: kept.then_some(r.slot.name),
                    holds: Vec::new(),
                });
                busy.push(Vec::new());
                physical.len() - 1
            }
        };
        // A resource that keeps the previous frame's content is busy all frame.
        let interval = if shareable {
            (r.first, r.last)
        } else {
            (0, usize::MAX)
        };
        busy[p].push(interval);
        physical[p].holds.push(r.slot.name);
        r.physical = p;
    }
    Assignment {
        resources,
        physical,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const F16: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

    fn slot(name: &'static str) -> Slot {
        Slot {
            name,
            kind: SlotKind::Owned,
        }
    }

    fn texture(
        name: &'static str,
        size: (u32, u32),
        levels: u32,
        first: usize,
        last: usize,
    ) -> Planned {
        Planned {
            slot: slot(name),
            shape: Shape::Texture(
                TextureClass { format: F16, size },
                levels,
                wgpu::TextureUsages::empty(),
            ),
            first,
            last,
            passes: (PassId::new("a"), PassId::new("b")),
            written_first: true,
            history: false,
            physical: usize::MAX,
        }
    }

    #[test]
    fn extents_round_up_and_mip_chains_reach_one_texel() {
        assert_eq!(Extent::HALF.texels((1919, 1080)), (960, 540));
        assert_eq!(Extent::QUARTER.texels((3, 1)), (1, 1));
        assert_eq!(Extent::Fixed(8, 4).texels((100, 100)), (8, 4));
        assert_eq!(Mips::Chain.levels((1920, 1080)), 11);
        assert_eq!(Mips::Chain.levels((1, 1)), 1);
        assert_eq!(Mips::One.levels((1920, 1080)), 1);
        let class = TextureClass {
            format: F16,
            size: (4, 2),
        };
        assert_eq!(class.bytes(1), 64);
        assert_eq!(class.bytes(3), 64 + 16 + 8);
    }

    #[test]
    fn resources_whose_lifetimes_do_not_overlap_share_a_texture() {
        let a = assign(vec![
            texture("a", (8, 8), 1, 0, 2),
            texture("b", (8, 8), 1, 1, 4),
            texture("c", (8, 8), 1, 3, 5),
            texture("d", (8, 8), 1, 5, 6),
        ]);
        let at: Vec<usize> = a.resources.iter().map(|r| r.physical).collect();
        // a and c share (a ends at 2, c starts at 3); d starts where c ends: not shared.
        assert_eq!(at, [0, 1, 0, 1]);
        assert_eq!(a.physical.len(), 2);
        let m = a.memory();
        assert_eq!(m.texture_bytes_unaliased, 4 * 8 * 8 * 8);
        assert_eq!(m.texture_bytes, 2 * 8 * 8 * 8);
    }

    #[test]
    fn another_size_or_format_is_another_class() {
        let mut other = texture("b", (8, 8), 1, 3, 4);
        other.shape = Shape::Texture(
            TextureClass {
                format: wgpu::TextureFormat::Rgba8Unorm,
                size: (8, 8),
            },
            1,
            wgpu::TextureUsages::empty(),
        );
        let a = assign(vec![
            texture("a", (8, 8), 1, 0, 1),
            other,
            texture("c", (4, 4), 1, 5, 6),
        ]);
        assert_eq!(a.physical.len(), 3);
        assert_eq!(a.memory().texture_bytes, a.memory().texture_bytes_unaliased);
    }

    #[test]
    fn a_single_level_shares_level_zero_of_a_mip_chain() {
        let a = assign(vec![
            texture("one", (8, 8), 1, 0, 1),
            texture("chain", (8, 8), 4, 2, 3),
        ]);
        assert_eq!(a.physical.len(), 1);
        assert_eq!(
            a.physical[0].shape.bytes(),
            texture("x", (8, 8), 4, 0, 0).shape.bytes()
        );
        assert_eq!(a.physical[0].holds, ["one", "chain"]);
    }

    #[test]
    fn histories_and_resources_read_before_written_are_never_shared() {
        let mut history = texture("history", (8, 8), 1, 0, 1);
        history.history = true;
        let mut kept = texture("kept", (8, 8), 1, 2, 3);
        kept.written_first = false;
        let a = assign(vec![history, kept, texture("late", (8, 8), 1, 4, 5)]);
        assert_eq!(a.physical.len(), 3, "{:?}", a.physical);
        assert_eq!(a.physical[0].kept, Some("history"));
        assert_eq!(a.physical[1].kept, Some("kept"));
        assert_eq!(a.physical[2].kept, None);
    }

    #[test]
    fn buffers_are_never_shared_and_count_apart() {
        let buffer = |name, first, last| Planned {
            shape: Shape::Buffer(100, wgpu::BufferUsages::STORAGE),
            ..texture(name, (1, 1), 1, first, last)
        };
        let a = assign(vec![buffer("x", 0, 1), buffer("y", 2, 3)]);
        assert_eq!(a.physical.len(), 2);
        assert_eq!(a.memory().buffer_bytes, 200);
        assert_eq!(a.memory().texture_bytes, 0);
    }
}

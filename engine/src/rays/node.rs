//! The node layout every BVH level shares, on the CPU and in storage buffers.
//!
//! A node is 32 bytes: its box (two corners, m) and two words.
//! - An inner node has `count == 0`; its children are nodes `first` and `first + 1`
//!   (siblings are stored next to each other, so one index names both).
//! - A leaf has `count > 0` primitives, `first .. first + count`, in the order its
//!   builder stored them (triangles of a BLAS, instances of the TLAS).
//!
//! It is the layout of Wald's "flat" BVH as tinybvh stores it (`BVHNode`: `aabbMin`,
//! `leftFirst`, `aabbMax`, `triCount`); `BvhNode` in `shaders/rays/bvh.wgsl` is the same.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// Deepest level of a tree (the root is depth 0): the builder ([`super::sah`]) stops
/// there, so a walk's stack of this many entries per level is always enough.
pub const MAX_DEPTH: usize = 32;

/// One node: 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    /// Smallest corner of the box (m, in the space of the level: object space for a
    /// BLAS, world space for the TLAS).
    pub lo: [f32; 3],
    /// Inner: index of the left child (the right one follows it); leaf: first primitive.
    pub first: u32,
    /// Largest corner of the box (m).
    pub hi: [f32; 3],
    /// Primitives in the leaf; 0 for an inner node.
    pub count: u32,
}

/// Bytes of one node.
pub const NODE_BYTES: usize = std::mem::size_of::<BvhNode>();

impl BvhNode {
    /// Whether the node is a leaf.
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// Smallest corner.
    pub fn lo(&self) -> Vec3 {
        Vec3::from(self.lo)
    }

    /// Largest corner.
    pub fn hi(&self) -> Vec3 {
        Vec3::from(self.hi)
    }

    /// The node with its child or primitive index moved by `nodes` or `primitives`
    /// (concatenating levels into one buffer).
    pub fn offset(self, nodes: u32, primitives: u32) -> BvhNode {
        BvhNode {
            first: self.first + if self.is_leaf() { primitives } else { nodes },
            ..self
        }
    }
}

/// The distances at which the ray `origin + t·dir` enters and leaves the box, clipped to
/// `t_min .. t_max` (the slab test, Kay and Kajiya 1986); the box is missed when
/// `near > far`. the exit is widened by [`SLAB_FAR_SCALE`]. `inv_dir` is `1 / dir` per component (±∞ on a zero component; a NaN
/// from 0 × ∞ on a slab's plane is treated as a hit).
pub fn slab(origin: Vec3, inv_dir: Vec3, lo: Vec3, hi: Vec3, t_min: f32, t_max: f32) -> (f32, f32) {
    let a = (lo - origin) * inv_dir;
    let b = (hi - origin) * inv_dir;
    let near = a.min(b).max_element().max(t_min);
    let far = (a.max(b).min_element() * SLAB_FAR_SCALE).min(t_max);
    (near, far)
}

/// The exit distance's margin for rounding, `1 + 2γ₃` with `γₙ = n·ε / (1 − n·ε)` (Ize
/// 2013, "Robust BVH ray traversal", JCGT 2(2)): the computed slab distances may be off by
/// a few ulps, and a triangle lying in a box's face (a floor under a cube) must not be
/// culled by its own box.
pub const SLAB_FAR_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Whether a slab interval is a hit.
pub fn slab_hit(near: f32, far: f32) -> bool {
    near.partial_cmp(&far) != Some(std::cmp::Ordering::Greater)
}

/// Visits the leaves of the tree at `root` whose boxes the ray `origin + t·dir`
/// (`inv_dir = 1/dir`) crosses inside `t_min .. t_far`, near child first, the far one on
/// a stack of [`MAX_DEPTH`] entries (enough for any tree of [`super::sah`]).
/// `leaf(first, count, t_far)` returns the distance of a hit it found, which shrinks the
/// interval; with `any`, the first hit ends the walk. Returns whether a leaf hit.
pub fn walk(
    nodes: &[BvhNode],
    root: u32,
    (origin, inv_dir): (Vec3, Vec3),
    (t_min, mut t_far): (f32, f32),
    any: bool,
    leaf: &mut dyn FnMut(u32, u32, f32) -> Option<f32>,
) -> bool {
    let Some(root_node) = nodes.get(root as usize) else {
        return false;
    };
    let box_hit = |n: &BvhNode, t_far: f32| slab(origin, inv_dir, n.lo(), n.hi(), t_min, t_far);
    let mut stack = [0u32; MAX_DEPTH];
    let mut depth = 0usize;
    let pop = |stack: &[u32], depth: &mut usize| {
        (*depth > 0).then(|| {
            *depth -= 1;
            stack[*depth]
        })
    };
    let (near, far) = box_hit(root_node, t_far);
    let mut node = slab_hit(near, far).then_some(root);
    let mut found = false;
    while let Some(index) = node {
        let n = nodes[index as usize];
        if n.is_leaf() {
            if let Some(t) = leaf(n.first, n.count, t_far) {
                t_far = t;
                found = true;
                if any {
                    return true;
                }
            }
            node = pop(&stack, &mut depth);
            continue;
        }
        let (l, r) = (n.first, n.first + 1);
        let (ln, lf) = box_hit(&nodes[l as usize], t_far);
        let (rn, rf) = box_hit(&nodes[r as usize], t_far);
        node = match (slab_hit(ln, lf), slab_hit(rn, rf)) {
            (true, true) => {
                let (near, far) = if rn < ln { (r, l) } else { (l, r) };
                stack[depth] = far;
                depth += 1;
                Some(near)
            }
            (true, false) => Some(l),
            (false, true) => Some(r),
            (false, false) => pop(&stack, &mut depth),
        };
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_node_is_32_bytes() {
        assert_eq!(NODE_BYTES, 32);
    }

    #[test]
    fn slab_hits_and_misses() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let inv = Vec3::new(1.0, 0.0, 0.0).recip();
        let (n, f) = slab(Vec3::new(-5.0, 0.0, 0.0), inv, lo, hi, 0.0, f32::MAX);
        assert!(slab_hit(n, f));
        assert_eq!(n, 4.0);
        assert!(f >= 6.0 && f <= 6.0 * SLAB_FAR_SCALE);
        let (n, f) = slab(Vec3::new(-5.0, 2.0, 0.0), inv, lo, hi, 0.0, f32::MAX);
        assert!(!slab_hit(n, f));
        let (n, f) = slab(Vec3::new(-5.0, 0.0, 0.0), inv, lo, hi, 0.0, 3.0);
        assert!(!slab_hit(n, f));
    }
}

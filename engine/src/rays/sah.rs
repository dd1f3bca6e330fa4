//! The binned surface-area-heuristic builder (Wald 2007, "On fast construction of
//! SAH-based bounding volume hierarchies"), shared by every level: triangles for a BLAS,
//! instance boxes for the TLAS, and the CPU path tracer's scene.
//!
//! A node of `n` primitives with box area `A` is split where the SAH cost
//! `C_trav + (A_L·n_L + A_R·n_R) / A · C_isect` is least among the planes between
//! [`BINS`] equal bins of the centroids' extent on each axis, and made a leaf when that
//! cost is not below the leaf's `n · C_isect` and `n` is at most the level's leaf size
//! ([`MAX_LEAF`] triangles, 1 instance). When every centroid is the same point (no plane
//! separates them) a larger node is
//! halved by index instead, so any input ends in small leaves. At depth
//! [`MAX_DEPTH`]` − 1` a node becomes a leaf whatever its size: a traversal stack of
//! [`MAX_DEPTH`] entries per level is then always enough (near-first traversal pushes at
//! most one node per level), and [`BuildStats::forced_leaves`] counts those leaves.

use super::node::BvhNode;
pub use super::node::MAX_DEPTH;
use crate::scene::mesh_data::Aabb;
use glam::Vec3;

/// Bins per axis.
pub const BINS: usize = 16;
/// Most triangles in a BLAS leaf the SAH chooses (the TLAS's leaves hold one instance).
pub const MAX_LEAF: usize = 4;
/// Cost of visiting a node, relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// What a build made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildStats {
    /// Nodes.
    pub nodes: u32,
    /// Deepest leaf (the root is 0).
    pub depth: u32,
    /// Leaves made at [`MAX_DEPTH`] over the leaf size (0 for any input that
    /// is not pathological).
    pub forced_leaves: u32,
    /// Largest leaf.
    pub largest_leaf: u32,
}

/// A built tree: nodes (root first, children after their parent) and the primitives in
/// leaf order (`order[k]` is the input index of the k-th stored primitive).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tree {
    /// Nodes; empty for no primitives.
    pub nodes: Vec<BvhNode>,
    /// Input index of each stored primitive.
    pub order: Vec<u32>,
    /// Counts.
    pub stats: BuildStats,
}

/// Surface area of a box (m²); 0 for an empty one.
pub fn area(b: &Aabb) -> f32 {
    let d = (b.max - b.min).max(Vec3::ZERO);
    2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
}

fn empty() -> Aabb {
    Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    }
}

/// Builds a tree over `bounds` (each finite; callers drop the rest).
pub fn build(bounds: &[Aabb], max_leaf: usize) -> Tree {
    let max_leaf = max_leaf.max(1);
    let mut tree = Tree {
        nodes: Vec::with_capacity(2 * bounds.len()),
        order: (0..bounds.len() as u32).collect(),
        stats: BuildStats::default(),
    };
    if bounds.is_empty() {
        return tree;
    }
    let centroids: Vec<Vec3> = bounds.iter().map(Aabb::center).collect();
    tree.nodes.push(BvhNode {
        count: bounds.len() as u32,
        ..BvhNode::default()
    });
    let mut work = vec![(0usize, 0u32)];
    while let Some((index, depth)) = work.pop() {
        let (start, count) = (
            tree.nodes[index].first as usize,
            tree.nodes[index].count as usize,
        );
        let range = start..start + count;
        let (mut node_box, mut centre_box) = (empty(), empty());
        for &i in &tree.order[range.clone()] {
            node_box = node_box.union(&bounds[i as usize]);
            let c = centroids[i as usize];
            centre_box = centre_box.union(&Aabb { min: c, max: c });
        }
        tree.nodes[index].lo = node_box.min.into();
        tree.nodes[index].hi = node_box.max.into();
        tree.stats.depth = tree.stats.depth.max(depth);
        let mid = if depth as usize + 1 >= MAX_DEPTH {
            None
        } else {
            split(
                &mut tree.order[range],
                bounds,
                &centroids,
                (&node_box, &centre_box),
                max_leaf,
            )
        };
        let Some(mid) = mid else {
            if count > max_leaf {
                tree.stats.forced_leaves += 1;
            }
            tree.stats.largest_leaf = tree.stats.largest_leaf.max(count as u32);
            continue;
        };
        let left = tree.nodes.len();
        for (first, n) in [(start, mid), (start + mid, count - mid)] {
            tree.nodes.push(BvhNode {
                first: first as u32,
                count: n as u32,
                ..BvhNode::default()
            });
        }
        tree.nodes[index].first = left as u32;
        tree.nodes[index].count = 0;
        work.push((left + 1, depth + 1));
        work.push((left, depth + 1));
    }
    tree.stats.nodes = tree.nodes.len() as u32;
    tree
}

/// Partitions `order` at the best SAH plane; the size of the left part, or `None` for a
/// leaf.
fn split(
    order: &mut [u32],
    bounds: &[Aabb],
    centroids: &[Vec3],
    (node_box, centre_box): (&Aabb, &Aabb),
    max_leaf: usize,
) -> Option<usize> {
    let n = order.len();
    if n <= 1 {
        return None;
    }
    let extent = centre_box.max - centre_box.min;
    if extent.max_element() <= 0.0 || !extent.is_finite() {
        // Every centroid at one point: halve by index when too many for a leaf.
        return (n > max_leaf).then_some(n / 2);
    }
    let mut best = (f32::INFINITY, 0usize, 0.0f32);
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let scale = BINS as f32 / extent[axis];
        let bin_of = |c: Vec3| (((c[axis] - centre_box.min[axis]) * scale) as usize).min(BINS - 1);
        let mut boxes = [empty(); BINS];
        let mut counts = [0usize; BINS];
        for &i in order.iter() {
            let b = bin_of(centroids[i as usize]);
            boxes[b] = boxes[b].union(&bounds[i as usize]);
            counts[b] += 1;
        }
        // Sweep from the right, then from the left, costing each of the BINS − 1 planes.
        let mut right_cost = [0.0f32; BINS];
        let (mut acc, mut m) = (empty(), 0usize);
        for b in (1..BINS).rev() {
            acc = acc.union(&boxes[b]);
            m += counts[b];
            right_cost[b] = area(&acc) * m as f32;
        }
        let (mut acc, mut m) = (empty(), 0usize);
        for b in 0..BINS - 1 {
            acc = acc.union(&boxes[b]);
            m += counts[b];
            let cost = area(&acc) * m as f32 + right_cost[b + 1];
            if m > 0 && m < n && cost < best.0 {
                best = (cost, axis, centre_box.min[axis] + (b + 1) as f32 / scale);
            }
        }
    }
    let parent = area(node_box).max(f32::MIN_POSITIVE);
    let split_cost = TRAVERSAL_COST + best.0 / parent;
    if !best.0.is_finite() || (split_cost >= n as f32 && n <= max_leaf) {
        return (n > max_leaf).then_some(n / 2);
    }
    let (axis, plane) = (best.1, best.2);
    let mut left = 0;
    for k in 0..n {
        if centroids[order[k] as usize][axis] < plane {
            order.swap(k, left);
            left += 1;
        }
    }
    // Rounding can put the plane on a bin edge that no centroid crosses: halve instead.
    Some(if left == 0 || left == n { n / 2 } else { left })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(c: Vec3) -> Aabb {
        Aabb {
            min: c - 0.5,
            max: c + 0.5,
        }
    }

    fn check(tree: &Tree, bounds: &[Aabb]) {
        // Every primitive appears once, every node's box holds its children or primitives,
        // and children come after their parent.
        let mut seen = vec![0u32; bounds.len()];
        for (i, node) in tree.nodes.iter().enumerate() {
            let inside = |b: &Aabb| b.min.cmpge(node.lo()).all() && b.max.cmple(node.hi()).all();
            if node.is_leaf() {
                for &p in &tree.order[node.first as usize..(node.first + node.count) as usize] {
                    seen[p as usize] += 1;
                    assert!(inside(&bounds[p as usize]));
                }
            } else {
                assert!(node.first as usize > i);
                for c in [node.first, node.first + 1] {
                    let child = tree.nodes[c as usize];
                    assert!(inside(&Aabb {
                        min: child.lo(),
                        max: child.hi()
                    }));
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
    }

    #[test]
    fn a_grid_of_boxes_splits_into_small_leaves() {
        let bounds: Vec<Aabb> = (0..1000)
            .map(|i| {
                unit_box(Vec3::new((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32) * 2.0)
            })
            .collect();
        let tree = build(&bounds, MAX_LEAF);
        check(&tree, &bounds);
        assert!(tree.stats.largest_leaf <= MAX_LEAF as u32);
        assert_eq!(tree.stats.forced_leaves, 0);
        // A balanced tree over 1000 boxes in leaves of ≤ 4 is about 8 levels deep.
        assert!(tree.stats.depth <= 12, "{:?}", tree.stats);
    }

    #[test]
    fn identical_boxes_are_halved_by_index() {
        let bounds = vec![unit_box(Vec3::ZERO); 100_000];
        let tree = build(&bounds, MAX_LEAF);
        check(&tree, &bounds);
        assert!(tree.stats.largest_leaf <= MAX_LEAF as u32);
        assert!(tree.stats.depth <= 17, "{:?}", tree.stats);
    }

    #[test]
    fn a_degenerate_chain_stops_at_the_depth_cap() {
        // Boxes at 2^k: the SAH peels one off per level, which would go 60 deep.
        let bounds: Vec<Aabb> = (0..60)
            .map(|k| unit_box(Vec3::splat(2f32.powi(k))))
            .collect();
        let tree = build(&bounds, MAX_LEAF);
        check(&tree, &bounds);
        assert!(tree.stats.depth < MAX_DEPTH as u32);
    }

    #[test]
    fn sah_beats_a_median_split_on_clustered_input() {
        // Two tight clusters far apart and one lone box between: the SAH's root cuts the
        // empty space, so each side's box is small.
        let mut bounds: Vec<Aabb> = (0..50)
            .map(|i| unit_box(Vec3::new(i as f32 * 0.01, 0.0, 0.0)))
            .collect();
        bounds.extend((0..50).map(|i| unit_box(Vec3::new(100.0 + i as f32 * 0.01, 0.0, 0.0))));
        let tree = build(&bounds, MAX_LEAF);
        let root = tree.nodes[0];
        let (l, r) = (
            tree.nodes[root.first as usize],
            tree.nodes[root.first as usize + 1],
        );
        assert!(l.hi()[0] - l.lo()[0] < 2.0 && r.hi()[0] - r.lo()[0] < 2.0);
        assert!(build(&[], MAX_LEAF).nodes.is_empty());
    }
}

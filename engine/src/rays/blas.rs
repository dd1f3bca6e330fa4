//! A bottom-level hierarchy: one mesh's triangles in object space, built once with the
//! binned SAH ([`super::sah`]) and refitted when the mesh deforms.
//!
//! Triangles are stored in leaf order, each as its three corners and its index in the
//! mesh ([`RayTriangle`], 48 bytes). A triangle with a non-finite corner is left out of
//! the build ([`Blas::dropped`]); a zero-area one is kept and never hit.

use super::node::{BvhNode, walk};
use super::sah::{self, BuildStats, MAX_LEAF};
use super::watertight::{TriangleHit, intersect_triangle, ray_transform};
use crate::scene::mesh_data::Aabb;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// One stored triangle: three corners (m, object space), the first carrying the
/// triangle's index in its mesh in `w` (bit pattern of a u32). `RayTriangle` in
/// `shaders/rays/bvh.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RayTriangle {
    /// Corner A and the mesh's triangle index (bits).
    pub a: [f32; 4],
    /// Corner B (w unused).
    pub b: [f32; 4],
    /// Corner C (w unused).
    pub c: [f32; 4],
}

impl RayTriangle {
    fn new(corners: [Vec3; 3], primitive: u32) -> RayTriangle {
        RayTriangle {
            a: corners[0].extend(f32::from_bits(primitive)).into(),
            b: corners[1].extend(0.0).into(),
            c: corners[2].extend(0.0).into(),
        }
    }

    /// The corners.
    pub fn corners(&self) -> [Vec3; 3] {
        [self.a, self.b, self.c].map(|p| Vec3::new(p[0], p[1], p[2]))
    }

    /// The triangle's index in its mesh.
    pub fn primitive(&self) -> u32 {
        self.a[3].to_bits()
    }
}

/// A closest or any hit in one hierarchy: the triangle's index in its mesh and the
/// hit's distance and barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimitiveHit {
    /// Triangle index in the mesh.
    pub primitive: u32,
    /// Distance and barycentrics.
    pub hit: TriangleHit,
}

/// One mesh's hierarchy.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Blas {
    /// Nodes, root first; leaves index [`Blas::triangles`].
    pub nodes: Vec<BvhNode>,
    /// Triangles in leaf order.
    pub triangles: Vec<RayTriangle>,
    /// Triangles left out for a non-finite corner.
    pub dropped: u32,
    /// Build counts.
    pub stats: BuildStats,
}

fn corners(positions: &[Vec3], indices: &[u32], primitive: u32) -> [Vec3; 3] {
    let k = 3 * primitive as usize;
    [0, 1, 2].map(|j| {
        indices
            .get(k + j)
            .and_then(|&i| positions.get(i as usize))
            .copied()
            .unwrap_or(Vec3::NAN)
    })
}

fn bounds_of(corners: &[Vec3; 3]) -> Aabb {
    Aabb {
        min: corners[0].min(corners[1]).min(corners[2]),
        max: corners[0].max(corners[1]).max(corners[2]),
    }
}

impl Blas {
    /// Builds the hierarchy of the indexed triangles (three indices per triangle into
    /// `positions`, m); an index out of range drops its triangle like a non-finite
    /// corner.
    pub fn build(positions: &[Vec3], indices: &[u32]) -> Blas {
        let all = (indices.len() / 3) as u32;
        let mut kept = Vec::with_capacity(all as usize);
        let mut boxes = Vec::with_capacity(all as usize);
        for p in 0..all {
            let c = corners(positions, indices, p);
            if c.iter().all(|v| v.is_finite()) {
                kept.push(p);
                boxes.push(bounds_of(&c));
            }
        }
        let tree = sah::build(&boxes, MAX_LEAF);
        let triangles = tree
            .order
            .iter()
            .map(|&k| {
                let p = kept[k as usize];
                RayTriangle::new(corners(positions, indices, p), p)
            })
            .collect();
        Blas {
            nodes: tree.nodes,
            triangles,
            dropped: all - kept.len() as u32,
            stats: tree.stats,
        }
    }

    /// Moves the corners to `positions` (the same mesh deformed: same indices) and
    /// recomputes every box bottom-up, keeping the tree (children follow their parent,
    /// so one pass from the last node to the first sees children first). A corner that is
    /// no longer finite leaves its triangle unhittable and out of its leaf's box.
    pub fn refit(&mut self, positions: &[Vec3], indices: &[u32]) {
        for t in &mut self.triangles {
            *t = RayTriangle::new(corners(positions, indices, t.primitive()), t.primitive());
        }
        for i in (0..self.nodes.len()).rev() {
            let node = self.nodes[i];
            let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            if node.is_leaf() {
                let range = node.first as usize..(node.first + node.count) as usize;
                for t in &self.triangles[range] {
                    let c = t.corners();
                    if c.iter().all(|v| v.is_finite()) {
                        let b = bounds_of(&c);
                        lo = lo.min(b.min);
                        hi = hi.max(b.max);
                    }
                }
            } else {
                for child in [node.first, node.first + 1] {
                    let c = self.nodes[child as usize];
                    lo = lo.min(c.lo());
                    hi = hi.max(c.hi());
                }
            }
            self.nodes[i].lo = lo.into();
            self.nodes[i].hi = hi.into();
        }
    }

    /// Bytes on the GPU: nodes and triangles.
    pub fn bytes(&self) -> usize {
        self.nodes.len() * super::node::NODE_BYTES + self.triangles.len() * TRIANGLE_BYTES
    }

    /// The closest hit with `t_min < t < t_max`, or with `any`, the first one found;
    /// `accept` may refuse a hit by primitive (alpha-masked texels), and the traversal
    /// goes on past it.
    pub fn trace(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        any: bool,
        accept: &mut dyn FnMut(u32, &TriangleHit) -> bool,
    ) -> Option<PrimitiveHit> {
        let view = LevelView {
            nodes: &self.nodes,
            triangles: &self.triangles,
            root: 0,
        };
        view.trace(origin, dir, (t_min, t_max), any, accept)
    }
}

/// One hierarchy inside arrays that may hold others (the packed scene): `root` and every
/// index in its nodes are absolute.
#[derive(Clone, Copy, Debug)]
pub struct LevelView<'a> {
    /// Nodes.
    pub nodes: &'a [BvhNode],
    /// Triangles.
    pub triangles: &'a [RayTriangle],
    /// Root node.
    pub root: u32,
}

impl LevelView<'_> {
    /// [`Blas::trace`] on this view, the interval `(t_min, t_max)` given as a pair.
    pub fn trace(
        &self,
        origin: Vec3,
        dir: Vec3,
        (t_min, t_max): (f32, f32),
        any: bool,
        accept: &mut dyn FnMut(u32, &TriangleHit) -> bool,
    ) -> Option<PrimitiveHit> {
        let ray = ray_transform(dir);
        let mut best = None;
        walk(
            self.nodes,
            self.root,
            (origin, dir.recip()),
            (t_min, t_max),
            any,
            &mut |first, count, mut t_far| {
                let mut found = None;
                for t in &self.triangles[first as usize..(first + count) as usize] {
                    if let Some(hit) = intersect_triangle(origin, &ray, t.corners(), t_min, t_far)
                        && accept(t.primitive(), &hit)
                    {
                        t_far = hit.t;
                        found = Some(hit.t);
                        best = Some(PrimitiveHit {
                            primitive: t.primitive(),
                            hit,
                        });
                        if any {
                            break;
                        }
                    }
                }
                found
            },
        );
        best
    }
}

/// Bytes of one stored triangle.
pub const TRIANGLE_BYTES: usize = std::mem::size_of::<RayTriangle>();

//! The top level: instances of the meshes' hierarchies, each with its transform, in a
//! hierarchy of their world-space boxes (one instance per leaf), and the packed arrays a
//! tracing shader binds ([`RayScene`]).
//!
//! A ray enters an instance in the instance's object space: origin and direction are
//! multiplied by `object_from_world` and the direction is not renormalised, so a
//! distance `t` means the same point in both spaces and hits of different instances
//! compare directly.

use super::blas::{Blas, LevelView, PrimitiveHit, RayTriangle};
use super::node::{BvhNode, walk};
use super::sah::{self, BuildStats};
use super::watertight::TriangleHit;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

/// The instance's surface stops every ray that hits it.
pub const SURFACE_OPAQUE: u32 = 0;
/// Alpha-masked: a hit counts where the coverage reaches the material's cutoff.
pub const SURFACE_MASKED: u32 = 1;
/// Alpha-blended: a hit counts with probability equal to the coverage (stochastic
/// transparency, as the path tracer treats blended surfaces).
pub const SURFACE_BLENDED: u32 = 2;

/// One instance as a tracing shader reads it (64 bytes). `RayInstance` in
/// `shaders/rays/bvh.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RayInstance {
    /// Rows of the upper 3×4 of object-from-world (m).
    pub object_from_world: [[f32; 4]; 3],
    /// Root node of its mesh's hierarchy in [`RayScene::blas_nodes`].
    pub root: u32,
    /// Its index among the frame's drawn instances.
    pub instance: u32,
    /// How its surface stops rays: `SURFACE_*`.
    pub surface: u32,
    /// Its material's index in the frame's material table.
    pub material: u32,
}

impl RayInstance {
    /// A world-space point or direction (w = 1 or 0) in object space.
    pub fn to_object(&self, v: Vec4) -> Vec3 {
        let r = self.object_from_world.map(Vec4::from);
        Vec3::new(r[0].dot(v), r[1].dot(v), r[2].dot(v))
    }
}

/// What a level of the scene takes for one instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceInput {
    /// Index of its mesh's hierarchy in the list given to [`RayScene::new`].
    pub blas: usize,
    /// World from local (m).
    pub world_from_local: Mat4,
    /// `SURFACE_*`.
    pub surface: u32,
    /// Material index.
    pub material: u32,
}

/// Every mesh's hierarchy in shared arrays, and the top level over the instances.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayScene {
    /// Every BLAS's nodes, with absolute indices.
    pub blas_nodes: Vec<BvhNode>,
    /// Every BLAS's triangles.
    pub triangles: Vec<RayTriangle>,
    /// Root of each BLAS in `blas_nodes` (`u32::MAX`: an empty mesh).
    pub roots: Vec<u32>,
    /// The top level's nodes; leaves index [`RayScene::instances`].
    pub tlas_nodes: Vec<BvhNode>,
    /// Instances in leaf order.
    pub instances: Vec<RayInstance>,
    /// Instances left out: an empty mesh, a missing hierarchy or a transform that is not
    /// finite and invertible.
    pub skipped_instances: u32,
    /// The top level's build counts.
    pub tlas_stats: BuildStats,
}

/// A hit in the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit {
    /// Index among the frame's instances ([`RayInstance::instance`]).
    pub instance: u32,
    /// Triangle in its mesh, distance (m along a unit direction) and barycentrics.
    pub hit: PrimitiveHit,
}

impl RayScene {
    /// Packs the meshes' hierarchies (`blases`, absolute indices) and builds the top level
    /// over `instances`.
    pub fn new(blases: &[&Blas], instances: &[InstanceInput]) -> RayScene {
        let mut scene = RayScene::default();
        for blas in blases {
            let (n, t) = (scene.blas_nodes.len() as u32, scene.triangles.len() as u32);
            scene
                .roots
                .push(if blas.nodes.is_empty() { u32::MAX } else { n });
            scene
                .blas_nodes
                .extend(blas.nodes.iter().map(|node| node.offset(n, t)));
            scene.triangles.extend_from_slice(&blas.triangles);
        }
        scene.set_instances(blases, instances);
        scene
    }

    /// Rebuilds the top level for `instances`, keeping the meshes' hierarchies (which must
    /// be the ones [`RayScene::new`] packed, or refits of them).
    pub fn set_instances(&mut self, blases: &[&Blas], instances: &[InstanceInput]) {
        let mut kept = Vec::with_capacity(instances.len());
        let mut boxes = Vec::with_capacity(instances.len());
        for (i, inst) in instances.iter().enumerate() {
            let m = inst.world_from_local;
            let object_from_world = m.inverse();
            let world_box = blases
                .get(inst.blas)
                .and_then(|b| b.nodes.first())
                .filter(|_| {
                    m.is_finite() && m.determinant() != 0.0 && object_from_world.is_finite()
                })
                .and_then(|root| {
                    crate::scene::mesh_data::Aabb {
                        min: root.lo(),
                        max: root.hi(),
                    }
                    .transformed(&m)
                });
            let Some(world_box) = world_box else {
                continue;
            };
            // The corners were rounded once more than the ray's trip into object space:
            // widen the box by a few ulps of its size so it holds every surface point.
            let margin = (world_box.max - world_box.min)
                .abs()
                .max(world_box.max.abs().max(world_box.min.abs()))
                * (4.0 * f32::EPSILON);
            let world_box = crate::scene::mesh_data::Aabb {
                min: world_box.min - margin,
                max: world_box.max + margin,
            };
            let rows = object_from_world.transpose();
            kept.push(RayInstance {
                object_from_world: [rows.x_axis, rows.y_axis, rows.z_axis].map(|r| r.to_array()),
                root: self.roots[inst.blas],
                instance: i as u32,
                surface: inst.surface,
                material: inst.material,
            });
            boxes.push(world_box);
        }
        let tree = sah::build(&boxes, 1);
        self.skipped_instances = (instances.len() - kept.len()) as u32;
        self.instances = tree.order.iter().map(|&k| kept[k as usize]).collect();
        self.tlas_nodes = tree.nodes;
        self.tlas_stats = tree.stats;
    }

    /// Bytes of the four arrays on the GPU.
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        (self.blas_nodes.len() + self.tlas_nodes.len()) * size_of::<BvhNode>()
            + self.triangles.len() * size_of::<RayTriangle>()
            + self.instances.len() * size_of::<RayInstance>()
    }

    /// The closest hit of the world-space ray with `t_min < t < t_max` (or with `any`, the
    /// first found); `accept(instance, primitive, hit)` may refuse a hit (alpha), and the
    /// traversal goes on past it.
    pub fn trace(
        &self,
        origin: Vec3,
        dir: Vec3,
        (t_min, t_max): (f32, f32),
        any: bool,
        accept: &mut dyn FnMut(&RayInstance, u32, &TriangleHit) -> bool,
    ) -> Option<SceneHit> {
        let mut best = None;
        walk(
            &self.tlas_nodes,
            0,
            (origin, dir.recip()),
            (t_min, t_max),
            any,
            &mut |first, _, t_far| {
                let inst = &self.instances[first as usize];
                let o = inst.to_object(origin.extend(1.0));
                let d = inst.to_object(dir.extend(0.0));
                let view = LevelView {
                    nodes: &self.blas_nodes,
                    triangles: &self.triangles,
                    root: inst.root,
                };
                let hit = view.trace(o, d, (t_min, t_far), any, &mut |p, h| accept(inst, p, h))?;
                best = Some(SceneHit {
                    instance: inst.instance,
                    hit,
                });
                Some(hit.hit.t)
            },
        );
        best
    }
}

//! Meshes that change shape every frame: skinning (vertices carried by joints) and morph
//! targets (vertices moved by weighted offsets), as glTF 2.0 defines them (§3.7.2.2
//! "Morph Targets" and §3.7.3 "Skins").
//!
//! For vertex `v` with rest position `p`, normal `n` and tangent `t`, morph targets
//! `k` with offsets `Δp_k`, `Δn_k`, `Δt_k` (m, unitless, unitless) and weights `w_k`:
//! - morph: `p' = p + Σ_k w_k Δp_k`, `n' = n + Σ_k w_k Δn_k`, `t' = t + Σ_k w_k Δt_k`;
//! - joint matrix of joint `j`: `J_j = world_from_joint_j · inverse_bind_j` (the joint's
//!   world transform this frame times the inverse of its transform in the bind pose);
//! - skin matrix (linear blend skinning, Magnenat-Thalmann, Laperrière and Thalmann
//!   1988, "Joint-dependent local deformations for hand animation and object grasping"):
//!   `S = Σ_{i<4} a_i J_{j_i}`, with the vertex's four joints `j_i` and weights `a_i`
//!   (which sum to 1);
//! - skinned vertex, in world space: `S p'`; normal `N n'` with `N = sign(det S₃) ·
//!   cof(S₃)`, the cofactor matrix of S's upper 3×3, which is the inverse transpose up to
//!   a positive factor; tangent `S₃ t'` (its handedness `w` kept); both normalised.
//!
//! A skinned mesh ignores its own entity's transform (glTF: "only the joint transforms
//! are applied"); a morphed mesh without a skin keeps it. The same names exist in
//! `shaders/skinning.wgsl`; `tests/shader_parity.rs` binds the two.

use crate::scene::mesh_data::{Aabb, MeshData, Vertex};
use bevy_ecs::prelude::*;
use glam::{Mat3, Mat4, Vec3, Vec4};
use std::sync::Arc;

/// Joints (and weights) one vertex can have: glTF's `JOINTS_0`/`WEIGHTS_0`.
pub const MAX_JOINT_INFLUENCES: usize = 4;

/// Deforms this entity's [`crate::scene::Mesh3d`] by the joints: the mesh must carry
/// joints and weights ([`Deformation`]). The glTF loader adds it for a node with a skin.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct SkinnedMesh {
    /// The joint entities, in the order the mesh's joint indices refer to.
    pub joints: Vec<Entity>,
    /// Each joint's inverse bind matrix (joint from mesh space, in the bind pose), one per
    /// joint.
    pub inverse_bind: Arc<[Mat4]>,
}

impl SkinnedMesh {
    /// This frame's joint matrices `J_j = world_from_joint_j · inverse_bind_j`, with
    /// `world_from` giving a joint entity's world transform (the identity for a joint
    /// that has none).
    pub fn joint_matrices(&self, world_from: impl Fn(Entity) -> Option<Mat4>) -> Vec<Mat4> {
        self.joints
            .iter()
            .zip(self.inverse_bind.iter())
            .map(|(&j, ib)| world_from(j).unwrap_or(Mat4::IDENTITY) * *ib)
            .collect()
    }
}

/// The weights of a mesh's morph targets (unitless, usually in [0, 1]), one per target.
/// On the entity with the [`crate::scene::Mesh3d`] or on its parent (the glTF loader
/// puts it on the node, which animations drive; the node's primitives are its children).
#[derive(Component, Clone, Debug, Default, PartialEq)]
pub struct MorphWeights(pub Vec<f32>);

/// One morph target: offsets added to a mesh's vertices, times the target's weight. Each
/// list is empty (the target does not move that attribute) or has one entry per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// Position offsets (m, model space).
    pub positions: Vec<[f32; 3]>,
    /// Normal offsets.
    pub normals: Vec<[f32; 3]>,
    /// Tangent offsets (xyz; the handedness is not morphed).
    pub tangents: Vec<[f32; 3]>,
}

/// What a mesh needs to be deformed: per-vertex joints and weights (empty when it has no
/// skin) and morph targets. Built by [`Deformation::new`], which checks it against the
/// mesh and precomputes what bounds need.
#[derive(Clone, Debug, PartialEq)]
pub struct Deformation {
    joints: Vec<[u32; 4]>,
    weights: Vec<[f32; 4]>,
    targets: Vec<MorphTarget>,
    /// Per joint index: the model-space box of the rest positions it influences.
    joint_boxes: Vec<Option<Aabb>>,
    /// Per target: the largest position offset of any vertex, per axis (m).
    target_extents: Vec<Vec3>,
}

impl Deformation {
    /// The deformation of `mesh` by per-vertex `joints` and `weights` (both empty, or one
    /// entry per vertex) and morph `targets`. Weights are normalised to sum to 1; a
    /// vertex whose weights are all zero follows joint 0 alone. Fails, naming the
    /// problem, on mismatched lengths or non-finite values.
    pub fn new(
        mesh: &MeshData,
        joints: Vec<[u32; 4]>,
        weights: Vec<[f32; 4]>,
        targets: Vec<MorphTarget>,
    ) -> Result<Deformation, String> {
        let n = mesh.vertices.len();
        if joints.len() != weights.len() || (!joints.is_empty() && joints.len() != n) {
            return Err(format!(
                "{} joint sets and {} weight sets for {n} vertices",
                joints.len(),
                weights.len()
            ));
        }
        if joints.is_empty() && targets.is_empty() {
            return Err("neither joints nor morph targets".into());
        }
        for (k, t) in targets.iter().enumerate() {
            for (name, list) in [
                ("positions", &t.positions),
                ("normals", &t.normals),
                ("tangents", &t.tangents),
            ] {
                if !list.is_empty() && list.len() != n {
                    return Err(format!(
                        "morph target {k} has {} {name} for {n} vertices",
                        list.len()
                    ));
                }
                if list.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(format!("morph target {k} has a non-finite offset"));
                }
            }
        }
        let weights: Vec<[f32; 4]> = weights
            .into_iter()
            .map(|w| {
                let w = Vec4::from(w);
                let w = if w.is_finite() {
                    w.max(Vec4::ZERO)
                } else {
                    Vec4::ZERO
                };
                let sum = w.element_sum();
                if sum > 0.0 {
                    (w / sum).into()
                } else {
                    [1.0, 0.0, 0.0, 0.0]
                }
            })
            .collect();
        let joint_count = joints
            .iter()
            .flatten()
            .map(|&j| j as usize + 1)
            .max()
            .unwrap_or(0);
        let mut joint_boxes: Vec<Option<Aabb>> = vec![None; joint_count];
        for ((js, ws), v) in joints.iter().zip(&weights).zip(&mesh.vertices) {
            let p = Vec3::from(v.position);
            for (&j, &w) in js.iter().zip(ws) {
                if w > 0.0 {
                    let b = &mut joint_boxes[j as usize];
                    *b = Some(b.map_or(Aabb { min: p, max: p }, |b| Aabb {
                        min: b.min.min(p),
                        max: b.max.max(p),
                    }));
                }
            }
        }
        let target_extents = targets
            .iter()
            .map(|t| {
                t.positions
                    .iter()
                    .fold(Vec3::ZERO, |m, d| m.max(Vec3::from(*d).abs()))
            })
            .collect();
        Ok(Deformation {
            joints,
            weights,
            targets,
            joint_boxes,
            target_extents,
        })
    }

    /// Whether the mesh is skinned (has joints and weights).
    pub fn skinned(&self) -> bool {
        !self.joints.is_empty()
    }

    /// How many joints the mesh's joint indices need (the largest index + 1).
    pub fn joint_count(&self) -> usize {
        self.joint_boxes.len()
    }

    /// Per vertex: four joint indices (empty without a skin).
    pub fn joints(&self) -> &[[u32; 4]] {
        &self.joints
    }

    /// Per vertex: four weights summing to 1 (empty without a skin).
    pub fn weights(&self) -> &[[f32; 4]] {
        &self.weights
    }

    /// The morph targets.
    pub fn targets(&self) -> &[MorphTarget] {
        &self.targets
    }

    /// A box holding every vertex of the deformed mesh: in model space when
    /// `joint_matrices` is `None` (morph targets only, `rest` is the mesh's box), in
    /// world space otherwise. Each joint's box of influenced rest positions, grown by the
    /// largest offset the morph weights allow, is carried by its joint matrix; a skinned
    /// vertex is a weighted mean of points in those boxes, so it lies in their union.
    pub fn bounds(
        &self,
        rest: Option<Aabb>,
        joint_matrices: Option<&[Mat4]>,
        morph_weights: &[f32],
    ) -> Option<Aabb> {
        let grow = self
            .target_extents
            .iter()
            .zip(morph_weights)
            .fold(Vec3::ZERO, |e, (m, w)| e + *m * finite_weight(*w).abs());
        let grown = |b: Aabb| Aabb {
            min: b.min - grow,
            max: b.max + grow,
        };
        match joint_matrices {
            None => rest.map(grown),
            Some(matrices) => self
                .joint_boxes
                .iter()
                .zip(matrices)
                .filter_map(|(b, m)| b.and_then(|b| grown(b).transformed(m)))
                .reduce(|a, b| a.union(&b)),
        }
    }

    /// Every vertex of `mesh` deformed on the CPU by [`deform_vertex`]: what the
    /// deformation pass computes on the GPU, for the path tracer and the tests.
    pub fn deformed_vertices(
        &self,
        mesh: &MeshData,
        joint_matrices: Option<&[Mat4]>,
        morph_weights: &[f32],
    ) -> Vec<Vertex> {
        (0..mesh.vertices.len())
            .map(|i| deform_vertex(mesh, self, i, joint_matrices, morph_weights))
            .collect()
    }
}

/// A weight as the shaders use it: a non-finite one counts as 0.
fn finite_weight(w: f32) -> f32 {
    if w.is_finite() { w } else { 0.0 }
}

/// Vertex `i` of `mesh` moved by the morph targets (`p' = p + Σ w_k Δp_k`, the same for
/// the normal and the tangent's xyz; not renormalised here).
pub fn morph_vertex(mesh: &MeshData, d: &Deformation, i: usize, morph_weights: &[f32]) -> Vertex {
    let mut v = mesh.vertices[i];
    let (mut p, mut n, mut t) = (
        Vec3::from(v.position),
        Vec3::from(v.normal),
        Vec3::from_slice(&v.tangent[..3]),
    );
    for (target, &w) in d.targets.iter().zip(morph_weights) {
        let w = finite_weight(w);
        let offset = |list: &[[f32; 3]]| list.get(i).map_or(Vec3::ZERO, |o| Vec3::from(*o) * w);
        p += offset(&target.positions);
        n += offset(&target.normals);
        t += offset(&target.tangents);
    }
    v.position = p.into();
    v.normal = n.into();
    v.tangent = [t.x, t.y, t.z, v.tangent[3]];
    v
}

/// The skin matrix `S = Σ a_i J_{j_i}` of a vertex with joint indices `joints` and
/// weights `weights`; an index past `joint_matrices` takes the last matrix (the
/// shader clamps the same way).
pub fn skin_matrix(joint_matrices: &[Mat4], joints: [u32; 4], weights: [f32; 4]) -> Mat4 {
    let last = joint_matrices.len().saturating_sub(1);
    joints.iter().zip(weights).fold(Mat4::ZERO, |s, (&j, a)| {
        let m = joint_matrices
            .get((j as usize).min(last))
            .copied()
            .unwrap_or(Mat4::IDENTITY);
        s + m * a
    })
}

/// The matrix that carries normals through the linear map `m`: `sign(det m) · cof(m)`,
/// the inverse transpose up to a positive factor (defined even where `m` is singular).
pub fn skin_normal_matrix(m: Mat3) -> Mat3 {
    let cofactor = Mat3::from_cols(
        m.y_axis.cross(m.z_axis),
        m.z_axis.cross(m.x_axis),
        m.x_axis.cross(m.y_axis),
    );
    if m.determinant() < 0.0 {
        -cofactor
    } else {
        cofactor
    }
}

/// Vertex `i` of `mesh`, morphed and (with `joint_matrices`) skinned into world space,
/// its normal and tangent renormalised: the formulas of the module docs.
pub fn deform_vertex(
    mesh: &MeshData,
    d: &Deformation,
    i: usize,
    joint_matrices: Option<&[Mat4]>,
    morph_weights: &[f32],
) -> Vertex {
    let mut v = morph_vertex(mesh, d, i, morph_weights);
    let (mut p, mut n, mut t) = (
        Vec3::from(v.position),
        Vec3::from(v.normal),
        Vec3::from_slice(&v.tangent[..3]),
    );
    if let (Some(matrices), Some(js), Some(ws)) =
        (joint_matrices, d.joints.get(i), d.weights.get(i))
    {
        let s = skin_matrix(matrices, *js, *ws);
        let s3 = Mat3::from_mat4(s);
        p = s.transform_point3(p);
        n = skin_normal_matrix(s3) * n;
        t = s3 * t;
    }
    v.position = p.into();
    let t = t.normalize_or(Vec3::X);
    v.normal = n.normalize_or(Vec3::Z).into();
    v.tangent = [t.x, t.y, t.z, v.tangent[3]];
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strip() -> MeshData {
        // Three vertices along +y at 0, 1 and 2 m.
        let v = |y: f32| {
            Vertex::new(
                [0.0, y, 0.0],
                [0.0, 0.0, 1.0],
                [0.0; 2],
                [1.0, 0.0, 0.0, 1.0],
            )
        };
        MeshData {
            vertices: vec![v(0.0), v(1.0), v(2.0)],
            indices: vec![0, 1, 2],
        }
    }

    #[test]
    fn a_morph_weight_of_one_half_moves_a_vertex_halfway() {
        let mesh = strip();
        let target = MorphTarget {
            positions: vec![[0.0; 3], [0.0; 3], [2.0, 0.0, 0.0]],
            ..MorphTarget::default()
        };
        let d = Deformation::new(&mesh, Vec::new(), Vec::new(), vec![target]).unwrap();
        let moved = deform_vertex(&mesh, &d, 2, None, &[0.5]);
        assert_eq!(moved.position, [1.0, 2.0, 0.0]);
        assert_eq!(
            deform_vertex(&mesh, &d, 2, None, &[0.0]).position,
            [0.0, 2.0, 0.0]
        );
        // The bounds grow by the largest offset times the weight.
        let b = d.bounds(mesh.bounds(), None, &[0.5]).unwrap();
        assert_eq!(b.max.x, 1.0);
        assert_eq!(b.min.x, -1.0);
    }

    #[test]
    fn morph_targets_move_normals_and_tangents_by_their_weights() {
        let mesh = strip();
        let target = MorphTarget {
            normals: vec![[1.0, 0.0, -1.0]; 3],
            tangents: vec![[-1.0, 1.0, 0.0]; 3],
            ..MorphTarget::default()
        };
        let d = Deformation::new(&mesh, Vec::new(), Vec::new(), vec![target]).unwrap();
        let v = morph_vertex(&mesh, &d, 1, &[0.5]);
        assert_eq!(v.normal, [0.5, 0.0, 0.5]);
        // The tangent's xyz moves; its handedness does not.
        assert_eq!(v.tangent, [0.5, 0.5, 0.0, 1.0]);
        assert_eq!(v.position, [0.0, 1.0, 0.0]);
        // A non-finite weight counts as 0.
        assert_eq!(
            morph_vertex(&mesh, &d, 1, &[f32::NAN]).normal,
            [0.0, 0.0, 1.0]
        );
    }

    #[test]
    fn weights_are_normalised_and_bad_inputs_named() {
        let mesh = strip();
        let d = Deformation::new(
            &mesh,
            vec![[0, 1, 0, 0]; 3],
            vec![[2.0, 2.0, 0.0, 0.0], [0.0; 4], [f32::NAN, 1.0, 0.0, 0.0]],
            Vec::new(),
        )
        .unwrap();
        assert_eq!(d.weights()[0], [0.5, 0.5, 0.0, 0.0]);
        assert_eq!(d.weights()[1], [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(d.weights()[2], [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(d.joint_count(), 2);
        let short = Deformation::new(
            &mesh,
            vec![[0; 4]; 2],
            vec![[1.0, 0.0, 0.0, 0.0]; 2],
            Vec::new(),
        );
        assert!(short.unwrap_err().contains("for 3 vertices"));
        let target = MorphTarget {
            normals: vec![[0.0; 3]],
            ..MorphTarget::default()
        };
        let bad = Deformation::new(&mesh, Vec::new(), Vec::new(), vec![target]);
        assert!(bad.unwrap_err().contains("1 normals for 3 vertices"));
    }

    #[test]
    fn skinned_vertices_stay_inside_the_joint_bounds() {
        let mesh = strip();
        // Vertex 0 on joint 0, vertex 1 shared, vertex 2 on joint 1; joint 1 bent 90°
        // about z at y = 1 m.
        let d = Deformation::new(
            &mesh,
            vec![[0, 0, 0, 0], [0, 1, 0, 0], [1, 0, 0, 0]],
            vec![
                [1.0, 0.0, 0.0, 0.0],
                [0.5, 0.5, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0],
            ],
            Vec::new(),
        )
        .unwrap();
        let pivot = Vec3::Y;
        let bend = Mat4::from_translation(pivot)
            * Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2)
            * Mat4::from_translation(-pivot);
        let joints = [Mat4::IDENTITY, bend];
        let tip = deform_vertex(&mesh, &d, 2, Some(&joints), &[]);
        let p = Vec3::from(tip.position);
        assert!(p.distance(Vec3::new(-1.0, 1.0, 0.0)) < 1e-6, "{p}");
        let b = d.bounds(None, Some(&joints), &[]).unwrap();
        for v in d.deformed_vertices(&mesh, Some(&joints), &[]) {
            let p = Vec3::from(v.position);
            assert!(p.cmpge(b.min - 1e-6).all() && p.cmple(b.max + 1e-6).all());
        }
        // A mirroring joint keeps normals pointing out of the surface they belong to.
        let mirror = Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0));
        let n = skin_normal_matrix(mirror) * Vec3::X;
        assert_eq!(n, Vec3::new(-1.0, 0.0, 0.0));
    }
}

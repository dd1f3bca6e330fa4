//! Extraction of the meshes that change shape: for each drawn entity whose mesh has a
//! [`crate::scene::deform::Deformation`] and that carries a [`SkinnedMesh`] or
//! [`MorphWeights`] (its own or its parent's), this frame's joint matrices and morph
//! weights, and the box that holds the deformed mesh (so culling and shadow fitting see
//! where the mesh is now, not where its rest pose was).

use crate::scene::{Aabb, GlobalTransform, MeshHandle, Meshes, MorphWeights, SkinnedMesh};
use bevy_ecs::hierarchy::ChildOf;
use bevy_ecs::prelude::*;
use bevy_ecs::system::SystemParam;
use std::collections::HashSet;
use std::hash::{Hash, Hasher};

/// One deformed instance of the frame: what the deformation pass computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeformedInstance {
    /// The drawn entity (its deformed vertices are kept per entity).
    pub entity: Entity,
    /// Its mesh.
    pub mesh: MeshHandle,
    /// Skinned: its vertices come out in world space (its own transform is ignored).
    pub skinned: bool,
    /// Its first joint matrix in [`DeformedFrame::joint_matrices`].
    pub joint_offset: u32,
    /// How many joint matrices it has.
    pub joint_count: u32,
    /// Its first weight in [`DeformedFrame::morph_weights`].
    pub weight_offset: u32,
    /// How many morph weights it has (its mesh's targets).
    pub weight_count: u32,
    /// A hash of its joint matrices and weights: equal poses, equal hashes (the shadow
    /// atlas cache compares it).
    pub pose: u64,
}

/// This frame's deformed instances and their inputs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DeformedFrame {
    /// The instances, in the order extraction met them.
    pub instances: Vec<DeformedInstance>,
    /// Joint matrices `J_j` (world from bind-pose model space), column-major.
    pub joint_matrices: Vec<[[f32; 4]; 4]>,
    /// Morph weights; a non-finite weight is stored as 0.
    pub morph_weights: Vec<f32>,
}

impl DeformedFrame {
    /// Forgets the previous frame's instances.
    pub fn clear(&mut self) {
        self.instances.clear();
        self.joint_matrices.clear();
        self.morph_weights.clear();
    }

    /// Instance `d`'s vertices in its pose this frame, deformed on the CPU
    /// ([`crate::scene::deform::Deformation::deformed_vertices`]) with its joint matrices
    /// and weights: what the deformation pass computes on the GPU. `None` where its mesh
    /// or deformation is missing.
    pub fn posed_vertices(
        &self,
        d: &DeformedInstance,
        meshes: &Meshes,
    ) -> Option<Vec<crate::scene::mesh_data::Vertex>> {
        let mesh = meshes.get(d.mesh)?;
        let deformation = meshes.deformation(d.mesh)?;
        let joints: Vec<glam::Mat4> = self
            .joint_matrices
            .iter()
            .skip(d.joint_offset as usize)
            .take(d.joint_count as usize)
            .map(glam::Mat4::from_cols_array_2d)
            .collect();
        let weights: Vec<f32> = self
            .morph_weights
            .iter()
            .skip(d.weight_offset as usize)
            .take(d.weight_count as usize)
            .copied()
            .collect();
        Some(deformation.deformed_vertices(mesh, d.skinned.then_some(&joints[..]), &weights))
    }
}

/// What extraction learns of one deformed entity.
pub struct Deformed {
    /// Index into [`DeformedFrame::instances`].
    pub index: u32,
    /// Skinned (vertices in world space).
    pub skinned: bool,
    /// The deformed mesh's box: in world space when skinned, model space otherwise.
    pub bounds: Option<Aabb>,
}

/// The components deformation reads.
#[derive(SystemParam)]
pub struct DeformSources<'w, 's> {
    skins: Query<'w, 's, &'static SkinnedMesh>,
    weights: Query<'w, 's, &'static MorphWeights>,
    parents: Query<'w, 's, &'static ChildOf>,
    transforms: Query<'w, 's, &'static GlobalTransform>,
    warned: Local<'s, HashSet<Entity>>,
}

impl DeformSources<'_, '_> {
    /// The deformation of `entity` (drawing `mesh`) this frame, appended to `out`; `None`
    /// when it is drawn rigid: its mesh has no deformation, or nothing drives it, or its
    /// skin names fewer joints than the mesh uses (a warning, once per entity).
    pub fn extract(
        &mut self,
        entity: Entity,
        mesh: MeshHandle,
        meshes: &Meshes,
        out: &mut DeformedFrame,
    ) -> Option<Deformed> {
        let deformation = meshes.deformation(mesh)?;
        let skin = self
            .skins
            .get(entity)
            .ok()
            .filter(|_| deformation.skinned());
        if let Some(s) = skin
            && s.joints.len().min(s.inverse_bind.len()) < deformation.joint_count()
        {
            if self.warned.insert(entity) {
                log::warn!(
                    "entity {entity}: its skin has {} joints but its mesh uses {}: drawn unskinned",
                    s.joints.len().min(s.inverse_bind.len()),
                    deformation.joint_count()
                );
            }
            return None;
        }
        let targets = deformation.targets().len();
        let weights = (targets > 0)
            .then(|| {
                self.weights.get(entity).ok().or_else(|| {
                    let parent = self.parents.get(entity).ok()?.parent();
                    self.weights.get(parent).ok()
                })
            })
            .flatten();
        if skin.is_none() && weights.is_none() {
            return None;
        }
        let mut morph: Vec<f32> = weights.map_or_else(Vec::new, |w| {
            w.0.iter()
                .map(|&w| if w.is_finite() { w } else { 0.0 })
                .collect()
        });
        morph.resize(targets, 0.0);
        let matrices = skin.map(|s| s.joint_matrices(|j| self.transforms.get(j).ok().map(|g| g.0)));
        let bounds = deformation.bounds(meshes.bounds(mesh), matrices.as_deref(), &morph);
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        for m in matrices.iter().flatten() {
            m.to_cols_array().map(f32::to_bits).hash(&mut hasher);
        }
        morph
            .iter()
            .map(|w| w.to_bits())
            .for_each(|w| w.hash(&mut hasher));
        let index = out.instances.len() as u32;
        out.instances.push(DeformedInstance {
            entity,
            mesh,
            skinned: matrices.is_some(),
            joint_offset: out.joint_matrices.len() as u32,
            joint_count: matrices.as_ref().map_or(0, Vec::len) as u32,
            weight_offset: out.morph_weights.len() as u32,
            weight_count: targets as u32,
            pose: hasher.finish(),
        });
        out.joint_matrices
            .extend(matrices.iter().flatten().map(|m| m.to_cols_array_2d()));
        out.morph_weights.extend(morph);
        Some(Deformed {
            index,
            skinned: skin.is_some(),
            bounds,
        })
    }
}

//! Triangle meshes: CPU data shared between entities through a handle.

pub use crate::scene::mesh_data::{Aabb, MeshData, Vertex};
use bevy_ecs::prelude::*;
use std::sync::Arc;

/// Identifies a mesh in [`Meshes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MeshHandle(pub u32);

/// Draws the mesh `0` at this entity's [`crate::scene::GlobalTransform`] with its
/// [`crate::scene::Material`].
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
#[require(crate::scene::Transform, crate::scene::Material)]
pub struct Mesh3d(pub MeshHandle);

/// The mesh store: every mesh is added once and shared by any number of entities.
#[derive(Resource, Clone, Default, Debug)]
pub struct Meshes {
    meshes: Vec<Arc<MeshData>>,
    /// Each mesh's [`MeshData::bounds`], computed once when it is added: extraction asks
    /// for them per instance and per view (a probe capture has six views per probe).
    bounds: Vec<Option<Aabb>>,
    /// Each mesh's skin weights and morph targets, if it has any.
    deformations: Vec<Option<Arc<crate::scene::deform::Deformation>>>,
}

impl Meshes {
    /// Adds a mesh and returns its handle. Fails (with the reason) on a mesh that breaks
    /// [`MeshData::validate`].
    pub fn add(&mut self, mesh: MeshData) -> Result<MeshHandle, String> {
        mesh.validate()?;
        let index = u32::try_from(self.meshes.len()).map_err(|_| "too many meshes".to_string())?;
        self.bounds.push(mesh.bounds());
        self.meshes.push(Arc::new(mesh));
        self.deformations.push(None);
        Ok(MeshHandle(index))
    }

    /// Adds a mesh that a [`crate::scene::SkinnedMesh`] or [`crate::scene::MorphWeights`]
    /// deforms, with its joints, weights and morph targets (see
    /// [`crate::scene::deform::Deformation::new`]). Fails with the reason on an invalid
    /// mesh or deformation.
    pub fn add_deformable(
        &mut self,
        mesh: MeshData,
        joints: Vec<[u32; 4]>,
        weights: Vec<[f32; 4]>,
        targets: Vec<crate::scene::MorphTarget>,
    ) -> Result<MeshHandle, String> {
        let deformation = crate::scene::deform::Deformation::new(&mesh, joints, weights, targets)?;
        // `add` validates the mesh.
        let handle = self.add(mesh)?;
        self.deformations[handle.0 as usize] = Some(Arc::new(deformation));
        Ok(handle)
    }

    /// The joints, weights and morph targets of the mesh behind a handle, if it has any.
    pub fn deformation(
        &self,
        handle: MeshHandle,
    ) -> Option<&Arc<crate::scene::deform::Deformation>> {
        self.deformations.get(handle.0 as usize)?.as_ref()
    }

    /// The bounding box of the mesh behind a handle (model space); `None` for an unknown
    /// handle or an empty mesh.
    pub fn bounds(&self, handle: MeshHandle) -> Option<Aabb> {
        self.bounds.get(handle.0 as usize).copied().flatten()
    }

    /// The mesh behind a handle.
    pub fn get(&self, handle: MeshHandle) -> Option<&Arc<MeshData>> {
        self.meshes.get(handle.0 as usize)
    }

    /// Number of meshes.
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// Whether the store is empty.
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }
}

/// The world-space box around every placed mesh (a [`Mesh3d`] with a
/// [`crate::scene::GlobalTransform`]), or `None` when there is none.
pub fn scene_bounds(world: &mut World) -> Option<Aabb> {
    let placed: Vec<_> = world
        .query::<(&Mesh3d, &crate::scene::GlobalTransform)>()
        .iter(world)
        .map(|(mesh, t)| (mesh.0, t.0))
        .collect();
    let meshes = world.resource::<Meshes>();
    placed
        .iter()
        .filter_map(|(mesh, m)| meshes.bounds(*mesh)?.transformed(m))
        .reduce(|a, b| a.union(&b))
}

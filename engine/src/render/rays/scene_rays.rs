//! The frame's acceleration structure, kept across frames: one BLAS per mesh (built
//! once), one per deformed instance (built once in its first pose, refitted when its pose
//! changes), the TLAS rebuilt only when the instances or a refit change it, and the four
//! storage buffers `shaders/rays.wgsl` binds. [`RayCounts`] says what each frame paid.

use crate::error::Result;
use crate::rays::blas::Blas;
use crate::rays::node::BvhNode;
use crate::rays::tlas::{InstanceInput, RayScene, SURFACE_BLENDED, SURFACE_MASKED, SURFACE_OPAQUE};
use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::scene_buffers::GrowableBuffer;
use crate::scene::{MeshHandle, Meshes};
use bevy_ecs::prelude::{Entity, Resource};
use glam::{Mat4, Vec3};
use std::collections::BTreeMap;

/// The bind group index of [`RAYS`] in the GPU's tracing shaders (their `RAYS_GROUP`).
pub const RAYS_GROUP: u32 = 1;

/// The group a tracing shader binds at `RAYS_GROUP`: TLAS nodes, instances, BLAS nodes,
/// triangles.
pub const RAYS: BindGroupSpec = BindGroupSpec::compute("rays", declared::RAY_BATCH_RAYS_GROUP);

/// Which hierarchy an instance traces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum BlasKey {
    /// A mesh drawn as stored: shared by its instances.
    Mesh(MeshHandle),
    /// A deformed instance's own vertices.
    Deformed(Entity),
}

/// What building the structure cost, counted since the resource was made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// BLAS builds (one per mesh and per deformed instance).
    pub blas_builds: u64,
    /// BLAS refits (a deformed instance's pose changed).
    pub blas_refits: u64,
    /// TLAS builds.
    pub tlas_builds: u64,
    /// Updates that changed nothing: the buffers were kept as they were.
    pub kept: u64,
    /// Triangles left out of the last build for a non-finite corner.
    pub dropped_triangles: u32,
    /// Instances left out of the last TLAS (empty mesh, singular transform).
    pub skipped_instances: u32,
}

/// The structure and its GPU buffers.
#[derive(Resource, Default)]
pub struct SceneRays {
    blases: BTreeMap<BlasKey, Blas>,
    poses: BTreeMap<Entity, u64>,
    instances: Vec<(BlasKey, InstanceInput)>,
    scene: RayScene,
    buffers: Option<[GrowableBuffer; 4]>,
    /// What was built, refitted and kept.
    pub counts: RayCounts,
}

impl SceneRays {
    /// A structure given whole (tests, tools): uploaded as it is; [`SceneRays::update`]
    /// would replace it.
    pub fn with_scene(gpu: &Gpu, scene: RayScene) -> SceneRays {
        let mut rays = SceneRays {
            scene,
            ..SceneRays::default()
        };
        rays.upload(gpu, true);
        rays
    }

    /// The packed structure of the last update.
    pub fn scene(&self) -> &RayScene {
        &self.scene
    }

    /// Brings the structure up to date with `frame`: builds the hierarchies of meshes it
    /// has not seen, refits deformed instances whose pose changed, rebuilds the TLAS when
    /// the instances or a hierarchy changed, and writes only what changed to the GPU.
    pub fn update(&mut self, gpu: &Gpu, frame: &ExtractedFrame, meshes: &Meshes) -> Result<()> {
        let mut blases_changed = false;
        let mut instances = Vec::with_capacity(frame.instances.len());
        for batch in &frame.batches {
            let deformed = batch
                .deformed
                .and_then(|d| frame.deformed.instances.get(d as usize));
            let key = match deformed {
                Some(d) => BlasKey::Deformed(d.entity),
                None => BlasKey::Mesh(batch.mesh),
            };
            blases_changed |= self.ensure_blas(key, batch.mesh, deformed, frame, meshes);
            let masked = batch
                .maps
                .and_then(|m| frame.material_maps.get(m as usize))
                .is_some_and(|m| m.maps.alpha_cutoff.is_some());
            let surface = if batch.blend {
                SURFACE_BLENDED
            } else if masked {
                SURFACE_MASKED
            } else {
                SURFACE_OPAQUE
            };
            let range = batch.first_instance..batch.first_instance + batch.count;
            for i in range {
                let Some(inst) = frame.instances.get(i as usize) else {
                    continue;
                };
                instances.push((
                    key,
                    InstanceInput {
                        blas: 0,
                        world_from_local: Mat4::from_cols_array_2d(&inst.world_from_local),
                        surface,
                        material: i,
                    },
                ));
            }
        }
        let instances_changed = instances != self.instances;
        if !blases_changed && !instances_changed && self.buffers.is_some() {
            self.counts.kept += 1;
            return Ok(());
        }
        // BLAS order is the map's: index each instance's key.
        let keys: Vec<BlasKey> = self.blases.keys().copied().collect();
        let refs: Vec<&Blas> = self.blases.values().collect();
        let inputs: Vec<InstanceInput> = instances
            .iter()
            .map(|(key, input)| InstanceInput {
                blas: keys.binary_search(key).unwrap_or(usize::MAX),
                ..*input
            })
            .collect();
        if blases_changed || self.buffers.is_none() {
            self.scene = RayScene::new(&refs, &inputs);
        } else {
            self.scene.set_instances(&refs, &inputs);
        }
        self.instances = instances;
        self.counts.tlas_builds += 1;
        self.counts.dropped_triangles = refs.iter().map(|b| b.dropped).sum();
        self.counts.skipped_instances = self.scene.skipped_instances;
        self.upload(gpu, blases_changed);
        Ok(())
    }

    /// Builds or refits the hierarchy of `key`; whether it changed.
    fn ensure_blas(
        &mut self,
        key: BlasKey,
        mesh: MeshHandle,
        deformed: Option<&crate::render::extract::deformed::DeformedInstance>,
        frame: &ExtractedFrame,
        meshes: &Meshes,
    ) -> bool {
        let built = self.blases.contains_key(&key);
        if let Some(d) = deformed {
            if built && self.poses.get(&d.entity) == Some(&d.pose) {
                return false;
            }
            let Some((positions, indices)) = posed_positions(frame, d, meshes) else {
                return false;
            };
            self.poses.insert(d.entity, d.pose);
            match self.blases.get_mut(&key) {
                Some(blas) => {
                    blas.refit(&positions, &indices);
                    self.counts.blas_refits += 1;
                }
                None => {
                    self.blases.insert(key, Blas::build(&positions, &indices));
                    self.counts.blas_builds += 1;
                }
            }
            return true;
        }
        if built {
            return false;
        }
        let Some(data) = meshes.get(mesh) else {
            return false;
        };
        let positions: Vec<Vec3> = data
            .vertices
            .iter()
            .map(|v| Vec3::from(v.position))
            .collect();
        self.blases
            .insert(key, Blas::build(&positions, &data.indices));
        self.counts.blas_builds += 1;
        true
    }

    fn upload(&mut self, gpu: &Gpu, blases_changed: bool) {
        let usage = wgpu::BufferUsages::STORAGE;
        let fresh = self.buffers.is_none();
        let buffers = self.buffers.get_or_insert_with(|| {
            [
                "rays: tlas nodes",
                "rays: instances",
                "rays: blas nodes",
                "rays: triangles",
            ]
            .map(|label| GrowableBuffer::with_usage(gpu, label, 256, usage))
        });
        // A shader reads the TLAS root (and a root of each BLAS it enters): an empty level
        // gets one node whose box nothing enters.
        let empty = [BvhNode {
            lo: [f32::INFINITY; 3],
            hi: [f32::NEG_INFINITY; 3],
            ..BvhNode::default()
        }];
        let or_empty = |nodes: &[BvhNode]| -> Vec<u8> {
            bytemuck::cast_slice(if nodes.is_empty() { &empty } else { nodes }).to_vec()
        };
        buffers[0].write(gpu, &or_empty(&self.scene.tlas_nodes));
        buffers[1].write(gpu, bytemuck::cast_slice(&self.scene.instances));
        if blases_changed || fresh {
            buffers[2].write(gpu, &or_empty(&self.scene.blas_nodes));
            buffers[3].write(gpu, bytemuck::cast_slice(&self.scene.triangles));
        }
    }

    /// The four buffers in `RAYS`'s order, once [`SceneRays::update`] has run.
    pub fn resources(&self) -> Option<Vec<wgpu::BindingResource<'_>>> {
        self.buffers
            .as_ref()
            .map(|b| b.iter().map(|b| b.buffer.as_entire_binding()).collect())
    }
}

/// The deformed instance's vertex positions in its pose (m) and its mesh's indices.
fn posed_positions(
    frame: &ExtractedFrame,
    d: &crate::render::extract::deformed::DeformedInstance,
    meshes: &Meshes,
) -> Option<(Vec<Vec3>, Vec<u32>)> {
    let mesh = meshes.get(d.mesh)?;
    let vertices = frame.deformed.posed_vertices(d, meshes)?;
    Some((
        vertices.iter().map(|v| Vec3::from(v.position)).collect(),
        mesh.indices.clone(),
    ))
}

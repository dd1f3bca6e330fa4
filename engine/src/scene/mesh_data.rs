//! Mesh geometry as plain data: vertices, indexed triangles and bounding boxes.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

/// One vertex as the G-buffer pass reads it (72 bytes, interleaved).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Object-space position in metres.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinate (set 0).
    pub uv: [f32; 2],
    /// Object-space unit tangent (xyz) and bitangent sign (w = ±1), as in glTF.
    pub tangent: [f32; 4],
    /// Texture coordinate set 1.
    pub uv1: [f32; 2],
    /// Linear RGBA vertex colour, multiplying the base colour (white when the mesh has
    /// none). Used only by entities with [`crate::scene::MaterialMaps`].
    pub color: [f32; 4],
}

impl Vertex {
    /// A vertex with no second texture coordinate set and a white colour.
    pub fn new(position: [f32; 3], normal: [f32; 3], uv: [f32; 2], tangent: [f32; 4]) -> Self {
        Vertex {
            position,
            normal,
            uv,
            tangent,
            uv1: [0.0; 2],
            color: [1.0; 4],
        }
    }
}

/// Axis-aligned bounding box in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box around a set of points; `None` when there is no finite point.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Option<Aabb> {
        let mut min = Vec3::splat(f32::INFINITY);
        let mut max = Vec3::splat(f32::NEG_INFINITY);
        for p in points.into_iter().filter(|p| p.is_finite()) {
            min = min.min(p);
            max = max.max(p);
        }
        (min.x <= max.x).then_some(Aabb { min, max })
    }

    /// The box around this box transformed by `m`.
    pub fn transformed(&self, m: &Mat4) -> Option<Aabb> {
        let (a, b) = (self.min, self.max);
        Aabb::from_points((0..8).map(|i| {
            m.transform_point3(Vec3::new(
                if i & 1 == 0 { a.x } else { b.x },
                if i & 2 == 0 { a.y } else { b.y },
                if i & 4 == 0 { a.z } else { b.z },
            ))
        }))
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Centre point.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
}

/// An indexed triangle list.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshData {
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Three indices per triangle, each `< vertices.len()`.
    pub indices: Vec<u32>,
}

impl MeshData {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Bounding box of the vertices; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(self.vertices.iter().map(|v| Vec3::from(v.position)))
    }

    /// Checks the invariants the renderer relies on: whole triangles, indices in range,
    /// finite positions. Returns a description of the first problem.
    pub fn validate(&self) -> Result<(), String> {
        if !self.indices.len().is_multiple_of(3) {
            return Err(format!(
                "{} indices is not a whole number of triangles",
                self.indices.len()
            ));
        }
        if let Some(i) = self
            .indices
            .iter()
            .find(|&&i| i as usize >= self.vertices.len())
        {
            return Err(format!(
                "index {i} points past the {} vertices",
                self.vertices.len()
            ));
        }
        if let Some(n) = self
            .vertices
            .iter()
            .position(|v| !Vec3::from(v.position).is_finite())
        {
            return Err(format!("vertex {n} has a non-finite position"));
        }
        Ok(())
    }
}

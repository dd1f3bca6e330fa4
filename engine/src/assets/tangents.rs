//! Tangents for meshes that lack them: MikkTSpace (Mikkelsen 2008, the tangent space glTF
//! and the common bakers assume), through the `bevy_mikktspace` crate.
//!
//! glTF's texture coordinates start at the image's top-left (v grows downwards) while a
//! normal map's +Y points up the image, so glTF's bitangent, cross(normal, tangent) × w,
//! must point towards decreasing v. MikkTSpace's bitangent follows increasing v, so it
//! is given v' = 1 − v, as the exporters do from their bottom-left coordinates.

use crate::scene::MeshData;
use bevy_mikktspace::{Geometry, TangentSpace, generate_tangents};
use glam::Vec3;

struct Faces<'a> {
    mesh: &'a mut MeshData,
    written: Vec<bool>,
}

impl Faces<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.mesh.indices[face * 3 + vert] as usize
    }
}

impl Geometry for Faces<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len() / 3
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.vertices[self.vertex(face, vert)].position
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.vertices[self.vertex(face, vert)].normal
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let [u, v] = self.mesh.vertices[self.vertex(face, vert)].uv;
        [u, 1.0 - v]
    }

    fn set_tangent(&mut self, tangent_space: Option<TangentSpace>, face: usize, vert: usize) {
        let v = self.vertex(face, vert);
        if let Some(t) = tangent_space {
            self.mesh.vertices[v].tangent = t.tangent_encoded();
            self.written[v] = true;
        }
    }
}

/// Writes MikkTSpace tangents (xyz, handedness w = ±1) into every vertex of a validated
/// mesh (indices in range, a whole number of triangles). Vertices MikkTSpace gives no
/// tangent (degenerate texture coordinates, unused vertices) get an arbitrary unit
/// tangent perpendicular to their normal, with w = 1. Returns how many did.
pub fn generate_mikktspace(mesh: &mut MeshData) -> usize {
    let count = mesh.vertices.len();
    let mut faces = Faces {
        mesh,
        written: vec![false; count],
    };
    // The crate reports an error only for meshes without faces; those keep the fallback.
    let _ = generate_tangents(&mut faces);
    let Faces { mesh, written } = faces;
    let mut fallbacks = 0;
    for (v, ok) in mesh.vertices.iter_mut().zip(written) {
        let n = Vec3::from(v.normal).try_normalize().unwrap_or(Vec3::Z);
        let t = Vec3::from_slice(&v.tangent[..3]);
        if !ok || !t.is_finite() || t.length_squared() < 1e-12 {
            v.tangent = n.any_orthonormal_vector().extend(1.0).into();
            fallbacks += 1;
        }
    }
    fallbacks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Vertex;

    /// A unit quad in the xy plane facing +z, with u along +x and v along `v_dir`.
    fn quad(v_dir: f32) -> MeshData {
        let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        MeshData {
            vertices: corners
                .iter()
                .map(|&[x, y]| {
                    Vertex::new(
                        [x, y, 0.0],
                        [0.0, 0.0, 1.0],
                        [x, if v_dir > 0.0 { y } else { 1.0 - y }],
                        [0.0; 4],
                    )
                })
                .collect(),
            indices: vec![0, 1, 2, 0, 2, 3],
        }
    }

    #[test]
    fn tangents_follow_u_and_bitangents_point_up_the_image() {
        // v along +y: the image's top (small v) is at −y, where glTF's bitangent points.
        for (v_dir, w) in [(1.0, -1.0), (-1.0, 1.0)] {
            let mut mesh = quad(v_dir);
            assert_eq!(generate_mikktspace(&mut mesh), 0);
            for v in &mesh.vertices {
                let t = Vec3::from_slice(&v.tangent[..3]);
                assert!((t - Vec3::X).length() < 1e-5, "{t}");
                assert_eq!(v.tangent[3], w, "v along {v_dir}");
            }
        }
    }

    #[test]
    fn degenerate_uvs_get_a_perpendicular_fallback() {
        let mut mesh = quad(1.0);
        for v in &mut mesh.vertices {
            v.uv = [0.5, 0.5];
        }
        generate_mikktspace(&mut mesh);
        for v in &mesh.vertices {
            let t = Vec3::from_slice(&v.tangent[..3]);
            assert!(t.is_normalized() && t.dot(Vec3::Z).abs() < 1e-5, "{t}");
        }
    }
}

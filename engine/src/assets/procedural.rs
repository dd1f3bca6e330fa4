//! Procedural meshes with normals, UVs and tangents: UV sphere, cube, plane.
//!
//! Triangles wind counter-clockwise seen from the side their normals point to. UVs have
//! their origin at the top left (glTF), and the tangent points along +u with w = +1, so
//! the bitangent `cross(normal, tangent.xyz) · w` points along −v (up in the image).

use crate::scene::{MeshData, Vertex};
use glam::Vec3;
use std::f32::consts::PI;

/// A UV sphere of `radius` metres centred on the origin, poles on ±Y, with `sectors`
/// longitude segments (≥ 3) and `stacks` latitude segments (≥ 2). Like Bevy's, the pole
/// rows have one triangle per sector: 2 · sectors · (stacks − 1) triangles in all
/// (960 for 32 × 16).
pub fn uv_sphere(radius: f32, sectors: u32, stacks: u32) -> MeshData {
    let sectors = sectors.max(3);
    let stacks = stacks.max(2);
    let mut vertices = Vec::with_capacity(((sectors + 1) * (stacks + 1)) as usize);
    for i in 0..=stacks {
        let theta = i as f32 * PI / stacks as f32;
        let (sin_t, cos_t) = theta.sin_cos();
        for j in 0..=sectors {
            let phi = j as f32 * 2.0 * PI / sectors as f32;
            let (sin_p, cos_p) = phi.sin_cos();
            let normal = Vec3::new(sin_t * sin_p, cos_t, sin_t * cos_p);
            vertices.push(Vertex::new(
                (normal * radius).into(),
                normal.into(),
                [j as f32 / sectors as f32, i as f32 / stacks as f32],
                [cos_p, 0.0, -sin_p, 1.0],
            ));
        }
    }
    let mut indices = Vec::with_capacity((6 * sectors * (stacks - 1)) as usize);
    let row = sectors + 1;
    for i in 0..stacks {
        for j in 0..sectors {
            let k1 = i * row + j;
            let k2 = k1 + row;
            if i != 0 {
                indices.extend_from_slice(&[k1, k2, k1 + 1]);
            }
            if i != stacks - 1 {
                indices.extend_from_slice(&[k1 + 1, k2, k2 + 1]);
            }
        }
    }
    MeshData { vertices, indices }
}

/// Appends one rectangle facing `normal`, spanning ±`half_u` along `tangent` and
/// ±`half_v` along the bitangent `normal × tangent`, centred at `center`.
fn push_quad(
    mesh: &mut MeshData,
    center: Vec3,
    normal: Vec3,
    tangent: Vec3,
    half_u: f32,
    half_v: f32,
) {
    let bitangent = normal.cross(tangent);
    let base = mesh.vertices.len() as u32;
    for (su, sv) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let position = center + tangent * (su * half_u) + bitangent * (sv * half_v);
        mesh.vertices.push(Vertex::new(
            position.into(),
            normal.into(),
            [(su + 1.0) * 0.5, (1.0 - sv) * 0.5],
            tangent.extend(1.0).into(),
        ));
    }
    mesh.indices
        .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
}

/// An axis-aligned box centred on the origin with edge lengths `size` (m); 24 vertices so
/// that every face has its own normal.
pub fn cuboid(size: Vec3) -> MeshData {
    let h = size * 0.5;
    let mut mesh = MeshData {
        vertices: Vec::with_capacity(24),
        indices: Vec::with_capacity(36),
    };
    let faces = [
        (Vec3::X, Vec3::NEG_Z, h.x, h.z, h.y),
        (Vec3::NEG_X, Vec3::Z, h.x, h.z, h.y),
        (Vec3::Y, Vec3::X, h.y, h.x, h.z),
        (Vec3::NEG_Y, Vec3::X, h.y, h.x, h.z),
        (Vec3::Z, Vec3::X, h.z, h.x, h.y),
        (Vec3::NEG_Z, Vec3::NEG_X, h.z, h.x, h.y),
    ];
    for (normal, tangent, offset, half_u, half_v) in faces {
        push_quad(&mut mesh, normal * offset, normal, tangent, half_u, half_v);
    }
    mesh
}

/// A cube of edge `size` metres.
pub fn cube(size: f32) -> MeshData {
    cuboid(Vec3::splat(size))
}

/// A horizontal plane through the origin facing +Y, `size_x` by `size_z` metres.
pub fn plane(size_x: f32, size_z: f32) -> MeshData {
    let mut mesh = MeshData {
        vertices: Vec::with_capacity(4),
        indices: Vec::with_capacity(6),
    };
    push_quad(
        &mut mesh,
        Vec3::ZERO,
        Vec3::Y,
        Vec3::X,
        size_x * 0.5,
        size_z * 0.5,
    );
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(mesh: &MeshData) {
        assert_eq!(mesh.validate(), Ok(()));
        for v in &mesh.vertices {
            let n = Vec3::from(v.normal);
            let t = Vec3::from_slice(&v.tangent[..3]);
            assert!((n.length() - 1.0).abs() < 1e-5, "normal {n}");
            assert!((t.length() - 1.0).abs() < 1e-5, "tangent {t}");
            assert!(n.dot(t).abs() < 1e-5, "tangent not orthogonal: {n} {t}");
            assert_eq!(v.tangent[3].abs(), 1.0);
            assert!(v.uv.iter().all(|c| (0.0..=1.0).contains(c)));
        }
        // Counter-clockwise winding seen from the normal side.
        for tri in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| &mesh.vertices[tri[k] as usize]);
            let (pa, pb, pc) = (
                Vec3::from(a.position),
                Vec3::from(b.position),
                Vec3::from(c.position),
            );
            let geometric = (pb - pa).cross(pc - pa);
            let shading = Vec3::from(a.normal) + Vec3::from(b.normal) + Vec3::from(c.normal);
            assert!(geometric.dot(shading) > 0.0, "clockwise triangle {tri:?}");
        }
    }

    #[test]
    fn sphere_like_the_peer() {
        let s = uv_sphere(0.4, 32, 16);
        check(&s);
        assert_eq!(s.triangle_count(), 960);
        assert_eq!(s.vertices.len(), 33 * 17);
        for v in &s.vertices {
            assert!((Vec3::from(v.position).length() - 0.4).abs() < 1e-5);
        }
        // The tangent follows +u: neighbouring vertices along a row move along it.
        let (a, b) = (&s.vertices[8 * 33 + 3], &s.vertices[8 * 33 + 4]);
        let du = Vec3::from(b.position) - Vec3::from(a.position);
        assert!(du.dot(Vec3::from_slice(&a.tangent[..3])) > 0.0);
        // The bitangent cross(n, t) points towards the north pole (−v).
        let n = Vec3::from(a.normal);
        let bt = n.cross(Vec3::from_slice(&a.tangent[..3]));
        assert!(bt.y > 0.0);
    }

    #[test]
    fn cube_and_plane() {
        let c = cube(2.0);
        check(&c);
        assert_eq!(c.triangle_count(), 12);
        let b = c.bounds().map(|b| (b.min, b.max));
        assert_eq!(b, Some((Vec3::splat(-1.0), Vec3::splat(1.0))));
        let p = plane(20.0, 10.0);
        check(&p);
        assert_eq!(p.triangle_count(), 2);
        assert!(p.vertices.iter().all(|v| v.normal == [0.0, 1.0, 0.0]));
        let b = p.bounds().map(|b| (b.min, b.max));
        assert_eq!(
            b,
            Some((Vec3::new(-10.0, 0.0, -5.0), Vec3::new(10.0, 0.0, 5.0)))
        );
    }
}

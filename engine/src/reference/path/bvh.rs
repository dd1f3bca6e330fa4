//! The path tracer's scene hierarchy: every instance's triangles in world space in one
//! [`crate::rays::blas::Blas`] (binned SAH, the watertight test of Woop, Benthin and Wald
//! 2013), the builder and traversal the GPU's tracing passes share.

use crate::rays::blas::Blas;
use glam::Vec3;

/// A triangle's corners in world space (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Corners.
    pub p: [Vec3; 3],
}

/// The hierarchy. Triangle indices it returns are indices into the slice it was built
/// from.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    blas: Blas,
    triangles: Vec<Triangle>,
}

/// A ray hit: distance along the (unit) direction, triangle index and barycentrics of
/// corners 1 and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance (m).
    pub t: f32,
    /// Triangle index.
    pub triangle: u32,
    /// Barycentric weight of corner 1.
    pub u: f32,
    /// Barycentric weight of corner 2.
    pub v: f32,
}

impl Bvh {
    /// Builds the hierarchy over `triangles` (one with a non-finite corner is never hit).
    pub fn build(triangles: Vec<Triangle>) -> Bvh {
        let positions: Vec<Vec3> = triangles.iter().flat_map(|t| t.p).collect();
        let indices: Vec<u32> = (0..positions.len() as u32).collect();
        Bvh {
            blas: Blas::build(&positions, &indices),
            triangles,
        }
    }

    /// The hierarchy itself, in world space (what the GPU path tracer uploads).
    pub fn blas(&self) -> &Blas {
        &self.blas
    }

    /// The triangles, in the order they were given.
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// The closest hit along `origin + t·dir` with `t_min < t < t_max`.
    pub fn closest(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        self.traverse(origin, dir, t_min, t_max, false)
    }

    /// Whether anything lies along the ray between `t_min` and `t_max`.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        self.traverse(origin, dir, t_min, t_max, true).is_some()
    }

    fn traverse(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32, any: bool) -> Option<Hit> {
        let hit = self
            .blas
            .trace(origin, dir, t_min, t_max, any, &mut |_, _| true)?;
        Some(Hit {
            t: hit.hit.t,
            triangle: hit.primitive,
            u: hit.hit.b,
            v: hit.hit.c,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rays::watertight::{intersect_triangle, ray_transform};

    fn grid(n: u32) -> Vec<Triangle> {
        // n × n unit quads in the z = 0 plane, two triangles each.
        let mut out = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (i as f32, j as f32);
                let a = Vec3::new(x, y, 0.0);
                let b = Vec3::new(x + 1.0, y, 0.0);
                let c = Vec3::new(x + 1.0, y + 1.0, 0.0);
                let d = Vec3::new(x, y + 1.0, 0.0);
                out.push(Triangle { p: [a, b, c] });
                out.push(Triangle { p: [a, c, d] });
            }
        }
        out
    }

    #[test]
    fn hits_agree_with_brute_force() {
        let tris = grid(16);
        let bvh = Bvh::build(tris.clone());
        let mut state = 12345u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        for _ in 0..500 {
            let origin = Vec3::new(next() * 20.0 - 2.0, next() * 20.0 - 2.0, 3.0 + next());
            let dir = Vec3::new(next() - 0.5, next() - 0.5, -1.0).normalize();
            let ray = ray_transform(dir);
            let brute = tris
                .iter()
                .enumerate()
                .filter_map(|(i, t)| {
                    intersect_triangle(origin, &ray, t.p, 1e-4, f32::MAX).map(|h| (h.t, i))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let hit = bvh.closest(origin, dir, 1e-4, f32::MAX);
            assert_eq!(brute.map(|(_, i)| i as u32), hit.map(|h| h.triangle));
            if let (Some((d, _)), Some(h)) = (brute, hit) {
                assert!((d - h.t).abs() < 1e-4);
                assert!(bvh.occluded(origin, dir, 1e-4, d + 1.0));
                assert!(!bvh.occluded(origin, dir, 1e-4, d * 0.5));
            }
        }
    }

    #[test]
    fn empty_and_degenerate_input() {
        let bvh = Bvh::build(Vec::new());
        assert!(bvh.closest(Vec3::ZERO, Vec3::Z, 0.0, 1.0).is_none());
        let flat = vec![Triangle { p: [Vec3::ZERO; 3] }; 10];
        let bvh = Bvh::build(flat);
        assert!(
            bvh.closest(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, 0.0, 10.0)
                .is_none()
        );
    }
}

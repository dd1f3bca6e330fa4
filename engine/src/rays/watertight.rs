//! The watertight ray–triangle test of Woop, Benthin and Wald 2013 ("Watertight
//! ray/triangle intersection", JCGT 2(1)).
//!
//! The ray is made the +z axis of a sheared frame: `kz` is the axis of the direction's
//! largest magnitude, `kx = (kz + 1) mod 3`, `ky = (kx + 1) mod 3` (swapped when
//! `d[kz] < 0`, keeping the frame's winding), and the shear is `S = (d[kx]/d[kz],
//! d[ky]/d[kz], 1/d[kz])`. A corner `P` relative to the origin maps to
//! `(P[kx] − S_x·P[kz], P[ky] − S_y·P[kz])`. The 2-D edge functions
//! `U = C_x·B_y − C_y·B_x`, `V = A_x·C_y − A_y·C_x`, `W = B_x·A_y − B_y·A_x` are the
//! signed areas opposite corners A, B and C; the ray passes inside when they share a
//! sign (zero counts as either), and the distance is `t = (U·A_z + V·B_z + W·C_z) / det`
//! with `det = U + V + W` and `P_z = S_z·P[kz]`.
//!
//! Watertightness: two triangles sharing an edge compute that edge's function from the
//! same two transformed corners, in the opposite order, so the values are exact
//! negatives of each other, and a ray on the edge (value 0) is inside both. The paper
//! recomputes a zero edge in double precision to break ties consistently; WGSL has no
//! f64, so both implementations accept the tie (a ray exactly on an edge may report
//! either triangle, never neither). A WGSL compiler may contract `a·b − c·d` into a fused
//! multiply-add, which breaks the exact negation by one rounding: the GPU's agreement
//! with this function is therefore stated with a tolerance (`tests/rays.rs`).
//!
//! `ray_transform` and `intersect_triangle` have the same names in
//! `shaders/rays/triangle.wgsl`.

use glam::Vec3;

/// The per-ray constants of the test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayTransform {
    /// Axis indices (kx, ky, kz).
    pub axes: [usize; 3],
    /// Shear (S_x, S_y, S_z), dimensionless and 1/(the direction's unit).
    pub shear: Vec3,
}

/// A hit: distance along `dir` (in units of `|dir|`) and the barycentric weights of
/// corners B and C (A's is `1 − b − c`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance.
    pub t: f32,
    /// Weight of corner B.
    pub b: f32,
    /// Weight of corner C.
    pub c: f32,
}

/// The shear frame of direction `dir` (any length, not zero).
pub fn ray_transform(dir: Vec3) -> RayTransform {
    let a = dir.abs();
    let kz = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let mut kx = (kz + 1) % 3;
    let mut ky = (kx + 1) % 3;
    if dir[kz] < 0.0 {
        std::mem::swap(&mut kx, &mut ky);
    }
    let sz = 1.0 / dir[kz];
    RayTransform {
        axes: [kx, ky, kz],
        shear: Vec3::new(dir[kx] * sz, dir[ky] * sz, sz),
    }
}

/// The hit of the ray from `origin` (sheared by `ray`) with triangle (a, b, c), either
/// facing, inside `t_min < t < t_max`.
pub fn intersect_triangle(
    origin: Vec3,
    ray: &RayTransform,
    corners: [Vec3; 3],
    t_min: f32,
    t_max: f32,
) -> Option<TriangleHit> {
    let [kx, ky, kz] = ray.axes;
    let s = ray.shear;
    let [a, b, c] = corners.map(|p| p - origin);
    let ax = a[kx] - s.x * a[kz];
    let ay = a[ky] - s.y * a[kz];
    let bx = b[kx] - s.x * b[kz];
    let by = b[ky] - s.y * b[kz];
    let cx = c[kx] - s.x * c[kz];
    let cy = c[ky] - s.y * c[kz];
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let t_scaled = u * (s.z * a[kz]) + v * (s.z * b[kz]) + w * (s.z * c[kz]);
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    (t > t_min && t < t_max).then_some(TriangleHit {
        t,
        b: v * inv,
        c: w * inv,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(o: Vec3, d: Vec3, tri: [Vec3; 3]) -> Option<TriangleHit> {
        intersect_triangle(o, &ray_transform(d), tri, 0.0, f32::INFINITY)
    }

    #[test]
    fn distance_and_barycentrics() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        for d in [
            -Vec3::Z,
            Vec3::new(0.1, 0.2, -1.0),
            Vec3::new(0.0, 0.0, -2.0),
        ] {
            let o = Vec3::new(0.25, 0.5, 0.0) - d * 3.0;
            let h = hit(o, d, tri).expect("inside");
            let p = o + d * h.t;
            assert!(p.z.abs() < 1e-5);
            assert!((h.b - p.x).abs() < 1e-5 && (h.c - p.y).abs() < 1e-5);
        }
        // Both facings, and a miss outside the edge.
        assert!(hit(Vec3::new(0.25, 0.25, -1.0), Vec3::Z, tri).is_some());
        assert!(hit(Vec3::new(0.75, 0.75, 1.0), -Vec3::Z, tri).is_none());
        // Behind the origin, and beyond t_max.
        assert!(hit(Vec3::new(0.25, 0.25, 1.0), Vec3::Z, tri).is_none());
        let r = ray_transform(-Vec3::Z);
        assert!(intersect_triangle(Vec3::new(0.2, 0.2, 1.0), &r, tri, 0.0, 0.5).is_none());
    }

    #[test]
    fn a_ray_along_the_shared_edge_hits_one_of_the_two() {
        // The diagonal of a unit quad, at points where Möller–Trumbore's rounding can
        // miss both halves: the shared edge's function is exactly 0 for both.
        let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        // Interior points of the diagonal (its ends are the quad's outer corners).
        for k in 1..1000 {
            let s = k as f32 / 1000.0;
            let dir = Vec3::new(0.013, -0.007, -1.0);
            let o = Vec3::new(s, s, 0.0) - dir * 1.7;
            let hits = [hit(o, dir, [a, b, c]), hit(o, dir, [a, c, d])];
            assert!(hits.iter().any(Option::is_some), "ray {k} passed through");
        }
    }

    #[test]
    fn degenerate_triangles_are_missed() {
        let o = Vec3::new(0.0, 0.0, 1.0);
        assert!(hit(o, -Vec3::Z, [Vec3::ZERO; 3]).is_none());
        assert!(hit(o, -Vec3::Z, [Vec3::ZERO, Vec3::X, Vec3::X * 2.0]).is_none());
        assert!(hit(o, -Vec3::Z, [Vec3::NAN, Vec3::X, Vec3::Y]).is_none());
    }
}

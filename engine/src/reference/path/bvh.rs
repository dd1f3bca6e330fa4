//! A bounding volume hierarchy over triangles: binary, split at the centroid median of the
//! longest axis, leaves of at most 4 triangles; closest-hit and any-hit traversal with
//! the Möller–Trumbore ray–triangle test (Möller & Trumbore 1997).

use glam::Vec3;

/// A triangle's corners in world space (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Corners.
    pub p: [Vec3; 3],
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf: first index into `order`; inner: index of the left child (right = left + 1).
    start: u32,
    /// Leaf: triangle count (> 0); inner: 0.
    count: u32,
}

/// The hierarchy. Triangle indices it returns are indices into the slice it was built
/// from.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
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

const LEAF: usize = 4;

impl Bvh {
    /// Builds the hierarchy over `triangles`.
    pub fn build(triangles: Vec<Triangle>) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * triangles.len().max(1)),
            order: (0..triangles.len() as u32).collect(),
            triangles,
        };
        if bvh.triangles.is_empty() {
            return bvh;
        }
        let centroids: Vec<Vec3> = bvh
            .triangles
            .iter()
            .map(|t| (t.p[0] + t.p[1] + t.p[2]) / 3.0)
            .collect();
        bvh.nodes.push(Node {
            lo: Vec3::ZERO,
            hi: Vec3::ZERO,
            start: 0,
            count: bvh.triangles.len() as u32,
        });
        let mut stack = vec![0usize];
        while let Some(index) = stack.pop() {
            let Node { start, count, .. } = bvh.nodes[index];
            let range = start as usize..(start + count) as usize;
            let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            let (mut clo, mut chi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for &i in &bvh.order[range.clone()] {
                let t = bvh.triangles[i as usize];
                for p in t.p {
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
                clo = clo.min(centroids[i as usize]);
                chi = chi.max(centroids[i as usize]);
            }
            bvh.nodes[index].lo = lo;
            bvh.nodes[index].hi = hi;
            let extent = chi - clo;
            if range.len() <= LEAF || extent.max_element() <= 0.0 {
                continue;
            }
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = range.len() / 2;
            bvh.order[range.clone()].select_nth_unstable_by(mid, |a, b| {
                centroids[*a as usize][axis].total_cmp(&centroids[*b as usize][axis])
            });
            let left = bvh.nodes.len();
            bvh.nodes.push(Node {
                lo,
                hi,
                start,
                count: mid as u32,
            });
            bvh.nodes.push(Node {
                lo,
                hi,
                start: start + mid as u32,
                count: count - mid as u32,
            });
            bvh.nodes[index].start = left as u32;
            bvh.nodes[index].count = 0;
            stack.push(left);
            stack.push(left + 1);
        }
        bvh
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
        if self.nodes.is_empty() {
            return None;
        }
        let inv = dir.recip();
        let mut best: Option<Hit> = None;
        let mut t_far = t_max;
        let mut stack = [0u32; 64];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let node = self.nodes[stack[depth] as usize];
            if !slab(origin, inv, node.lo, node.hi, t_min, t_far) {
                continue;
            }
            if node.count > 0 {
                let range = node.start as usize..(node.start + node.count) as usize;
                for &i in &self.order[range] {
                    if let Some((t, u, v)) = intersect(&self.triangles[i as usize], origin, dir)
                        && t > t_min
                        && t < t_far
                    {
                        t_far = t;
                        best = Some(Hit {
                            t,
                            triangle: i,
                            u,
                            v,
                        });
                        if any {
                            return best;
                        }
                    }
                }
            } else if depth + 2 <= stack.len() {
                stack[depth] = node.start;
                stack[depth + 1] = node.start + 1;
                depth += 2;
            }
        }
        best
    }
}

/// Ray–box slab test.
fn slab(origin: Vec3, inv: Vec3, lo: Vec3, hi: Vec3, t_min: f32, t_max: f32) -> bool {
    let a = (lo - origin) * inv;
    let b = (hi - origin) * inv;
    let near = a.min(b).max_element().max(t_min);
    let far = a.max(b).min_element().min(t_max);
    // NaN (a zero direction component on the slab's plane) is not ordered: treat it as
    // a hit.
    near.partial_cmp(&far) != Some(std::cmp::Ordering::Greater)
}

/// Möller–Trumbore: distance and barycentrics of corners 1 and 2, for either facing.
fn intersect(tri: &Triangle, origin: Vec3, dir: Vec3) -> Option<(f32, f32, f32)> {
    let e1 = tri.p[1] - tri.p[0];
    let e2 = tri.p[2] - tri.p[0];
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv_det = 1.0 / det;
    let tv = origin - tri.p[0];
    let u = tv.dot(pv) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = dir.dot(qv) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some((e2.dot(qv) * inv_det, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let brute = tris
                .iter()
                .enumerate()
                .filter_map(|(i, t)| intersect(t, origin, dir).map(|(d, ..)| (d, i)))
                .filter(|(d, _)| *d > 1e-4)
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

// Rays against the scene: the acceleration structure's layout and its traversal, imported
// by every shader that traces (engine/src/rays/, docs/rays.md). The Rust twins are in
// engine/src/rays/: BvhNode, RayTriangle, RayInstance (node.rs, blas.rs, tlas.rs),
// ray_transform and intersect_triangle (watertight.rs), and the walk (node.rs, tlas.rs).
//
// The importer sets the header constant RAYS_GROUP (the bind group of the four arrays
// below) and defines
//     fn ray_hit_counts(inst: RayInstance, primitive: u32, b: f32, c: f32) -> bool
// which decides, for a hit on an instance whose `surface` is not SURFACE_OPAQUE, whether
// the hit stops the ray (alpha mask, stochastic blend); a refused hit is passed through.
//
// Traversal: one loop over both levels, near child first, the far one pushed on a stack
// of RAY_STACK entries: a tree of the builder is at most RAY_MAX_DEPTH deep and near-first
// traversal pushes at most one node per level, so the TLAS and one BLAS together never
// need more. A walk ends after RAY_MAX_STEPS node visits whatever the input (a corrupt
// buffer with a cycle cannot hang the GPU), and `RayHit.overflow` says so.

struct BvhNode {
    lo: vec3<f32>,
    first: u32,
    hi: vec3<f32>,
    count: u32,
}

struct RayTriangle {
    // Corner A; w: the triangle's index in its mesh (bits of a u32).
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
}

struct RayInstance {
    // Rows of the upper 3×4 of object-from-world.
    row0: vec4<f32>,
    row1: vec4<f32>,
    row2: vec4<f32>,
    root: u32,
    instance: u32,
    surface: u32,
    material: u32,
}

const SURFACE_OPAQUE: u32 = 0u;
const SURFACE_MASKED: u32 = 1u;
const SURFACE_BLENDED: u32 = 2u;
const RAY_NO_BLAS: u32 = 0xffffffffu;
const RAY_MAX_DEPTH: u32 = 32u;
const RAY_STACK: u32 = 64u;
const RAY_MAX_STEPS: u32 = 4194304u;
const SLAB_FAR_SCALE: f32 = 1.0000003576;

@group(RAYS_GROUP) @binding(0) var<storage, read> tlas_nodes: array<BvhNode>;
@group(RAYS_GROUP) @binding(1) var<storage, read> ray_instances: array<RayInstance>;
@group(RAYS_GROUP) @binding(2) var<storage, read> blas_nodes: array<BvhNode>;
@group(RAYS_GROUP) @binding(3) var<storage, read> ray_triangles: array<RayTriangle>;

// The shear frame of the watertight test (Woop, Benthin and Wald 2013).
struct RayTransform {
    kx: u32,
    ky: u32,
    kz: u32,
    shear: vec3<f32>,
}

fn ray_transform(dir: vec3<f32>) -> RayTransform {
    let a = abs(dir);
    var kz = 2u;
    if a.x >= a.y && a.x >= a.z {
        kz = 0u;
    } else if a.y >= a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if dir[kz] < 0.0 {
        let k = kx;
        kx = ky;
        ky = k;
    }
    let sz = 1.0 / dir[kz];
    return RayTransform(kx, ky, kz, vec3<f32>(dir[kx] * sz, dir[ky] * sz, sz));
}

// Distance and the weights of corners B and C; hit false for a miss.
struct TriangleHit {
    hit: bool,
    t: f32,
    b: f32,
    c: f32,
}

fn intersect_triangle(
    origin: vec3<f32>,
    ray: RayTransform,
    pa: vec3<f32>,
    pb: vec3<f32>,
    pc: vec3<f32>,
    t_min: f32,
    t_max: f32,
) -> TriangleHit {
    let miss = TriangleHit(false, 0.0, 0.0, 0.0);
    let a = pa - origin;
    let b = pb - origin;
    let c = pc - origin;
    let s = ray.shear;
    let ax = a[ray.kx] - s.x * a[ray.kz];
    let ay = a[ray.ky] - s.y * a[ray.kz];
    let bx = b[ray.kx] - s.x * b[ray.kz];
    let by = b[ray.ky] - s.y * b[ray.kz];
    let cx = c[ray.kx] - s.x * c[ray.kz];
    let cy = c[ray.ky] - s.y * c[ray.kz];
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return miss;
    }
    let det = u + v + w;
    // det == 0: degenerate or edge-on; a NaN or infinite det fails the range test below.
    if det == 0.0 || !(abs(det) <= 3.4e38) {
        return miss;
    }
    let t_scaled = u * (s.z * a[ray.kz]) + v * (s.z * b[ray.kz]) + w * (s.z * c[ray.kz]);
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if !(t > t_min && t < t_max) {
        return miss;
    }
    return TriangleHit(true, t, v * inv, w * inv);
}

// The slab test (Kay and Kajiya 1986): entry and exit distances, clipped to t_min..t_max;
// a miss when x > y. A NaN (0 × ∞ on a slab's plane) counts as a hit, as in node.rs. The
// exit is widened by SLAB_FAR_SCALE = 1 + 2γ₃ (Ize 2013) so that rounding never culls a
// triangle lying in its box's face.
fn ray_slab(origin: vec3<f32>, inv_dir: vec3<f32>, n: BvhNode, t_min: f32, t_max: f32) -> vec2<f32> {
    let a = (n.lo - origin) * inv_dir;
    let b = (n.hi - origin) * inv_dir;
    let lo = min(a, b);
    let hi = max(a, b);
    let far = min(min(hi.x, hi.y), hi.z) * SLAB_FAR_SCALE;
    return vec2<f32>(max(max(max(lo.x, lo.y), lo.z), t_min), min(far, t_max));
}

fn ray_slab_hit(s: vec2<f32>) -> bool {
    return !(s.x > s.y);
}

struct RayHit {
    found: bool,
    // Distance in units of the direction's length (m for a unit direction).
    t: f32,
    // Barycentric weights of corners B and C.
    b: f32,
    c: f32,
    // Index among the frame's instances, and in ray_instances.
    instance: u32,
    slot: u32,
    // The triangle's index in its mesh, and in ray_triangles.
    primitive: u32,
    triangle: u32,
    // True when the walk stopped at RAY_MAX_STEPS or a full stack.
    overflow: bool,
}

fn ray_to_object(inst: RayInstance, v: vec4<f32>) -> vec3<f32> {
    return vec3<f32>(dot(inst.row0, v), dot(inst.row1, v), dot(inst.row2, v));
}

fn ray_node(index: u32, in_blas: bool) -> BvhNode {
    if in_blas {
        return blas_nodes[index];
    }
    return tlas_nodes[index];
}

// The closest hit of the world-space ray origin + t·dir with t_min < t < t_max, or with
// `any`, the first hit found (shadow rays).
fn trace_ray(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32, any: bool) -> RayHit {
    var best = RayHit(false, t_max, 0.0, 0.0, 0u, 0u, 0u, 0u, false);
    var stack: array<u32, RAY_STACK>;
    var sp = 0u;
    var base = 0u;
    var in_blas = false;
    var slot = 0u;
    var o = origin;
    var inv = 1.0 / dir;
    var frame = ray_transform(dir);
    if !ray_slab_hit(ray_slab(o, inv, tlas_nodes[0], t_min, best.t)) {
        return best;
    }
    var node = 0u;
    var steps = 0u;
    loop {
        steps += 1u;
        if steps > RAY_MAX_STEPS {
            best.overflow = true;
            break;
        }
        let n = ray_node(node, in_blas);
        var next = false;
        if n.count > 0u && !in_blas {
            // An instance: enter its BLAS in object space.
            let inst = ray_instances[n.first];
            if inst.root != RAY_NO_BLAS {
                let d = ray_to_object(inst, vec4<f32>(dir, 0.0));
                let ob = ray_to_object(inst, vec4<f32>(origin, 1.0));
                let ib = 1.0 / d;
                if ray_slab_hit(ray_slab(ob, ib, blas_nodes[inst.root], t_min, best.t)) {
                    o = ob;
                    inv = ib;
                    frame = ray_transform(d);
                    in_blas = true;
                    base = sp;
                    slot = n.first;
                    node = inst.root;
                    next = true;
                }
            }
        } else if n.count > 0u {
            let inst = ray_instances[slot];
            for (var k = n.first; k < n.first + n.count; k += 1u) {
                let tri = ray_triangles[k];
                let h = intersect_triangle(o, frame, tri.a.xyz, tri.b.xyz, tri.c.xyz, t_min, best.t);
                let primitive = bitcast<u32>(tri.a.w);
                if h.hit && (inst.surface == SURFACE_OPAQUE || ray_hit_counts(inst, primitive, h.b, h.c)) {
                    best = RayHit(true, h.t, h.b, h.c, inst.instance, slot, primitive, k, false);
                    if any {
                        return best;
                    }
                }
            }
        } else {
            let l = ray_node(n.first, in_blas);
            let r = ray_node(n.first + 1u, in_blas);
            let sl = ray_slab(o, inv, l, t_min, best.t);
            let sr = ray_slab(o, inv, r, t_min, best.t);
            let hl = ray_slab_hit(sl);
            let hr = ray_slab_hit(sr);
            if hl && hr {
                var near = n.first;
                var far = n.first + 1u;
                if sr.x < sl.x {
                    near = n.first + 1u;
                    far = n.first;
                }
                if sp < RAY_STACK {
                    stack[sp] = far;
                    sp += 1u;
                } else {
                    best.overflow = true;
                }
                node = near;
                next = true;
            } else if hl {
                node = n.first;
                next = true;
            } else if hr {
                node = n.first + 1u;
                next = true;
            }
        }
        if next {
            continue;
        }
        if sp == 0u {
            break;
        }
        sp -= 1u;
        node = stack[sp];
        if in_blas && sp < base {
            in_blas = false;
            o = origin;
            inv = 1.0 / dir;
            frame = ray_transform(dir);
        }
    }
    return best;
}

// Traces a batch of rays against the scene's acceleration structure (rays.wgsl) and
// writes each one's hit: the kernel behind `lumen bench --rays` and the traversal's tests
// (engine/src/render/rays/ray_batch.rs).
//
// A masked or blended instance's hit counts where the test pattern
// `ray_pattern_counts` says so (a hit's weight b of corner B below one half), the same
// rule the Rust side gives the CPU traversal, so that a refused hit must be passed
// through identically on both.

#import rays

struct BatchRay {
    // Origin (m) and t_min.
    origin: vec4<f32>,
    // Direction and t_max; the any-hit query when t_max is negative (its magnitude is
    // the limit).
    dir: vec4<f32>,
}

struct BatchHit {
    t: f32,
    b: f32,
    c: f32,
    // Frame instance (0xffffffff: a miss).
    instance: u32,
    primitive: u32,
    // 1: the walk overflowed.
    overflow: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<storage, read> batch_rays: array<BatchRay>;
@group(0) @binding(1) var<storage, read_write> batch_hits: array<BatchHit>;

fn ray_hit_counts(inst: RayInstance, primitive: u32, b: f32, c: f32) -> bool {
    return b < 0.5;
}

@compute @workgroup_size(64)
fn cs_trace(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = id.x + id.y * groups.x * 64u;
    if i >= arrayLength(&batch_rays) {
        return;
    }
    let ray = batch_rays[i];
    let any = ray.dir.w < 0.0;
    let h = trace_ray(ray.origin.xyz, ray.dir.xyz, ray.origin.w, abs(ray.dir.w), any);
    var out = BatchHit(h.t, h.b, h.c, 0xffffffffu, 0u, select(0u, 1u, h.overflow), 0u, 0u);
    if h.found {
        out.instance = h.instance;
        out.primitive = h.primitive;
    }
    batch_hits[i] = out;
}

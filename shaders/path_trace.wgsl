// The GPU path tracer (engine/src/render/rays/path_trace.rs, docs/src/reference.md): one
// path per pixel per dispatch, added to a running sum. The estimator is the CPU path
// tracer's unidirectional one (engine/src/reference/path/integrator.rs, `radiance`
// without light connections) for the materials it supports: the base's diffuse and GGX
// lobes (brdf.wgsl's `surface_brdf_lobes`, the scene's visibility term, the energy
// compensation's table), emission, punctual lights with shadow rays (the sun's disc
// sampled uniformly), a uniform environment or none, next-event estimation combined with
// BSDF sampling by the power heuristic (Veach 1997), Russian roulette from the fourth
// bounce. The Rust side refuses a scene with anything else.

#import common
#import brdf
#import punctual
#import ibl
#import rays

struct PtParams {
    world_from_clip: mat4x4<f32>,
    // Eye position (m); w: the seed.
    eye: vec4<f32>,
    // Uniform environment radiance (pre-exposed, rgb); w: 1 when there is an environment.
    environment: vec4<f32>,
    // What a camera ray that misses shows (rgb); w: 1 when that colour replaces the
    // environment.
    background: vec4<f32>,
    // Width, height, this dispatch's sample index, the most bounces.
    size_sample: vec4<u32>,
    // Light count, visibility model, compensation table size (0: off), unused.
    counts: vec4<u32>,
}

struct PtMaterial {
    // Linear base colour and metallic.
    base_metallic: vec4<f32>,
    // Perceptual roughness, specular level, unlit (1 or 0), unused.
    params: vec4<f32>,
    // Emitted luminance, pre-exposed (rgb).
    emitted: vec4<f32>,
}

struct PtTriangle {
    // Corner normals (world space); n0.w: the material index (bits of a u32).
    n0: vec4<f32>,
    n1: vec4<f32>,
    n2: vec4<f32>,
}

struct PtLight {
    // Directional: unit direction to the light; point and spot: position (m).
    // w: 0 directional, 1 point, 2 spot.
    a: vec4<f32>,
    // Illuminance (lux) or intensity (cd), pre-exposed (rgb); w: 1/range² (1/m²).
    b: vec4<f32>,
    // Spot axis (away from the light); w: the sun's tan(angular radius).
    c: vec4<f32>,
    // Cone scale, cone offset, shadow rays tested (1 or 0), unused.
    d: vec4<f32>,
}

@group(0) @binding(0) var<uniform> pt: PtParams;
@group(0) @binding(1) var<storage, read> pt_materials: array<PtMaterial>;
@group(0) @binding(2) var<storage, read> pt_triangles: array<PtTriangle>;
@group(0) @binding(3) var<storage, read> pt_lights: array<PtLight>;
@group(0) @binding(4) var<storage, read> pt_compensation: array<f32>;
@group(0) @binding(5) var<storage, read_write> pt_sum: array<vec4<f32>>;

// Every surface of a scene the GPU traces stops rays (no masked or blended surface).
fn ray_hit_counts(inst: RayInstance, primitive: u32, b: f32, c: f32) -> bool {
    return true;
}

// PCG (O'Neill 2014) as a hash: state advanced once per draw.
var<private> pt_state: u32;

fn pt_uniform() -> f32 {
    pt_state = pt_state * 747796405u + 2891336453u;
    var w = ((pt_state >> ((pt_state >> 28u) + 4u)) ^ pt_state) * 277803737u;
    w = (w >> 22u) ^ w;
    return f32(w >> 8u) * (1.0 / 16777216.0);
}

// PCG's output permutation as a hash of one word (Jarzynski and Olano 2020).
fn pt_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let w = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (w >> 22u) ^ w;
}

fn pt_pair() -> vec2<f32> {
    let x = pt_uniform();
    return vec2<f32>(x, pt_uniform());
}

// An orthonormal frame whose third column is the unit n (Duff et al. 2017).
fn pt_basis(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(
        vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3<f32>(b, s + n.y * n.y * a, -n.y),
        n,
    );
}

// A cosine-distributed direction about +z (Malley's method on a uniform disc).
fn pt_cosine(xi: vec2<f32>) -> vec3<f32> {
    let r = sqrt(xi.x);
    let phi = 2.0 * PI * xi.y;
    let d = vec2<f32>(r * cos(phi), r * sin(phi));
    return vec3<f32>(d, sqrt(max(1.0 - dot(d, d), 0.0)));
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 > 0.0 {
        return a2 / (a2 + b2);
    }
    return 0.0;
}

fn lobe_probability(lobe: f32, rest: f32) -> f32 {
    if lobe + rest > 0.0 {
        return clamp(lobe / (lobe + rest), 0.1, 0.9);
    }
    return 0.5;
}

fn pt_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// GGX: the isotropic distribution of half vectors h (local, z the normal) and Smith's G1.
fn pt_d_ggx(alpha: f32, h: vec3<f32>) -> f32 {
    let a2 = alpha * alpha;
    let k = h.z * h.z * (a2 - 1.0) + 1.0;
    return a2 / max(PI * k * k, 1e-30);
}

fn pt_g1_ggx(alpha: f32, v: vec3<f32>) -> f32 {
    let a2 = alpha * alpha;
    return 2.0 * v.z / (v.z + sqrt(a2 + (1.0 - a2) * v.z * v.z));
}

// Solid-angle density of reflecting v about a GGX visible normal (Heitz 2018).
fn reflection_pdf(frame: mat3x3<f32>, v: vec3<f32>, l: vec3<f32>, alpha: f32) -> f32 {
    let t = transpose(frame);
    let lv = t * v;
    let ll = t * l;
    if ll.z <= 0.0 || lv.z <= 0.0 {
        return 0.0;
    }
    let h = safe_normalize(lv + ll, vec3<f32>(0.0, 0.0, 1.0));
    return pt_g1_ggx(alpha, lv) * pt_d_ggx(alpha, h) / (4.0 * lv.z);
}

// The energy compensation's albedo table: bilinear at (n·v, perceptual roughness).
fn pt_albedo(n_dot_v: f32, roughness: f32) -> f32 {
    let size = pt.counts.z;
    let scale = f32(size - 1u);
    let x = clamp(n_dot_v, 0.0, 1.0) * scale;
    let y = clamp(roughness, 0.0, 1.0) * scale;
    let x0 = u32(floor(x));
    let y0 = u32(floor(y));
    let x1 = min(x0 + 1u, size - 1u);
    let y1 = min(y0 + 1u, size - 1u);
    let fx = x - f32(x0);
    let fy = y - f32(y0);
    let a = mix(pt_compensation[y0 * size + x0], pt_compensation[y0 * size + x1], fx);
    let b = mix(pt_compensation[y1 * size + x0], pt_compensation[y1 * size + x1], fx);
    return mix(a, b, fy);
}

struct PtBsdf {
    frame: mat3x3<f32>,
    surface: Surface,
    specular_scale: vec3<f32>,
    alpha: f32,
    p_specular: f32,
}

fn pt_bsdf(n: vec3<f32>, v: vec3<f32>, m: PtMaterial) -> PtBsdf {
    let surface = Surface(m.base_metallic.xyz, m.base_metallic.w, m.params.x, m.params.y);
    let f0 = tinted_f0(surface.base_color, surface.metallic, surface.specular_level, vec3<f32>(1.0));
    let spec = pt_luminance(f0);
    let diff = pt_luminance(surface.base_color) * (1.0 - surface.metallic);
    var scale = vec3<f32>(1.0);
    if pt.counts.z > 0u {
        let e = pt_albedo(dot(n, v), surface.perceptual_roughness);
        scale = vec3<f32>(1.0) + f0 * (1.0 / e - 1.0);
    }
    let alpha = surface.perceptual_roughness * surface.perceptual_roughness;
    return PtBsdf(pt_basis(n), surface, scale, alpha, lobe_probability(spec, diff));
}

// f(v, l) · cos θ_l.
fn pt_eval(b: PtBsdf, v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    let n = b.frame[2];
    let n_dot_l = dot(n, l);
    if n_dot_l <= 0.0 {
        return vec3<f32>(0.0);
    }
    let lobes = surface_brdf_lobes(n, v, l, b.surface, pt.counts.y);
    return (lobes.diffuse + lobes.specular * b.specular_scale) * n_dot_l;
}

fn pt_pdf(b: PtBsdf, v: vec3<f32>, l: vec3<f32>) -> f32 {
    let n = b.frame[2];
    let n_dot_l = dot(n, l);
    if dot(n, v) <= 0.0 || !(n_dot_l > 0.0) {
        return 0.0;
    }
    return b.p_specular * reflection_pdf(b.frame, v, l, b.alpha)
        + (1.0 - b.p_specular) * n_dot_l / PI;
}

struct PtSample {
    ok: bool,
    l: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
}

fn pt_sample(b: PtBsdf, v: vec3<f32>) -> PtSample {
    var none = PtSample(false, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    let lv = transpose(b.frame) * v;
    if lv.z <= 0.0 {
        return none;
    }
    var l: vec3<f32>;
    if pt_uniform() < b.p_specular {
        let h = sample_ggx_vndf(lv, b.alpha, pt_pair());
        let ll = 2.0 * dot(lv, h) * h - lv;
        if ll.z <= 0.0 {
            return none;
        }
        l = normalize(b.frame * ll);
    } else {
        l = normalize(b.frame * pt_cosine(pt_pair()));
    }
    let pdf = pt_pdf(b, v, l);
    if !(pdf > 0.0) {
        return none;
    }
    let weight = pt_eval(b, v, l) / pdf;
    if any(weight != weight) {
        return none;
    }
    return PtSample(true, l, weight, pdf);
}

fn pt_occluded(origin: vec3<f32>, l: vec3<f32>, t_max: f32) -> bool {
    return trace_ray(origin, l, 0.0, t_max, true).found;
}

// A direction uniform in the cone within cos_max of the unit axis.
fn pt_cone(axis: vec3<f32>, cos_max: f32, xi: vec2<f32>) -> vec3<f32> {
    let cos_t = 1.0 - xi.x * (1.0 - cos_max);
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let phi = 2.0 * PI * xi.y;
    return pt_basis(axis) * vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), cos_t);
}

// Light from the punctual lights and the environment at p, reflected towards v.
fn pt_direct(p: vec3<f32>, offset: vec3<f32>, v: vec3<f32>, b: PtBsdf) -> vec3<f32> {
    let n = b.frame[2];
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < pt.counts.x; i += 1u) {
        let light = pt_lights[i];
        var l: vec3<f32>;
        var e: vec3<f32>;
        var distance = 3.4e38;
        if light.a.w == 0.0 {
            let axis = safe_normalize(light.a.xyz, vec3<f32>(0.0, 1.0, 0.0));
            let tan_r = light.c.w;
            l = axis;
            if tan_r > 0.0 && tan_r < 3.4e38 {
                l = pt_cone(axis, 1.0 / sqrt(1.0 + tan_r * tan_r), pt_pair());
            }
            e = light.b.xyz;
        } else {
            let to_light = light.a.xyz - p;
            let d2 = dot(to_light, to_light);
            l = safe_normalize(to_light, n);
            distance = sqrt(d2);
            e = light.b.xyz * distance_attenuation(d2, light.b.w);
            if light.a.w == 2.0 {
                e *= spot_attenuation(dot(-l, light.c.xyz), light.d.x, light.d.y);
            }
        }
        if all(e == vec3<f32>(0.0)) || dot(n, l) <= 0.0 {
            continue;
        }
        let f = pt_eval(b, v, l);
        if all(f == vec3<f32>(0.0)) {
            continue;
        }
        if light.d.z > 0.0 && pt_occluded(p + offset, l, distance * (1.0 - 1e-4)) {
            continue;
        }
        sum += f * e;
    }
    if pt.environment.w > 0.0 {
        let l = b.frame * pt_cosine(pt_pair());
        let pdf = max(dot(n, l), 0.0) / PI;
        let f = pt_eval(b, v, l);
        if pdf > 0.0 && any(f != vec3<f32>(0.0)) && !pt_occluded(p + offset, l, 3.4e38) {
            let w = power_heuristic(pdf, pt_pdf(b, v, l));
            sum += f * pt.environment.xyz * (w / pdf);
        }
    }
    return sum;
}

struct PtHit {
    found: bool,
    p: vec3<f32>,
    // Geometric normal turned to the viewer, and the shading normal turned with it.
    facing: vec3<f32>,
    n: vec3<f32>,
    material: PtMaterial,
}

// The closest surface along the ray. The scene is one BLAS in world space under an
// identity instance, so the stored corners are world positions.
fn pt_hit(origin: vec3<f32>, dir: vec3<f32>) -> PtHit {
    var out: PtHit;
    let h = trace_ray(origin, dir, 0.0, 3.4e38, false);
    out.found = h.found;
    if !h.found {
        return out;
    }
    let tri = pt_triangles[h.primitive];
    let w = 1.0 - h.b - h.c;
    let normal = safe_normalize(
        tri.n0.xyz * w + tri.n1.xyz * h.b + tri.n2.xyz * h.c,
        vec3<f32>(0.0, 0.0, 1.0),
    );
    out.p = origin + dir * h.t;
    out.material = pt_materials[bitcast<u32>(tri.n0.w)];
    let corners = ray_triangles[h.triangle];
    let g = safe_normalize(
        cross(corners.b.xyz - corners.a.xyz, corners.c.xyz - corners.a.xyz),
        vec3<f32>(0.0, 0.0, 1.0),
    );
    out.facing = select(g, -g, dot(g, dir) > 0.0);
    out.n = select(normal, -normal, dot(normal, out.facing) < 0.0);
    return out;
}

// Density with which next-event estimation picks l at a surface of normal n: cosine
// about n for a uniform environment, 0 without one.
fn pt_environment_pdf(l: vec3<f32>, n: vec3<f32>) -> f32 {
    if pt.environment.w > 0.0 {
        return max(dot(n, l), 0.0) / PI;
    }
    return 0.0;
}

// One path's pre-exposed radiance along a camera ray.
fn pt_radiance(origin: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    var hit = pt_hit(origin, dir);
    if !hit.found {
        if pt.background.w > 0.0 {
            return pt.background.xyz;
        }
        return pt.environment.xyz * pt.environment.w;
    }
    var throughput = vec3<f32>(1.0);
    var radiance = hit.material.emitted.xyz;
    var v = -dir;
    for (var bounce = 0u; bounce < pt.size_sample.w; bounce += 1u) {
        // An unlit surface's colour was counted on arrival; it scatters nothing.
        if hit.material.params.z > 0.0 {
            break;
        }
        let p = hit.p;
        let offset = hit.facing * (1e-4 * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z))));
        let b = pt_bsdf(hit.n, v, hit.material);
        radiance += throughput * pt_direct(p, offset, v, b);
        let s = pt_sample(b, v);
        if !s.ok || dot(s.l, hit.facing) <= 0.0 {
            break;
        }
        throughput *= s.weight;
        let next = pt_hit(p + offset, s.l);
        if !next.found {
            let w = power_heuristic(s.pdf, pt_environment_pdf(s.l, hit.n));
            radiance += throughput * pt.environment.xyz * pt.environment.w * w;
            break;
        }
        radiance += throughput * next.material.emitted.xyz;
        hit = next;
        v = -s.l;
        if bounce >= 3u {
            let q = min(max(max(throughput.x, throughput.y), throughput.z), 0.95);
            if pt_uniform() >= q {
                break;
            }
            throughput /= q;
        }
    }
    return radiance;
}

@compute @workgroup_size(8, 8)
fn cs_path_trace(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = pt.size_sample.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = id.y * size.x + id.x;
    // A stream per (seed, pixel, sample): the three words hashed in turn.
    pt_state = pt_hash(pt_hash(pt_hash(bitcast<u32>(pt.eye.w)) + pixel) + pt.size_sample.z);
    let jitter = pt_pair();
    let xy = vec2<f32>(f32(id.x), f32(id.y)) + jitter;
    let ndc = vec2<f32>(xy.x / f32(size.x) * 2.0 - 1.0, 1.0 - xy.y / f32(size.y) * 2.0);
    let near = pt.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let dir = normalize(near.xyz / near.w - pt.eye.xyz);
    let l = pt_radiance(pt.eye.xyz, dir);
    var sum = pt_sum[pixel];
    if all(abs(l) <= vec3<f32>(3.4e38)) {
        sum += vec4<f32>(l, 1.0);
    }
    pt_sum[pixel] = sum;
}

// The GPU path tracer (engine/src/render/rays/path_trace.rs, docs/src/reference.md): one
// path per pixel per dispatch, added to a running sum. The estimator is the CPU path
// tracer's unidirectional one (engine/src/reference/path/integrator.rs, `radiance`
// without light connections) for the materials it supports: the base's diffuse and GGX
// lobes (brdf.wgsl's `surface_brdf_lobes`, the scene's visibility term, the energy
// compensation's table) with the base colour, metallic-roughness, emissive and normal
// maps, alpha masks and alpha blending (stochastic), emission, punctual lights with shadow rays (the sun's disc
// sampled uniformly), an image environment (importance-sampled by its table), a uniform
// one or none, next-event estimation combined with
// BSDF sampling by the power heuristic (Veach 1997), Russian roulette from the fourth
// bounce, and the camera's thin lens. The Rust side refuses a scene with anything else.

#import common
#import color
#import brdf
#import punctual
#import ibl
#import rays

struct PtParams {
    world_from_clip: mat4x4<f32>,
    // Eye position (m); w: the seed.
    eye: vec4<f32>,
    // Uniform environment radiance (pre-exposed, rgb); w: 0 no environment, 1 uniform,
    // 2 an image (image, image_size).
    environment: vec4<f32>,
    // What a camera ray that misses shows (rgb); w: 1 when that colour replaces the
    // environment.
    background: vec4<f32>,
    // Width, height, this dispatch's first sample index, the most bounces.
    size_sample: vec4<u32>,
    // Light count, visibility model, compensation table size (0: off), first word of
    // the texture slots in pt_data.
    counts: vec4<u32>,
    // The camera's right vector; w: the thin lens's aperture radius (m; 0: a pinhole).
    lens_right: vec4<f32>,
    // Its up vector; w: the focus distance along the view axis (m; 0: at infinity).
    lens_up: vec4<f32>,
    // Its forward vector.
    forward: vec4<f32>,
    // The image environment in pt_data: first word of its texels (rgb, 3 words each),
    // of its row table, of its column tables; its width.
    image: vec4<u32>,
    // Its height, rotation about +y and total weight (f32 bits), unused.
    image_size: vec4<u32>,
    // Samples per pixel this dispatch adds (from sample size_sample.z on), unused ×3.
    batch: vec4<u32>,
}

struct PtMaterial {
    // Linear base colour and metallic.
    base_metallic: vec4<f32>,
    // Perceptual roughness, specular level, unlit (1 or 0), alpha-blended (1 or 0).
    params: vec4<f32>,
    // Emissive luminance, pre-exposed (rgb).
    emissive: vec4<f32>,
    // Slots (in pt_data's table) of the base colour, metallic-roughness, normal and
    // emissive maps; PT_NO_SLOT: none.
    maps: vec4<u32>,
    // Normal scale, alpha, alpha cutoff (negative: not masked), 1 where the material
    // has maps (its vertex colour and textures apply).
    alpha: vec4<f32>,
}

struct PtTriangle {
    // Corner normals (world space); n0.w: the material index (bits of a u32).
    n0: vec4<f32>,
    n1: vec4<f32>,
    n2: vec4<f32>,
    // Per corner: texture coordinates of sets 0 (xy) and 1 (zw).
    uv0: vec4<f32>,
    uv1: vec4<f32>,
    uv2: vec4<f32>,
    // Per corner: linear vertex colour.
    c0: vec4<f32>,
    c1: vec4<f32>,
    c2: vec4<f32>,
    // Per corner: tangent and handedness.
    t0: vec4<f32>,
    t1: vec4<f32>,
    t2: vec4<f32>,
}

const PT_NO_SLOT: u32 = 0xffffffffu;
const PT_SLOT_WORDS: u32 = 12u;

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
// The compensation table (f32 bits) from word 0, the texture slots from word
// pt.counts.w, then the texels (RGBA8): path_trace.rs's data_words.
@group(0) @binding(4) var<storage, read> pt_data: array<u32>;
@group(0) @binding(5) var<storage, read_write> pt_sum: array<vec4<f32>>;

// Whether a hit on a masked or blended surface stops the ray, as the CPU path tracer's
// `trace` decides: a masked surface where its coverage (alpha × the base colour texel's
// × the vertex colour's, where it has maps) reaches its cutoff, as the G-buffer keeps it;
// a blended one with probability equal to its coverage (stochastic transparency,
// Enderton et al. 2010), drawn from the path's own stream.
fn ray_hit_counts(inst: RayInstance, primitive: u32, b: f32, c: f32) -> bool {
    let tri = pt_triangles[primitive];
    let m = pt_materials[bitcast<u32>(tri.n0.w)];
    let blended = m.params.w > 0.0;
    if m.alpha.z < 0.0 && !blended {
        return true;
    }
    var coverage = m.alpha.y;
    if m.alpha.w > 0.0 {
        let w = 1.0 - b - c;
        let uv = tri.uv0 * w + tri.uv1 * b + tri.uv2 * c;
        let color = tri.c0 * w + tri.c1 * b + tri.c2 * c;
        coverage *= pt_sample_map(m.maps.x, uv).a * color.a;
    }
    if m.alpha.z >= 0.0 && coverage < m.alpha.z {
        return false;
    }
    if blended {
        return pt_uniform() < coverage;
    }
    return true;
}

// Texture coordinates wrapped by mode (0 repeat, 1 mirrored repeat, 2 clamp to edge).
fn pt_wrap(t: f32, mode: u32) -> f32 {
    if mode == 0u {
        return t - floor(t);
    }
    if mode == 1u {
        let m = t - 2.0 * floor(t * 0.5);
        return select(m, 2.0 - m, m > 1.0);
    }
    return clamp(t, 0.0, 1.0);
}

fn pt_wrap_index(i: i32, n: i32, mode: u32) -> i32 {
    if mode == 0u {
        return ((i % n) + n) % n;
    }
    return clamp(i, 0, n - 1);
}

// Texel (x, y) of the slot at word `slot`, decoded to linear.
fn pt_texel(slot: u32, x: i32, y: i32) -> vec4<f32> {
    let w = i32(pt_data[slot + 1u]);
    let h = i32(pt_data[slot + 2u]);
    let i = u32(clamp(y, 0, h - 1) * w + clamp(x, 0, w - 1));
    let t = unpack4x8unorm(pt_data[pt_data[slot] + i]);
    if (pt_data[slot + 3u] & 1u) != 0u {
        return vec4<f32>(srgb_decode(t.x), srgb_decode(t.y), srgb_decode(t.z), t.w);
    }
    return t;
}

// Map `index` at the corner-interpolated coordinates `uv` (set 0 in xy, set 1 in zw),
// as the CPU path tracer samples it (textures.rs): transform, wrap, then nearest or
// bilinear without mip maps; white where there is no map.
fn pt_sample_map(index: u32, uv: vec4<f32>) -> vec4<f32> {
    if index == PT_NO_SLOT {
        return vec4<f32>(1.0);
    }
    let slot = pt.counts.w + index * PT_SLOT_WORDS;
    let flags = pt_data[slot + 3u];
    let p = vec3<f32>(select(uv.xy, uv.zw, (flags & 64u) != 0u), 1.0);
    let r0 = vec3<f32>(bitcast<f32>(pt_data[slot + 4u]), bitcast<f32>(pt_data[slot + 5u]), bitcast<f32>(pt_data[slot + 6u]));
    let r1 = vec3<f32>(bitcast<f32>(pt_data[slot + 7u]), bitcast<f32>(pt_data[slot + 8u]), bitcast<f32>(pt_data[slot + 9u]));
    let wrap_u = (flags >> 2u) & 3u;
    let wrap_v = (flags >> 4u) & 3u;
    let u = pt_wrap(dot(r0, p), wrap_u);
    let v = pt_wrap(dot(r1, p), wrap_v);
    let w = i32(pt_data[slot + 1u]);
    let h = i32(pt_data[slot + 2u]);
    let x = u * f32(w) - 0.5;
    let y = v * f32(h) - 0.5;
    if (flags & 2u) != 0u {
        return pt_texel(slot, i32(floor(x + 0.5)), i32(floor(y + 0.5)));
    }
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let xa = pt_wrap_index(i32(x0), w, wrap_u);
    let xb = pt_wrap_index(i32(x0) + 1, w, wrap_u);
    let ya = pt_wrap_index(i32(y0), h, wrap_v);
    let yb = pt_wrap_index(i32(y0) + 1, h, wrap_v);
    let top = mix(pt_texel(slot, xa, ya), pt_texel(slot, xb, ya), fx);
    let bottom = mix(pt_texel(slot, xa, yb), pt_texel(slot, xb, yb), fx);
    return mix(top, bottom, fy);
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
    let a = mix(bitcast<f32>(pt_data[y0 * size + x0]), bitcast<f32>(pt_data[y0 * size + x1]), fx);
    let b = mix(bitcast<f32>(pt_data[y1 * size + x0]), bitcast<f32>(pt_data[y1 * size + x1]), fx);
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

// The image environment (traced_scene.rs's EnvironmentImage): radiance per texel,
// nearest, and directions drawn in proportion to luminance × sin θ from its row and
// column tables.
fn pt_env_index(dir: vec3<f32>) -> u32 {
    let w = pt.image.w;
    let h = pt.image_size.x;
    let uv = equirect_uv(rotate_y(dir, -bitcast<f32>(pt.image_size.y)));
    let x = min(u32(uv.x * f32(w)), w - 1u);
    let y = min(u32(uv.y * f32(h)), h - 1u);
    return y * w + x;
}

fn pt_env_texel(i: u32) -> vec3<f32> {
    let k = pt.image.x + 3u * i;
    return vec3<f32>(bitcast<f32>(pt_data[k]), bitcast<f32>(pt_data[k + 1u]), bitcast<f32>(pt_data[k + 2u]));
}

// Radiance arriving from direction dir (pre-exposed).
fn pt_env_radiance(dir: vec3<f32>) -> vec3<f32> {
    if pt.environment.w == 2.0 {
        return pt_env_texel(pt_env_index(dir));
    }
    return pt.environment.xyz * pt.environment.w;
}

// Solid-angle density with which next-event estimation picks l at a surface of normal
// n: the image's table, a cosine about n for a uniform environment, 0 without one.
fn pt_environment_pdf(l: vec3<f32>, n: vec3<f32>) -> f32 {
    if pt.environment.w == 2.0 {
        let total = bitcast<f32>(pt.image_size.z);
        if !(total > 0.0) {
            return 0.0;
        }
        let i = pt_env_index(l);
        let w = pt.image.w;
        let h = pt.image_size.x;
        let sin_theta = sin((f32(i / w) + 0.5) / f32(h) * PI);
        let weight = max(dot(pt_env_texel(i), vec3<f32>(0.2126, 0.7152, 0.0722)), 0.0) * sin_theta / total;
        return weight * f32(w * h) / (2.0 * PI * PI * max(sin_theta, 1e-6));
    }
    if pt.environment.w > 0.0 {
        return max(dot(n, l), 0.0) / PI;
    }
    return 0.0;
}

// Index i with cdf[i] <= u < cdf[i + 1] among the count + 1 entries from word `at`.
fn pt_find(at: u32, count: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = count + 1u;
    // The first entry greater than u, by bisection.
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if bitcast<f32>(pt_data[at + mid]) <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return min(max(lo, 1u) - 1u, count - 1u);
}

struct PtEnvSample {
    ok: bool,
    l: vec3<f32>,
    radiance: vec3<f32>,
    pdf: f32,
}

// A next-event direction towards the environment from a surface of normal n.
fn pt_env_sample(n: vec3<f32>) -> PtEnvSample {
    var out = PtEnvSample(false, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    let xi = pt_pair();
    if pt.environment.w == 2.0 {
        if !(bitcast<f32>(pt.image_size.z) > 0.0) {
            return out;
        }
        let w = pt.image.w;
        let h = pt.image_size.x;
        let y = pt_find(pt.image.y, h, xi.y);
        let row = pt.image.z + y * (w + 1u);
        let x = pt_find(row, w, xi.x);
        let c0 = bitcast<f32>(pt_data[row + x]);
        let c1 = bitcast<f32>(pt_data[row + x + 1u]);
        let r0 = bitcast<f32>(pt_data[pt.image.y + y]);
        let r1 = bitcast<f32>(pt_data[pt.image.y + y + 1u]);
        let fx = clamp((xi.x - c0) / max(c1 - c0, 1e-12), 0.0, 1.0);
        let fy = clamp((xi.y - r0) / max(r1 - r0, 1e-12), 0.0, 1.0);
        let uv = vec2<f32>((f32(x) + fx) / f32(w), (f32(y) + fy) / f32(h));
        out.l = rotate_y(equirect_direction(uv), bitcast<f32>(pt.image_size.y));
        out.pdf = pt_environment_pdf(out.l, n);
        out.radiance = pt_env_radiance(out.l);
        out.ok = out.pdf > 0.0;
        return out;
    }
    if pt.environment.w > 0.0 {
        out.l = pt_basis(n) * pt_cosine(xi);
        out.pdf = max(dot(n, out.l), 0.0) / PI;
        out.radiance = pt.environment.xyz;
        out.ok = out.pdf > 0.0;
    }
    return out;
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
    let e = pt_env_sample(n);
    if e.ok {
        let f = pt_eval(b, v, e.l);
        if any(f != vec3<f32>(0.0)) && !pt_occluded(p + offset, e.l, 3.4e38) {
            let w = power_heuristic(e.pdf, pt_pdf(b, v, e.l));
            sum += f * e.radiance * (w / e.pdf);
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
    // The material with its maps applied at the hit, and the light it emits.
    material: PtMaterial,
    emitted: vec3<f32>,
}

// The closest surface along the ray, its maps applied as the CPU path tracer's
// `surface` applies them. The scene is one BLAS in world space under an identity
// instance, so the stored corners are world positions.
fn pt_hit(origin: vec3<f32>, dir: vec3<f32>) -> PtHit {
    var out: PtHit;
    let h = trace_ray(origin, dir, 0.0, 3.4e38, false);
    out.found = h.found;
    if !h.found {
        return out;
    }
    let tri = pt_triangles[h.primitive];
    let w = 1.0 - h.b - h.c;
    var normal = safe_normalize(
        tri.n0.xyz * w + tri.n1.xyz * h.b + tri.n2.xyz * h.c,
        vec3<f32>(0.0, 0.0, 1.0),
    );
    out.p = origin + dir * h.t;
    var m = pt_materials[bitcast<u32>(tri.n0.w)];
    if m.alpha.w > 0.0 {
        let uv = tri.uv0 * w + tri.uv1 * h.b + tri.uv2 * h.c;
        let color = tri.c0 * w + tri.c1 * h.b + tri.c2 * h.c;
        let base = pt_sample_map(m.maps.x, uv) * color;
        m.base_metallic = vec4<f32>(
            clamp(m.base_metallic.xyz * base.xyz, vec3<f32>(0.0), vec3<f32>(1.0)),
            m.base_metallic.w,
        );
        let mr = pt_sample_map(m.maps.y, uv);
        m.params.x = clamp_perceptual_roughness(m.params.x * mr.y);
        m.base_metallic.w = clamp(m.base_metallic.w * mr.z, 0.0, 1.0);
        m.emissive = vec4<f32>(m.emissive.xyz * pt_sample_map(m.maps.w, uv).xyz, 0.0);
        if m.maps.z != PT_NO_SLOT {
            let tangent = tri.t0 * w + tri.t1 * h.b + tri.t2 * h.c;
            normal = normal_from_map(normal, tangent, pt_sample_map(m.maps.z, uv).xyz, m.alpha.x);
        }
    }
    out.material = m;
    // An unlit surface emits its base colour, as the lighting pass shows it.
    out.emitted = select(m.emissive.xyz, m.base_metallic.xyz, m.params.z > 0.0);
    let corners = ray_triangles[h.triangle];
    let g = safe_normalize(
        cross(corners.b.xyz - corners.a.xyz, corners.c.xyz - corners.a.xyz),
        vec3<f32>(0.0, 0.0, 1.0),
    );
    out.facing = select(g, -g, dot(g, dir) > 0.0);
    out.n = select(normal, -normal, dot(normal, out.facing) < 0.0);
    return out;
}

// One path's pre-exposed radiance along a camera ray.
fn pt_radiance(origin: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    var hit = pt_hit(origin, dir);
    if !hit.found {
        if pt.background.w > 0.0 {
            return pt.background.xyz;
        }
        return pt_env_radiance(dir);
    }
    var throughput = vec3<f32>(1.0);
    var radiance = hit.emitted;
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
            radiance += throughput * pt_env_radiance(s.l) * w;
            break;
        }
        radiance += throughput * next.emitted;
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
    var sum = pt_sum[pixel];
    for (var k = 0u; k < pt.batch.x; k += 1u) {
        let l = pt_camera_path(id.xy, pixel, pt.size_sample.z + k);
        if all(abs(l) <= vec3<f32>(3.4e38)) {
            sum += vec4<f32>(l, 1.0);
        }
    }
    pt_sum[pixel] = sum;
}

// Sample `sample` of pixel `xy` (index `pixel`): one path along a jittered camera ray.
fn pt_camera_path(xy_pixel: vec2<u32>, pixel: u32, sample: u32) -> vec3<f32> {
    let size = pt.size_sample.xy;
    // A stream per (seed, pixel, sample): the three words hashed in turn.
    pt_state = pt_hash(pt_hash(pt_hash(bitcast<u32>(pt.eye.w)) + pixel) + sample);
    let jitter = pt_pair();
    let xy = vec2<f32>(f32(xy_pixel.x), f32(xy_pixel.y)) + jitter;
    let ndc = vec2<f32>(xy.x / f32(size.x) * 2.0 - 1.0, 1.0 - xy.y / f32(size.y) * 2.0);
    let near = pt.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    var dir = safe_normalize(near.xyz / near.w - pt.eye.xyz, pt.forward.xyz);
    var eye = pt.eye.xyz;
    // The thin lens, as the CPU's camera_ray: a point on the aperture disc aimed at the
    // point the pinhole ray meets on the plane of focus.
    let lens = pt_pair();
    if pt.lens_right.w > 0.0 {
        let r = sqrt(lens.x) * pt.lens_right.w;
        let phi = 2.0 * PI * lens.y;
        eye = pt.eye.xyz + pt.lens_right.xyz * (r * cos(phi)) + pt.lens_up.xyz * (r * sin(phi));
        if pt.lens_up.w > 0.0 {
            let focus_point = pt.eye.xyz + dir * (pt.lens_up.w / max(dot(dir, pt.forward.xyz), 1e-6));
            dir = safe_normalize(focus_point - eye, dir);
        }
    }
    return pt_radiance(eye, dir);
}

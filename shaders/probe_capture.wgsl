// Reduces one captured cube face of an irradiance probe (the capture's lit HDR and depth)
// into the probe's record: the irradiance E(n) = Σ L(ω) max(0, n·ω) Δω for the normal n of
// each texel of the 6² octahedral irradiance map, each captured pixel weighted by its solid
// angle Δω, and the distance moments of the 8² octahedral map (DDGI, Majercik et al. 2019).
// One workgroup per face; thread t owns moment texel t and, for t < 36, irradiance texel
// t. Face 0 starts the record afresh; faces 1–5 add to it.
#import common
#import bindings
#import encoding
#import irradiance_volume

struct CaptureParams {
    // Probe index, face 0–5, vec4s per record, unused.
    probe_face_stride: vec4<u32>,
    // Largest distance a moment stores (m), unused ×3.
    range: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var hdr: texture_2d<f32>;
@group(0) @binding(2) var depth_buffer: texture_2d<f32>;
@group(0) @binding(3) var<uniform> params: CaptureParams;
@group(0) @binding(4) var<storage, read_write> probes: array<vec4<f32>>;

fn unproject(ndc: vec2<f32>, depth: f32) -> vec3<f32> {
    let h = view.world_from_clip * vec4<f32>(ndc, depth, 1.0);
    return h.xyz / h.w;
}

// One chunk of 64 captured pixels, shared by the workgroup: each thread prepares one
// pixel's direction and solid angle (xyz, w) and radiance and distance (rgb, w), then
// every thread adds all 64 to its own texels. The per-pixel work is done once per face,
// not once per texel.
var<workgroup> chunk_dir: array<vec4<f32>, 64>;
var<workgroup> chunk_light: array<vec4<f32>, 64>;

@compute @workgroup_size(64)
fn cs_reduce(@builtin(local_invocation_index) t: u32) {
    let size = textureDimensions(hdr);
    let pixels = size.x * size.y;
    let origin = view.position_exposure.xyz;
    let exposure = max(view.position_exposure.w, 1e-30);
    let range = params.range.x;
    let texel_dir = oct_texel_direction(vec2<u32>(t % OCT_SIDE, t / OCT_SIDE), OCT_SIDE);
    let normal = oct_texel_direction(vec2<u32>(t % IRRADIANCE_SIDE, t / IRRADIANCE_SIDE), IRRADIANCE_SIDE);
    var moments = vec4<f32>(0.0);
    var irradiance = vec3<f32>(0.0);
    for (var first = 0u; first < pixels; first += 64u) {
        let i = first + t;
        if i < pixels {
            let x = i % size.x;
            let y = i / size.x;
            let ndc = vec2<f32>(
                (f32(x) + 0.5) / f32(size.x) * 2.0 - 1.0,
                1.0 - (f32(y) + 0.5) / f32(size.y) * 2.0,
            );
            let dir = safe_normalize(unproject(ndc, 0.5) - origin, vec3<f32>(0.0, 0.0, -1.0));
            let depth = textureLoad(depth_buffer, vec2<u32>(x, y), 0).r;
            var distance = range;
            if depth > 0.0 {
                distance = min(length(unproject(ndc, depth) - origin), range);
            }
            let radiance = textureLoad(hdr, vec2<u32>(x, y), 0).rgb / exposure;
            chunk_dir[t] = vec4<f32>(dir, cube_texel_solid_angle(ndc, f32(size.x)));
            chunk_light[t] = vec4<f32>(radiance, distance);
        }
        workgroupBarrier();
        let count = min(64u, pixels - first);
        for (var k = 0u; k < count; k++) {
            let dir = chunk_dir[k].xyz;
            let solid_angle = chunk_dir[k].w;
            let light = chunk_light[k];
            if t < IRRADIANCE_TEXELS {
                irradiance += light.rgb * (irradiance_weight(normal, dir) * solid_angle);
            }
            let w = moment_weight(texel_dir, dir) * solid_angle;
            moments += vec4<f32>(w * light.w, w * light.w * light.w, w, 0.0);
        }
        workgroupBarrier();
    }
    let base = params.probe_face_stride.x * params.probe_face_stride.z;
    let fresh = params.probe_face_stride.y == 0u;
    if t < IRRADIANCE_TEXELS {
        probes[base + t] = select(probes[base + t], vec4<f32>(0.0), fresh) + vec4<f32>(irradiance, 0.0);
    }
    let m = base + IRRADIANCE_TEXELS + t;
    probes[m] = select(probes[m], vec4<f32>(0.0), fresh) + moments;
}

// Irradiance from the probe grid for the lighting pass (DDGI's blend, Majercik et al.
// 2019): the eight probes of the shaded point's cell, weighted by trilinear position, the
// back-face weight and Chebyshev visibility from the probes' distance moments
// (irradiance_volume.wgsl). Header constant IRRADIANCE_VOLUME.
#import common
#import encoding
#import ibl
#import irradiance_volume

// The grid (engine/src/render/indirect/irradiance_volume.rs, GpuVolume).
struct VolumeUniform {
    // Corner probe position (m, xyz); 1 once a capture pass has completed (w).
    origin_ready: vec4<f32>,
    // Probe spacing per axis (m, xyz); largest distance a moment stores (m, w).
    spacing_range: vec4<f32>,
    // Probes per axis (xyz); vec4s per probe record (w).
    counts_stride: vec4<u32>,
}

// The lighting pass's group 3 (engine/src/render/lighting.rs, PROBES).
@group(3) @binding(0) var<uniform> volume: VolumeUniform;
@group(3) @binding(1) var<storage, read> volume_probes: array<vec4<f32>>;

// Record layout: 9 SH coefficients of radiance (rgb, physical cd/m²), then OCT_SIDE²
// moment texels (Σw·d, Σw·d², Σw, 0).
const PROBE_SH: u32 = 0u;
const PROBE_MOMENTS: u32 = 9u;

fn probe_sh(base: u32) -> array<vec4<f32>, 9> {
    var sh: array<vec4<f32>, 9>;
    for (var i = 0u; i < 9u; i++) {
        sh[i] = volume_probes[base + PROBE_SH + i];
    }
    return sh;
}

// Mean and mean square of the distances probe `base` saw around direction d, bilinear over
// the moment texels.
fn probe_moments(base: u32, d: vec3<f32>) -> vec2<f32> {
    let c = clamp(oct_texel_coordinate(d) - vec2<f32>(0.5), vec2<f32>(0.0), vec2<f32>(f32(OCT_SIDE) - 1.0));
    let t0 = vec2<u32>(floor(c));
    let t1 = min(t0 + vec2<u32>(1u), vec2<u32>(OCT_SIDE - 1u));
    let f = c - floor(c);
    let at = base + PROBE_MOMENTS;
    let m = mix(
        mix(volume_probes[at + t0.y * OCT_SIDE + t0.x], volume_probes[at + t0.y * OCT_SIDE + t1.x], f.x),
        mix(volume_probes[at + t1.y * OCT_SIDE + t0.x], volume_probes[at + t1.y * OCT_SIDE + t1.x], f.x),
        f.y,
    );
    if !(m.z > 0.0) {
        return vec2<f32>(0.0);
    }
    return m.xy / m.z;
}

// Irradiance (physical lux) at `p` with normal n, seen from direction v.
fn volume_irradiance(p: vec3<f32>, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let spacing = volume.spacing_range.xyz;
    let counts = volume.counts_stride.xyz;
    let stride = volume.counts_stride.w;
    let bias = SELF_SHADOW_BIAS * min(spacing.x, min(spacing.y, spacing.z));
    let biased = p + (n * 0.2 + v * 0.8) * bias;
    let top = vec3<f32>(counts - vec3<u32>(1u));
    let local = clamp((biased - volume.origin_ready.xyz) / spacing, vec3<f32>(0.0), top);
    let base = min(vec3<u32>(floor(local)), counts - vec3<u32>(1u));
    let f = local - vec3<f32>(base);
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < 8u; i++) {
        let corner = vec3<u32>(i & 1u, (i >> 1u) & 1u, (i >> 2u) & 1u);
        let index = min(base + corner, counts - vec3<u32>(1u));
        let trilinear = select(vec3<f32>(1.0) - f, f, corner == vec3<u32>(1u));
        let probe = volume.origin_ready.xyz + vec3<f32>(index) * spacing;
        let record = (index.x + counts.x * (index.y + counts.y * index.z)) * stride;
        var w = backface_weight(safe_normalize(probe - p, n), n);
        let from_probe = biased - probe;
        let distance = length(from_probe);
        let moments = probe_moments(record, safe_normalize(from_probe, n));
        w *= chebyshev_visibility(moments.x, moments.y, distance);
        // DDGI: weights under 0.2 are crushed further, so barely visible probes fade out.
        w = select(w, w * w * w / 0.04, w < 0.2);
        w = max(w, 1e-6) * trilinear.x * trilinear.y * trilinear.z;
        sum += w * sh_irradiance(probe_sh(record), n);
        total += w;
    }
    return sum / max(total, 1e-12);
}

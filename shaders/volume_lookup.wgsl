// Irradiance from the probe grid for the lighting pass (DDGI's blend, Majercik et al.
// 2019): the eight probes of the shaded point's cell, weighted by trilinear position, the
// back-face weight and Chebyshev visibility from the probes' distance moments
// (irradiance_volume.wgsl), each read with one bilinear sample from the atlases that
// probe_bake.wgsl writes. (Nearest moment texels were tried: the lights golden then
// differed between GL and lavapipe by a mean FLIP of 0.0050, five times the bilinear
// read's, as texel boundaries round differently.) Header constant IRRADIANCE_VOLUME.
#import common
#import encoding
#import irradiance_volume

// The grid (engine/src/render/indirect/probe_volume.rs, GpuVolume).
struct VolumeUniform {
    // Corner probe position (m, xyz); 1 once a capture pass has completed (w).
    origin_ready: vec4<f32>,
    // Probe spacing per axis (m, xyz); the exposure the irradiance atlas holds (w).
    spacing_exposure: vec4<f32>,
    // Probes per axis (xyz); probe tiles per atlas row (w).
    counts_tiles: vec4<u32>,
    // 1 / size of the irradiance atlas (xy) and of the moment atlas (zw), in texels.
    texel_sizes: vec4<f32>,
}

// The lighting pass's group 3 (engine/src/render/lighting.rs, PROBES).
@group(3) @binding(0) var<uniform> volume: VolumeUniform;
@group(3) @binding(1) var probe_irradiance: texture_2d<f32>;
@group(3) @binding(2) var probe_moments: texture_2d<f32>;
@group(3) @binding(3) var probe_sampler: sampler;

// The first texel of probe `probe`'s tile of `tile`² texels.
fn tile_origin(probe: u32, tile: u32) -> vec2<f32> {
    let tiles = volume.counts_tiles.w;
    return vec2<f32>(vec2<u32>(probe % tiles, probe / tiles) * tile);
}

// How much the volume's light replaces the environment's at `p` (volume_fade over the
// grid's box: its probes' cells).
fn volume_coverage(p: vec3<f32>) -> f32 {
    let spacing = volume.spacing_exposure.xyz;
    let low = volume.origin_ready.xyz - 0.5 * spacing;
    let high = low + vec3<f32>(volume.counts_tiles.xyz) * spacing;
    return volume_fade(p, low, high, spacing);
}

// volume_irradiance at the frame's `exposure` instead of the atlas's.
fn exposed_volume_irradiance(p: vec3<f32>, n: vec3<f32>, v: vec3<f32>, exposure: f32) -> vec3<f32> {
    return volume_irradiance(p, n, v) * (exposure / volume.spacing_exposure.w);
}

// Irradiance at `p` with normal n, seen from direction v, pre-exposed by the atlas's
// exposure (volume.spacing_exposure.w).
fn volume_irradiance(p: vec3<f32>, n: vec3<f32>, v: vec3<f32>) -> vec3<f32> {
    let spacing = volume.spacing_exposure.xyz;
    let counts = volume.counts_tiles.xyz;
    let bias = SELF_SHADOW_BIAS * min(spacing.x, min(spacing.y, spacing.z));
    let biased = p + (n * 0.2 + v * 0.8) * bias;
    let top = vec3<f32>(counts - vec3<u32>(1u));
    let local = clamp((biased - volume.origin_ready.xyz) / spacing, vec3<f32>(0.0), top);
    let base = min(vec3<u32>(floor(local)), counts - vec3<u32>(1u));
    let f = local - vec3<f32>(base);
    // Every probe's irradiance is read along n: its octahedral position within a tile,
    // once for all eight.
    let along_n = atlas_position(vec2<f32>(0.0), f32(IRRADIANCE_SIDE), n);
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < 8u; i++) {
        let corner = vec3<u32>(i & 1u, (i >> 1u) & 1u, (i >> 2u) & 1u);
        let index = min(base + corner, counts - vec3<u32>(1u));
        let trilinear = select(vec3<f32>(1.0) - f, f, corner == vec3<u32>(1u));
        let position = volume.origin_ready.xyz + vec3<f32>(index) * spacing;
        let probe = index.x + counts.x * (index.y + counts.y * index.z);
        var w = backface_weight(safe_normalize(position - p, n), n);
        let from_probe = biased - position;
        let at = atlas_position(tile_origin(probe, OCT_SIDE + 2u), f32(OCT_SIDE), safe_normalize(from_probe, n));
        let moments = textureSampleLevel(probe_moments, probe_sampler, at * volume.texel_sizes.zw, 0.0).rg;
        w *= chebyshev_visibility(moments.x, moments.y, length(from_probe));
        // DDGI: weights under 0.2 are crushed further, so barely visible probes fade out.
        w = select(w, w * w * w / 0.04, w < 0.2);
        w = max(w, 1e-6) * trilinear.x * trilinear.y * trilinear.z;
        let e = tile_origin(probe, IRRADIANCE_SIDE + 2u) + along_n;
        sum += w * textureSampleLevel(probe_irradiance, probe_sampler, e * volume.texel_sizes.xy, 0.0).rgb;
        total += w;
    }
    return sum / max(total, 1e-12);
}

// Specular light from the reflection probes, for the lighting and reflection passes: up
// to two prefiltered cube maps, each looked up along the reflected direction corrected
// for its box's parallax (reflection_probe.wgsl), blended by their box weights with the
// environment's prefiltered radiance taking what weight is left.
#import common
#import reflection_probe

struct ReflectionProbe {
    // Probe position (m, xyz); width of the fade band inside the box (m, w).
    position_blend: vec4<f32>,
    // Half-size of the box (m, xyz); highest prefiltered mip (w).
    half_extents_mips: vec4<f32>,
    // The exposure the capture was pre-exposed by (x).
    exposure: vec4<f32>,
}

struct ReflectionProbes {
    items: array<ReflectionProbe, 2>,
    // Probes in use (x).
    count: vec4<u32>,
}

// Group 3, after the irradiance volume's bindings (engine/src/render/lighting.rs, PROBES).
@group(3) @binding(4) var<uniform> reflection_probes: ReflectionProbes;
@group(3) @binding(5) var probe_cube_0: texture_cube<f32>;
@group(3) @binding(6) var probe_cube_1: texture_cube<f32>;
@group(3) @binding(7) var probe_cube_sampler: sampler;

// Probe i's prefiltered radiance at p along dir for perceptual roughness r, pre-exposed by
// `exposure`.
fn probe_radiance(i: u32, p: vec3<f32>, dir: vec3<f32>, r: f32, exposure: f32) -> vec3<f32> {
    let probe = reflection_probes.items[i];
    let c = probe.position_blend.xyz;
    let h = probe.half_extents_mips.xyz;
    let d = parallax_corrected(p, dir, c - h, c + h, c);
    let level = r * probe.half_extents_mips.w;
    var radiance: vec3<f32>;
    if i == 0u {
        radiance = textureSampleLevel(probe_cube_0, probe_cube_sampler, d, level).rgb;
    } else {
        radiance = textureSampleLevel(probe_cube_1, probe_cube_sampler, d, level).rgb;
    }
    return radiance * (exposure / max(probe.exposure.x, 1e-30));
}

// The prefiltered radiance at p along dir for perceptual roughness r, pre-exposed by
// `exposure`, with `environment` (pre-exposed too) where no probe's box reaches.
fn probe_reflection(p: vec3<f32>, dir: vec3<f32>, r: f32, environment: vec3<f32>, exposure: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < min(reflection_probes.count.x, 2u); i++) {
        let probe = reflection_probes.items[i];
        let w = box_weight(p, probe.position_blend.xyz, probe.half_extents_mips.xyz, probe.position_blend.w);
        if w > 0.0 {
            sum += w * probe_radiance(i, p, dir, r, exposure);
            total += w;
        }
    }
    return sum / max(total, 1.0) + environment * max(1.0 - total, 0.0);
}

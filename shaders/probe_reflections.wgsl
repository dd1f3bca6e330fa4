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

// Where probe `i` is looked up for the prefiltered radiance at p along dir for perceptual
// roughness r: the direction corrected for its box's parallax (`dir`), the mip (`level`),
// the factor from its capture's exposure to `exposure` (`scale`) and its box weight
// (`weight`).
struct ProbeLookup {
    dir: vec3<f32>,
    level: f32,
    scale: f32,
    weight: f32,
}

fn probe_lookup(i: u32, p: vec3<f32>, dir: vec3<f32>, r: f32, exposure: f32) -> ProbeLookup {
    let probe = reflection_probes.items[i];
    let c = probe.position_blend.xyz;
    let h = probe.half_extents_mips.xyz;
    var out: ProbeLookup;
    out.dir = parallax_corrected(p, dir, c - h, c + h, c);
    out.level = r * probe.half_extents_mips.w;
    out.scale = exposure / max(probe.exposure.x, 1e-30);
    out.weight = box_weight(p, c, h, probe.position_blend.w);
    return out;
}

// A probe's weighted radiance: 0 where its weight is 0, whatever the cube returned.
fn weighted_probe(lookup: ProbeLookup, radiance: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), lookup.weight * radiance * lookup.scale, lookup.weight > 0.0);
}

// The prefiltered radiance at p along dir for perceptual roughness r, pre-exposed by
// `exposure`, with `environment` (pre-exposed too) where no probe's box reaches. Only the
// REFLECTION_PROBE_SLOTS slots in use are looked up: the count is compiled in because a
// SIMD rasterizer such as llvmpipe samples both sides of a branch, and a cube lookup for
// a slot that holds no probe cost 4-5 ms of the lighting pass of `spheres` at 1280×720
// there.
fn probe_reflection(p: vec3<f32>, dir: vec3<f32>, r: f32, environment: vec3<f32>, exposure: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    if REFLECTION_PROBE_SLOTS > 0u {
        let a = probe_lookup(0u, p, dir, r, exposure);
        sum += weighted_probe(a, textureSampleLevel(probe_cube_0, probe_cube_sampler, a.dir, a.level).rgb);
        total += a.weight;
    }
    if REFLECTION_PROBE_SLOTS > 1u {
        let b = probe_lookup(1u, p, dir, r, exposure);
        sum += weighted_probe(b, textureSampleLevel(probe_cube_1, probe_cube_sampler, b.dir, b.level).rgb);
        total += b.weight;
    }
    return sum / max(total, 1.0) + environment * max(1.0 - total, 0.0);
}

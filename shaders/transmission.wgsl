// Light through transmissive surfaces and their volumes (KHR_materials_transmission,
// _volume and _ior); the CPU twin is engine/src/shading/transmission.rs, with the same names.
// The transparent pass samples the opaque frame where the refracted ray leaves a slab of
// the material's thickness, blurred by roughness, and attenuates it by Beer–Lambert.
#import common
#import brdf

// The smallest cosine of the refracted ray against the normal that refraction_path_m
// divides by.
const MIN_COS_REFRACTED: f32 = 0.05;
// Attenuation distances (m) from this one up (and NaN) absorb nothing.
const INFINITE_DISTANCE_M: f32 = 1e30;

// The index of refraction clamped into 1..10; NaN gives 1.5.
fn clamp_ior(ior: f32) -> f32 {
    if !(ior == ior) {
        return 1.5;
    }
    return clamp(ior, 1.0, 10.0);
}

// The unit direction of the ray refracted into a surface of unit normal `n` (facing the
// viewer) seen from the unit direction `v` (towards the viewer), relative index `ior`
// (Snell's law, in Glassner's vector form, 1989).
fn refracted_direction(n: vec3<f32>, v: vec3<f32>, ior: f32) -> vec3<f32> {
    let eta = 1.0 / clamp_ior(ior);
    let cos_i = clamp(dot(n, v), 0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    return safe_normalize(-v * eta + n * (eta * cos_i - cos_t), -n);
}

// The length (m) of the refracted ray's path across a slab of thickness `thickness_m`
// (along n): thickness / cos θt, cos θt ≥ MIN_COS_REFRACTED; 0 when thin-walled.
fn refraction_path_m(n: vec3<f32>, v: vec3<f32>, ior: f32, thickness_m: f32) -> f32 {
    if !(thickness_m > 0.0) {
        return 0.0;
    }
    let cos_t = max(-dot(refracted_direction(n, v, ior), n), MIN_COS_REFRACTED);
    return min(thickness_m, 1e6) / cos_t;
}

// Beer–Lambert: the fraction of light left after `path_m` metres through a volume that
// turns white light into `attenuation_color` over `attenuation_distance_m`, c^(s/d).
fn volume_transmittance(attenuation_color: vec3<f32>, attenuation_distance_m: f32, path_m: f32) -> vec3<f32> {
    if !(path_m > 0.0) || !(attenuation_distance_m < INFINITE_DISTANCE_M) {
        return vec3<f32>(1.0);
    }
    let s = min(min(path_m, INFINITE_DISTANCE_M) / max(attenuation_distance_m, 1e-6), INFINITE_DISTANCE_M);
    let c = clamp(select(vec3<f32>(1.0), attenuation_color, attenuation_color == attenuation_color),
                  vec3<f32>(1e-6), vec3<f32>(1.0));
    return exp2(log2(c) * s);
}

// The indices of refraction of red, green and blue light: `ior` ± (ior − 1)·0.025·
// dispersion, dispersion = 20 / the Abbe number (KHR_materials_dispersion).
fn dispersion_iors(ior: f32, dispersion: f32) -> vec3<f32> {
    let n = clamp_ior(ior);
    var d = 0.0;
    if dispersion == dispersion {
        d = clamp(dispersion, 0.0, 1e3);
    }
    let half = (n - 1.0) * 0.025 * d;
    return vec3<f32>(clamp_ior(n - half), n, clamp_ior(n + half));
}

// The perceptual roughness that blurs the frame seen through a rough surface: its own
// × clamp(2·ior − 2, 0, 1) (Khronos glTF sample renderer, applyIorToRoughness).
fn transmission_roughness(perceptual_roughness: f32, ior: f32) -> f32 {
    let r = clamp_perceptual_roughness(perceptual_roughness);
    return r * clamp(2.0 * clamp_ior(ior) - 2.0, 0.0, 1.0);
}

// The mip level of the frame copy (`width` pixels wide) that such a surface samples.
fn transmission_lod(perceptual_roughness: f32, ior: f32, width: f32) -> f32 {
    return log2(max(width, 1.0)) * transmission_roughness(perceptual_roughness, ior);
}

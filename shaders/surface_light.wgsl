// The light leaving one surface point towards the viewer: the Cook-Torrance BRDF of every
// light that reaches it, plus the indirect light of the environment and the probes. Shared
// by the deferred lighting pass (lighting.wgsl, from the G-buffer) and the transparent pass
// (transparent.wgsl, from the material): both call `surface_light`, so a blended surface
// is lit by the same code as an opaque one. The entry module declares group 0 (`view`)
// and the header constants.
//
// Header constants: HAS_DIRECTIONAL, HAS_POINT, HAS_SPOT (light kinds present in the
// scene; absent kinds compile to nothing), VISIBILITY_MODEL, DIRECTIONAL_SHADOWS,
// POINT_SHADOWS, SPOT_SHADOWS (kinds with shadowed lights), DIRECTIONAL_SHADOWED,
// POINT_SHADOWED, SPOT_SHADOWED (their counts, see shadowed_count), SHADOW_FILTER,
// HAS_ENVIRONMENT and ENV_MAP (image-based lighting from an image or a uniform colour),
// ENERGY_COMPENSATION (multiple-scattering compensation of the specular lobe),
// SCREEN_AO and AO_MULTI_BOUNCE (the AO pass's occlusion on environment light, with the
// multiple-bounce fit), IRRADIANCE_VOLUME (diffuse indirect light from the probe grid,
// volume_lookup.wgsl, in place of the environment's irradiance once a capture pass has
// completed), REFLECTION_PROBE_SLOTS (u32: the reflection probe slots looked up for
// specular indirect light, probe_reflections.wgsl, blended with the environment's; 0
// for none).
//
// Shadowed lights come first within their kind and get their own loop: software
// rasterizers (llvmpipe) run both sides of a branch, so shadow code in a loop over
// unshadowed lights would cost as if every light were shadowed (measured: +53 ms at
// 1280×720 for one unused branch).
//
// SHEEN_LOBE: the surface is a sheen layer (layers.wgsl): every light and the environment
// reflect by the sheen lobe (sheen.wgsl) of colour `surface.base_color` and roughness
// `surface.perceptual_roughness` instead of the Cook-Torrance lobes, its environment
// albedo being the colour × `layer_albedo`, which the layers pass sets.
//
// RELIT_BASE: the surface is a base relit by the layers pass, with what the G-buffer
// cannot hold: its specular lobe is anisotropic GGX (anisotropy.wgsl) along
// `anisotropy_t` with strength `relit_lobe.strength` (0: isotropic, height-correlated
// Smith), its dielectric F0 is tinted by `relit_lobe.tint` (KHR_materials_specular) and
// its Fresnel mixed with an iridescent film's (`relit_lobe.film`,
// KHR_materials_iridescence), which that pass sets: every light reflects by it, the
// environment and the reflection probes are read about its bent normal, and the split
// sum uses the tinted F0, and under a film the F0 whose Schlick Fresnel at n·v is the
// film's (schlick_f0_of). A relit base may also transmit part of its diffuse lobe
// (`translucency`, KHR_materials_diffuse_transmission, diffuse_transmission.wgsl): lights
// behind it shine through, their shadows looked up on the side they reach, and the
// environment's and the probes' irradiance from behind is added in the transmission's
// colour.
//
// SHADOW_MASK_SCALE: 0, or the shadowed directional lights' visibility comes from the
// shadow-mask pass (shadow_mask.wgsl) through ShadingPoint.directional_lit, which the
// lighting pass reads from the mask at that scale (1 or 2 pixels per texel).
//
// HALF_VOLUME: the irradiance volume's irradiance comes from the
// half-resolution volume pass (volume_irradiance.wgsl) through
// ShadingPoint.volume_irradiance, which the lighting pass upsamples (2 pixels per texel).
//
// LIGHT_CULLING: the unshadowed point and spot lights come from this pixel's tile list
// (light_culling.wgsl) instead of the whole range; an overflowed tile loops over the
// whole range in the same loop (no branch).
#import common
#import brdf
#import punctual
#import color
#import ibl
#import bindings
#import lights
#import shadows
#import light_tiles
#import ambient_occlusion
#import volume_lookup
#import probe_reflections
#import sheen
#import anisotropy
#import diffuse_transmission

// Group 2, indirect light: the environment and the AO pass's occlusion (ENVIRONMENT).
@group(2) @binding(0) var<uniform> environment: EnvironmentUniform;
@group(2) @binding(1) var env_cube: texture_cube<f32>;
@group(2) @binding(2) var env_sampler: sampler;
@group(2) @binding(3) var brdf_lut: texture_2d<f32>;
@group(2) @binding(4) var screen_ao: texture_2d<f32>;

fn punctual_at(i: u32) -> PunctualLight {
    if UNIFORM_LIGHTS {
        return uniform_lights.items[min(i, UNIFORM_LIGHT_CAPACITY - 1u)];
    }
    return punctual_of(lights[i]);
}

// The number of lights to loop over for one kind whose unshadowed lights span
// [first, end), and the tile list they come from (`list`: the word after the counts).
struct LightList {
    count: u32,
    list: u32,
    first: u32,
    overflow: bool,
}

fn light_list(tile: u32, which: u32, first: u32, end: u32) -> LightList {
    var out: LightList;
    out.first = first;
    if LIGHT_CULLING {
        let stored = light_tiles[tile + which];
        out.overflow = stored == TILE_OVERFLOW;
        out.count = select(stored, end - first, out.overflow);
        out.list = tile + 2u + which * MAX_TILE_LIGHTS;
    } else {
        out.overflow = true;
        out.count = end - first;
    }
    return out;
}

// Index into `lights` of entry k of a list.
fn list_light(list: LightList, k: u32) -> u32 {
    if LIGHT_CULLING {
        return select(light_tiles[list.list + min(k, MAX_TILE_LIGHTS - 1u)], list.first + k, list.overflow);
    }
    return list.first + k;
}

// The specular lobe's multiple-scattering compensation for this pixel (1 when off).
var<private> specular_energy: vec3<f32> = vec3<f32>(1.0);
// Multiplies every diffuse term: 1 − the diffuse transmission's factor on a relit base
// (set by relight_base), × 1 − transmission on a transmissive surface (set by the
// transparent pass before surface_light), 0 for a layer, 1 everywhere else.
var<private> diffuse_weight: f32 = 1.0;
// With SHEEN_LOBE: the sheen lobe's directional albedo at this pixel (colour 1), set by
// the layers pass before surface_light.
var<private> layer_albedo: f32 = 0.0;
// With RELIT_BASE: the unit anisotropy direction (world, perpendicular to the
// normal) and the relit lobe (the anisotropy's strength, the dielectric F0's tint, the
// film), set by the layers pass before surface_light.
var<private> anisotropy_t: vec3<f32> = vec3<f32>(1.0, 0.0, 0.0);
var<private> relit_lobe: RelitLobe = RelitLobe(0.0, vec3<f32>(1.0), vec3<f32>(0.0));
// A relit base's split-sum (A, B) from the anisotropic table, which the layers pass sets
// for an anisotropic lobe (anisotropic_dfg.wgsl); negative: the isotropic table's.
var<private> relit_dfg: vec2<f32> = vec2<f32>(-1.0);
// With RELIT_BASE: the diffuse transmission (rgb: colour, w: factor, 0: none), set by
// the layers pass; it also sets `diffuse_weight` to 1 − factor.
var<private> translucency: vec4<f32> = vec4<f32>(0.0);

// Radiance leaving the surface towards v for light arriving from l with illuminance
// `illuminance` (already × exposure): f_r · E · (n·l), the specular lobe × the
// pixel's energy compensation. A relit base's light from behind passes through by its
// diffuse transmission.
fn shade(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, surface: Surface, illuminance: vec3<f32>) -> vec3<f32> {
    let n_dot_l = dot(n, l);
    if RELIT_BASE && n_dot_l < 0.0 && translucency.w > 0.0 {
        return diffuse_transmission_lobe(n, v, l, surface, relit_lobe, translucency.w, translucency.rgb)
            * illuminance * -n_dot_l;
    }
    if !(n_dot_l > 0.0) {
        return vec3<f32>(0.0);
    }
    if SHEEN_LOBE {
        let h = safe_normalize(v + l, n);
        return sheen_brdf(surface.base_color, surface.perceptual_roughness, max(dot(n, v), MIN_N_DOT_V),
                          n_dot_l, dot(n, h)) * illuminance * n_dot_l;
    }
    var lobes: BrdfLobes;
    if RELIT_BASE {
        lobes = relit_brdf_lobes(n, v, l, anisotropy_t, surface, relit_lobe);
    } else {
        lobes = surface_brdf_lobes(n, v, l, surface, VISIBILITY_MODEL);
    }
    return (lobes.diffuse * diffuse_weight + lobes.specular * specular_energy) * illuminance * n_dot_l;
}

// The normal a shadow lookup offsets along for a light from l: n, or, for a light behind
// a relit base (diffuse transmission), −n, the side the light reaches.
fn light_side(n: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    if RELIT_BASE {
        return select(n, -n, dot(n, l) < 0.0);
    }
    return n;
}

// Direction towards a point or spot light and the illuminance (× exposure) it gives at
// `world`, before any spot cone: inverse-square law times the range window.
struct Incident {
    l: vec3<f32>,
    illuminance: vec3<f32>,
}

fn punctual_incident(light: PunctualLight, world: vec3<f32>, n: vec3<f32>) -> Incident {
    let to_light = light.position_inv_range2.xyz - world;
    let d2 = dot(to_light, to_light);
    var incident: Incident;
    incident.l = safe_normalize(to_light, n);
    incident.illuminance = light.color_spot_scale.rgb * distance_attenuation(d2, light.position_inv_range2.w);
    return incident;
}

// A surface point as the light loops need it.
struct ShadingPoint {
    // World position (m).
    world: vec3<f32>,
    // Unit normal, facing the viewer.
    n: vec3<f32>,
    // Unit direction towards the viewer.
    v: vec3<f32>,
    // The fragment's position in the target (px, pixel centres at .5).
    frag: vec2<f32>,
    // The material's occlusion of indirect light (0 occluded .. 1 open).
    occlusion: f32,
    // 1 where shadows are received, 0 where not.
    receives: f32,
    // With SHADOW_MASK_SCALE > 0: the visibility (0..1) of shadowed directional lights 0 to
    // 2 from the shadow mask, which already holds `receives`.
    directional_lit: vec3<f32>,
    // With HALF_VOLUME: the irradiance volume's pre-exposed irradiance
    // from the half-resolution volume pass (volume_irradiance.wgsl).
    volume_irradiance: vec3<f32>,
}

// The number of shadowed lights of one kind: the header constant `constant`
// (DIRECTIONAL_SHADOWED, POINT_SHADOWED or SPOT_SHADOWED), or, where it is
// SHADOWED_AT_RUN_TIME, the view's count `run_time`. A constant count unrolls the kind's
// shadowed loop and gives its reads constant indices (lighting.rs,
// UNROLLED_SHADOWED_LIGHTS).
const SHADOWED_AT_RUN_TIME: u32 = 0xffffffffu;
fn shadowed_count(constant: u32, run_time: u32) -> u32 {
    if constant == SHADOWED_AT_RUN_TIME {
        return run_time;
    }
    return constant;
}

// The world position (m) of a forward pass's fragment at `clip` (its @builtin(position):
// pixel centre and depth), as the deferred pass finds it from the depth buffer.
fn fragment_world(clip: vec4<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(clip.x * view.viewport.z * 2.0 - 1.0, 1.0 - clip.y * view.viewport.w * 2.0);
    let world_h = view.world_from_clip * vec4<f32>(ndc, clip.z, 1.0);
    return world_h.xyz / world_h.w;
}

// Pre-exposed radiance (cd/m² × exposure) leaving `p` towards the viewer, emission
// excluded: every light's direct term and the indirect terms.
fn surface_light(p: ShadingPoint, surface: Surface) -> vec3<f32> {
    let n = p.n;
    let v = p.v;
    let world = p.world;
    let pixel = vec2<i32>(p.frag);
    let counts = view.light_counts;
    var color = vec3<f32>(0.0);
    // Split-sum terms shared by energy compensation and image-based lighting.
    let n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    let r = clamp_perceptual_roughness(surface.perceptual_roughness);
    var f0 = compute_f0(surface.base_color, surface.metallic, surface.specular_level);
    if RELIT_BASE {
        f0 = film_f0(tinted_f0(surface.base_color, surface.metallic, surface.specular_level, relit_lobe.tint),
                     n_dot_v, relit_lobe.film);
    }
    var dfg = vec2<f32>(1.0, 0.0);
    if ENERGY_COMPENSATION || HAS_ENVIRONMENT || IRRADIANCE_VOLUME || REFLECTION_PROBE_SLOTS > 0u {
        dfg = textureSampleLevel(brdf_lut, env_sampler, vec2<f32>(n_dot_v, r), 0.0).rg;
        if RELIT_BASE && relit_dfg.x >= 0.0 {
            dfg = relit_dfg;
        }
    }
    if ENERGY_COMPENSATION {
        specular_energy = energy_compensation(f0, dfg);
    }
    if HAS_ENVIRONMENT || IRRADIANCE_VOLUME || REFLECTION_PROBE_SLOTS > 0u {
        // Split sum (Karis 2013): prefiltered radiance × (F0·A + B); diffuse from SH
        // irradiance weighted by what the specular lobe leaves, (1 − E_spec), so a white
        // surface in a uniform environment returns exactly that environment. Inside an
        // irradiance volume whose first capture pass is done, the irradiance comes from
        // its probes (pre-exposed here), which saw the environment and the lit scene.
        // Occlusion of indirect light only: the material's, and the AO pass's where it
        // runs (the smaller of the two, combine_occlusion).
        var ao = p.occlusion;
        var diffuse_ao = vec3<f32>(ao);
        if SCREEN_AO {
            ao = combine_occlusion(ao, textureLoad(screen_ao, pixel, 0).r);
            diffuse_ao = vec3<f32>(ao);
            if AO_MULTI_BOUNCE {
                diffuse_ao = gtao_multi_bounce(ao, surface.base_color);
            }
        }
        var e_spec = (f0 * dfg.x + vec3<f32>(dfg.y)) * specular_energy;
        if SHEEN_LOBE {
            e_spec = surface.base_color * layer_albedo;
        }
        var irradiance = vec3<f32>(0.0);
        // A relit base's irradiance from behind, for its diffuse transmission.
        var back_irradiance = vec3<f32>(0.0);
        var prefiltered = vec3<f32>(0.0);
        // The mirror direction the prefiltered light is read along.
        var reflect_n = n;
        if RELIT_BASE {
            reflect_n = anisotropic_bent_normal(n, v, anisotropy_t, relit_lobe.strength, surface.perceptual_roughness);
        }
        let reflected_world = 2.0 * dot(reflect_n, v) * reflect_n - v;
        if HAS_ENVIRONMENT {
            let rotation = environment.params.y;
            irradiance = sh_irradiance(environment.sh, rotate_y(n, -rotation));
            if RELIT_BASE && translucency.w > 0.0 {
                back_irradiance = sh_irradiance(environment.sh, rotate_y(-n, -rotation));
            }
            prefiltered = environment.uniform_radiance.rgb;
            if ENV_MAP {
                let reflected = rotate_y(reflected_world, -rotation);
                prefiltered = textureSampleLevel(env_cube, env_sampler, reflected, r * environment.params.z).rgb * environment.params.x;
            }
        }
        if REFLECTION_PROBE_SLOTS > 0u {
            prefiltered = probe_reflection(world, reflected_world, r, prefiltered, view.position_exposure.w);
        }
        if IRRADIANCE_VOLUME {
            if volume.origin_ready.w > 0.5 {
                var from_volume = p.volume_irradiance;
                if !HALF_VOLUME {
                    from_volume = exposed_volume_irradiance(world, n, v, view.position_exposure.w);
                }
                // Outside the volume's box its light fades into the environment's.
                let coverage = volume_coverage(world);
                irradiance = mix(irradiance, from_volume, coverage);
                if RELIT_BASE && translucency.w > 0.0 {
                    let back = exposed_volume_irradiance(world, -n, -n, view.position_exposure.w);
                    back_irradiance = mix(back_irradiance, back, coverage);
                }
            }
        }
        // Transmitted from behind: the material's occlusion only (the AO pass sees the
        // front).
        var transmitted = vec3<f32>(0.0);
        if RELIT_BASE {
            transmitted = translucency.w * translucency.rgb * back_irradiance * p.occlusion;
        }
        let diffuse = (vec3<f32>(1.0) - e_spec) * (1.0 - clamp(surface.metallic, 0.0, 1.0))
            * (surface.base_color * irradiance * diffuse_ao * diffuse_weight + transmitted) * fd_lambert();
        color += diffuse + prefiltered * e_spec * specular_occlusion(n_dot_v, ao, r);
    }
    let shadowed = vec3<u32>(
        shadowed_count(DIRECTIONAL_SHADOWED, view.shadowed_counts.x),
        shadowed_count(POINT_SHADOWED, view.shadowed_counts.y),
        shadowed_count(SPOT_SHADOWED, view.shadowed_counts.z),
    );
    let receives = p.receives;
    let view_depth = dot(world - view.position_exposure.xyz, view.forward.xyz);
    var tile = 0u;
    if LIGHT_CULLING {
        tile = tile_base(vec2<u32>(pixel), u32(view.viewport.x));
    }

    if HAS_DIRECTIONAL {
        var first = 0u;
        if DIRECTIONAL_SHADOWS {
            if SHADOW_MASK_SCALE == 0u {
                first = shadowed.x;
                for (var i = 0u; i < shadowed.x; i++) {
                    let light = shadowed_light(i, i);
                    let l = light.direction.xyz;
                    let lit = mix(1.0, directional_shadow(light, world, light_side(n, l), p.frag, view_depth), receives);
                    color += shade(n, v, l, surface, light.color_inv_range2.rgb * lit);
                }
            }
        }
        // With the mask, the shadowed suns join this loop: their visibility is one value
        // of directional_lit (the mask holds at most 3, the first of the kind).
        for (var i = first; i < counts.x; i++) {
            let light = punctual_at(i);
            var lit = 1.0;
            if DIRECTIONAL_SHADOWS && SHADOW_MASK_SCALE > 0u {
                lit = select(1.0, p.directional_lit[min(i, 2u)], i < shadowed.x);
            }
            color += shade(n, v, light.direction_spot_offset.xyz, surface, light.color_spot_scale.rgb * lit);
        }
    }
    if HAS_POINT {
        var first = counts.x;
        if POINT_SHADOWS {
            first = counts.x + shadowed.y;
            for (var i = counts.x; i < first; i++) {
                let light = shadowed_light(i, i - counts.x + shadowed.x);
                let incident = punctual_incident(punctual_of(light), world, n);
                let lit = mix(1.0, point_shadow(light, world, light_side(n, incident.l), incident.l, p.frag), receives);
                color += shade(n, v, incident.l, surface, incident.illuminance * lit);
            }
        }
        let list = light_list(tile, 0u, first, counts.x + counts.y);
        for (var k = 0u; k < list.count; k++) {
            let incident = punctual_incident(punctual_at(list_light(list, k)), world, n);
            color += shade(n, v, incident.l, surface, incident.illuminance);
        }
    }
    if HAS_SPOT {
        let start = counts.x + counts.y;
        var first = start;
        if SPOT_SHADOWS {
            first = start + shadowed.z;
            for (var i = start; i < first; i++) {
                let light = shadowed_light(i, i - start + shadowed.x + shadowed.y);
                let incident = punctual_incident(punctual_of(light), world, n);
                let cone = spot_attenuation(dot(-incident.l, light.direction.xyz), light.spot.x, light.spot.y);
                let lit = mix(1.0, spot_shadow(light, world, light_side(n, incident.l), incident.l, p.frag), receives);
                color += shade(n, v, incident.l, surface, incident.illuminance * (cone * lit));
            }
        }
        let list = light_list(tile, 1u, first, counts.w);
        for (var k = 0u; k < list.count; k++) {
            let light = punctual_at(list_light(list, k));
            let incident = punctual_incident(light, world, n);
            let cone = spot_attenuation(dot(-incident.l, light.direction_spot_offset.xyz), light.color_spot_scale.w, light.direction_spot_offset.w);
            color += shade(n, v, incident.l, surface, incident.illuminance * cone);
        }
    }
    return color;
}

// The lighting pass's group 1, its lights (LIGHTS_AND_SHADOWS in
// engine/src/render/shadow/lookups.rs): bindings 0 to 3 are declared here, the shadow
// bindings, 4 to 8, in shadows.wgsl. Imported by surface_light.wgsl and by the shadow-mask pass
// (shadow_mask.wgsl), which binds the same group. The entry module declares the header
// constants UNIFORM_LIGHTS, UNIFORM_LIGHT_CAPACITY and SHADOWED_LIGHT_CAPACITY.
#import bindings

@group(1) @binding(0) var<storage, read> lights: array<Light>;
@group(1) @binding(3) var<storage, read> light_tiles: array<u32>;

// The first UNIFORM_LIGHT_CAPACITY lights again, compact, in a uniform buffer: the
// unshadowed loops read from here when every light fits (UNIFORM_LIGHTS), because uniform
// loads in the loops cost a third of storage loads on lavapipe. Shadowed lights, few and
// each far costlier, read the full `lights` entry.
struct UniformLights {
    items: array<PunctualLight, UNIFORM_LIGHT_CAPACITY>,
}
@group(1) @binding(1) var<uniform> uniform_lights: UniformLights;

// The shadowed lights again, whole and packed (directional, point, spot): read from here
// when UNIFORM_LIGHTS.
struct ShadowedLights {
    items: array<Light, SHADOWED_LIGHT_CAPACITY>,
}
@group(1) @binding(2) var<uniform> shadowed_lights: ShadowedLights;

// Shadowed light i of `lights`, the `slot`-th shadowed light overall.
fn shadowed_light(i: u32, slot: u32) -> Light {
    if UNIFORM_LIGHTS {
        return shadowed_lights.items[min(slot, SHADOWED_LIGHT_CAPACITY - 1u)];
    }
    return lights[i];
}

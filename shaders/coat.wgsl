// Clearcoat pass (engine/src/render/coat.rs): the coat of a clearcoated opaque surface
// (KHR_materials_clearcoat), drawn over the lit frame after the deferred lighting and SSR
// have lit its base. The same mesh, with the same vertex code as the G-buffer's textured
// variant, is drawn where its own depth is; each fragment is the coat's specular lobe
// (F0 0.04, the coat's roughness, on the mesh's interpolated normal rather than the
// base's normal map), lit by surface_light.wgsl, the deferred pass's own code, as a
// surface without a diffuse lobe. It leaves (factor · L_coat, factor · E_coat), which the
// pipeline composites as dst ← src + dst · (1 − α): the base's light × (1 − factor · E_coat)
// plus the coat's, the layering of clearcoat.wgsl. Header constants: the lighting pass's.
#import common
#import brdf
#import color
#import encoding
#import bindings
#import mesh_vertex
#import material_maps
#import surface_light
#import clearcoat

@group(0) @binding(0) var<uniform> view: View;

@vertex
fn vs_main(in: VertexInput, inst: InstanceInput) -> TexturedOutput {
    return textured_vertex(in, inst);
}

@fragment
fn fs_main(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Texels a masked material drops have no base, so no coat.
    let base = in.base_color * base_color_texel(in.uv0, in.uv1);
    if masked_out(base.a) {
        discard;
    }
    // Back faces reach here only for double-sided materials: lit from the side the
    // viewer sees.
    let n = safe_normalize(in.world_normal * select(-1.0, 1.0, front), vec3<f32>(0.0, 0.0, 1.0));
    let mapped = mapped_material(in.uv0, in.uv1, n, in.world_tangent, in.params, in.emissive_occlusion);
    let world = fragment_world(in.clip);

    var coat: Surface;
    coat.base_color = vec3<f32>(0.0);
    coat.metallic = 0.0;
    coat.specular_level = CLEARCOAT_SPECULAR_LEVEL;
    coat.perceptual_roughness = maps.clearcoat.y;

    var point: ShadingPoint;
    point.world = world;
    point.n = n;
    point.v = safe_normalize(view.position_exposure.xyz - world, n);
    point.frag = in.clip.xy;
    point.occlusion = mapped.occlusion;
    point.receives = select(0.0, 1.0, in.params.w > 0.5);
    let light = surface_light(point, coat);
    // surface_light left the coat lobe's energy compensation in `specular_energy`.
    let n_dot_v = max(dot(n, point.v), MIN_N_DOT_V);
    let r = clamp_perceptual_roughness(coat.perceptual_roughness);
    let dfg = textureSampleLevel(brdf_lut, env_sampler, vec2<f32>(n_dot_v, r), 0.0).rg;
    let factor = maps.clearcoat.x;
    let albedo = clearcoat_albedo(dfg, specular_energy.x);
    return vec4<f32>(light * factor, 1.0 - clearcoat_base_weight(factor, albedo));
}

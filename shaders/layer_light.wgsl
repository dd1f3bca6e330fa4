// The light of a layer over a base (engine/src/render/layers.rs over opaque surfaces,
// engine/src/render/transparent/mod.rs over blended ones): a sheen (KHR_materials_sheen)
// and a clearcoat (KHR_materials_clearcoat), each lit by surface_light.wgsl as a surface
// with only the layer's lobe and no diffuse lobe, on the mesh's interpolated normal (not
// the base's normal map). Each returns the layer's light and w, the fraction of the light
// beneath it that the layer lets through (clearcoat.wgsl, sheen.wgsl): the surface leaves
// L_layer + w · L_beneath. The entry module declares `view`, the maps' group and
// `sheen_table`, and compiles surface_light's lobe for the layer: `sheen_layer` needs
// SHEEN_LOBE on, `coat_layer` SHEEN_LOBE and RELIT_BASE off.
#import common
#import brdf
#import material_maps
#import extension_units
#import surface_light
#import clearcoat
#import sheen
#import sheen_table

// A layer's pre-exposed radiance towards the viewer and what it lets through (0..1) of
// the light beneath it.
struct LayerLight {
    light: vec3<f32>,
    through: f32,
}

// The sheen at `p`: colour × sheenColorTexture, roughness × sheenRoughnessTexture; the
// base keeps 1 − max(colour) · E_sheen(n·v, r).
fn sheen_layer(ext: ExtensionTexels, p: ShadingPoint) -> LayerLight {
    var sheen: Surface;
    let color = maps.sheen.rgb * extension_texel(ext, PROPERTY_SHEEN_COLOR).rgb;
    sheen.base_color = clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
    sheen.metallic = 0.0;
    sheen.specular_level = 0.0;
    sheen.perceptual_roughness = clamp_sheen_roughness(maps.sheen.w * extension_texel(ext, PROPERTY_SHEEN_ROUGHNESS).a);
    let n_dot_v = max(dot(p.n, p.v), MIN_N_DOT_V);
    layer_albedo = sheen_albedo(n_dot_v, sheen.perceptual_roughness);
    diffuse_weight = 0.0;
    let light = surface_light(p, sheen);
    return LayerLight(light, sheen_base_weight(sheen.base_color, layer_albedo));
}

// The coat at `p` (interpolated tangent `tangent`, handedness in w): factor · L_coat; the
// base keeps 1 − factor · E_coat(n·v, r_c). clearcoatNormalTexture bends the coat's
// normal as the base's normal map bends its.
fn coat_layer(ext: ExtensionTexels, p: ShadingPoint, tangent: vec4<f32>) -> LayerLight {
    var point = p;
    if extension_unit(PROPERTY_CLEARCOAT_NORMAL) < EXTENSION_UNITS {
        point.n = normal_from_map(point.n, tangent, extension_texel(ext, PROPERTY_CLEARCOAT_NORMAL).rgb,
                                  maps.extension_params.z);
    }
    var coat: Surface;
    coat.base_color = vec3<f32>(0.0);
    coat.metallic = 0.0;
    coat.specular_level = CLEARCOAT_SPECULAR_LEVEL;
    coat.perceptual_roughness = maps.clearcoat.y * extension_texel(ext, PROPERTY_CLEARCOAT_ROUGHNESS).g;
    diffuse_weight = 0.0;
    let light = surface_light(point, coat);
    // surface_light left the coat lobe's energy compensation in `specular_energy`.
    let n_dot_v = max(dot(point.n, point.v), MIN_N_DOT_V);
    let r = clamp_perceptual_roughness(coat.perceptual_roughness);
    let dfg = textureSampleLevel(brdf_lut, env_sampler, vec2<f32>(n_dot_v, r), 0.0).rg;
    let factor = maps.clearcoat.x * extension_texel(ext, PROPERTY_CLEARCOAT).r;
    let albedo = clearcoat_albedo(dfg, specular_energy.x);
    return LayerLight(light * factor, clearcoat_base_weight(factor, albedo));
}

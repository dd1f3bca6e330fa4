// Layers pass (engine/src/render/layers.rs): the layers of an opaque surface, drawn over
// the lit frame after the deferred lighting and SSR have lit its base: a sheen
// (KHR_materials_sheen, `fs_sheen`, compiled with SHEEN_LOBE) and a clearcoat
// (KHR_materials_clearcoat, `fs_coat`). Before them, a base the G-buffer cannot hold
// (KHR_materials_anisotropy, a tinted KHR_materials_specular, KHR_materials_iridescence,
// KHR_materials_diffuse_transmission;
// `fs_relit`, compiled with RELIT_BASE) is lit again from its material, with its own
// lobe, and replaces the deferred pass's light (alpha 1). The same mesh, with the same vertex code as the
// G-buffer's textured variant, is drawn where its own depth is; each fragment is the
// layer's lobe on the mesh's interpolated normal (not the base's normal map), lit by
// surface_light.wgsl, the deferred pass's own code, as a surface without a diffuse lobe.
// It leaves (L_layer, 1 − w), w being what the layer lets through of the light beneath it
// (clearcoat.wgsl, sheen.wgsl), which the pipeline composites as dst ← src + dst · (1 − α).
// Header constants: the lighting pass's, SHEEN_LOBE, RELIT_BASE.
#import common
#import brdf
#import color
#import encoding
#import bindings
#import mesh_vertex
#import material_maps
#import extension_units
#import surface_light
#import forward_surface
#import clearcoat
#import sheen
#import anisotropy
#import relit_base

@group(0) @binding(0) var<uniform> view: View;

// The sheen lobe's directional albedo E(n·v, r) (engine/src/sheen.rs, `albedo_table`):
// 32 × 32 entries, n·v along a row, packed four to a vec4.
struct SheenTable {
    entries: array<vec4<f32>, 256>,
}
@group(0) @binding(1) var<uniform> sheen_table: SheenTable;

const SHEEN_TABLE_SIZE: u32 = 32u;

fn sheen_table_at(i: u32, j: u32) -> f32 {
    let k = min(j, SHEEN_TABLE_SIZE - 1u) * SHEEN_TABLE_SIZE + min(i, SHEEN_TABLE_SIZE - 1u);
    return sheen_table.entries[k / 4u][k % 4u];
}

// Bilinear lookup of the table at (n·v, r), both clamped to 0..1, NaN: 1
// (engine/src/sheen.rs, `sheen_albedo`).
fn sheen_albedo(n_dot_v: f32, perceptual_roughness: f32) -> f32 {
    let scale = f32(SHEEN_TABLE_SIZE - 1u);
    var nv = clamp(n_dot_v, 0.0, 1.0);
    if !(n_dot_v == n_dot_v) {
        nv = 1.0;
    }
    let x = nv * scale;
    var r = clamp(perceptual_roughness, 0.0, 1.0);
    if !(perceptual_roughness == perceptual_roughness) {
        r = 1.0;
    }
    let y = r * scale;
    let x0 = u32(x);
    let y0 = u32(y);
    let fx = x - f32(x0);
    let fy = y - f32(y0);
    let row0 = mix(sheen_table_at(x0, y0), sheen_table_at(x0 + 1u, y0), fx);
    let row1 = mix(sheen_table_at(x0, y0 + 1u), sheen_table_at(x0 + 1u, y0 + 1u), fx);
    return mix(row0, row1, fy);
}

// The layer's shading point at fragment `in`: on the mesh's interpolated normal, facing
// the viewer, with the material's occlusion; or None (a masked texel: no base, no layer).
struct LayerPoint {
    point: ShadingPoint,
    kept: bool,
}

fn layer_point(in: TexturedOutput, front: bool) -> LayerPoint {
    var out: LayerPoint;
    // Texels a masked material drops have no base, so no layer.
    let base = in.base_color * base_color_texel(in.uv0, in.uv1);
    out.kept = !masked_out(base.a);
    // Back faces reach here only for double-sided materials: lit from the side the
    // viewer sees.
    let n = safe_normalize(in.world_normal * select(-1.0, 1.0, front), vec3<f32>(0.0, 0.0, 1.0));
    let mapped = mapped_material(in.uv0, in.uv1, n, in.world_tangent, in.params, in.emissive_occlusion);
    let world = fragment_world(in.clip);
    out.point.world = world;
    out.point.n = n;
    out.point.v = safe_normalize(view.position_exposure.xyz - world, n);
    out.point.frag = in.clip.xy;
    out.point.occlusion = mapped.occlusion;
    out.point.receives = select(0.0, 1.0, in.params.w > 0.5);
    // No diffuse lobe: a layer only reflects.
    diffuse_weight = 0.0;
    return out;
}

@vertex
fn vs_main(in: VertexInput, inst: InstanceInput) -> TexturedOutput {
    return textured_vertex(in, inst);
}

// A layer's light kept finite in the f16 target, as the lighting pass keeps its own
// (docs/src/formulas.md#numerical-guards): NaN becomes 0.
fn finite_layer(color: vec3<f32>) -> vec3<f32> {
    return min(select(color, vec3<f32>(0.0), color != color), vec3<f32>(HALF_MAX));
}

// The sheen: L_sheen over the base, which keeps 1 − max(colour) · E_sheen(n·v, r).
@fragment
fn fs_sheen(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let ext = extension_texels(in.uv0, in.uv1);
    let lp = layer_point(in, front);
    if !lp.kept {
        discard;
    }
    var sheen: Surface;
    let color = maps.sheen.rgb * extension_texel(ext, PROPERTY_SHEEN_COLOR).rgb;
    sheen.base_color = clamp(color, vec3<f32>(0.0), vec3<f32>(1.0));
    sheen.metallic = 0.0;
    sheen.specular_level = 0.0;
    sheen.perceptual_roughness = clamp_sheen_roughness(maps.sheen.w * extension_texel(ext, PROPERTY_SHEEN_ROUGHNESS).a);
    let n_dot_v = max(dot(lp.point.n, lp.point.v), MIN_N_DOT_V);
    layer_albedo = sheen_albedo(n_dot_v, sheen.perceptual_roughness);
    let light = surface_light(lp.point, sheen);
    return vec4<f32>(finite_layer(light), 1.0 - sheen_base_weight(sheen.base_color, layer_albedo));
}

// The coat: factor · L_coat over the base, which keeps 1 − factor · E_coat(n·v, r_c).
@fragment
fn fs_coat(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let ext = extension_texels(in.uv0, in.uv1);
    var lp = layer_point(in, front);
    if !lp.kept {
        discard;
    }
    // clearcoatNormalTexture bends the coat's normal as the base's normal map bends its.
    if extension_unit(PROPERTY_CLEARCOAT_NORMAL) < EXTENSION_UNITS {
        lp.point.n = normal_from_map(lp.point.n, in.world_tangent,
                                     extension_texel(ext, PROPERTY_CLEARCOAT_NORMAL).rgb, maps.extension_params.z);
    }
    var coat: Surface;
    coat.base_color = vec3<f32>(0.0);
    coat.metallic = 0.0;
    coat.specular_level = CLEARCOAT_SPECULAR_LEVEL;
    coat.perceptual_roughness = maps.clearcoat.y * extension_texel(ext, PROPERTY_CLEARCOAT_ROUGHNESS).g;
    let light = surface_light(lp.point, coat);
    // surface_light left the coat lobe's energy compensation in `specular_energy`.
    let n_dot_v = max(dot(lp.point.n, lp.point.v), MIN_N_DOT_V);
    let r = clamp_perceptual_roughness(coat.perceptual_roughness);
    let dfg = textureSampleLevel(brdf_lut, env_sampler, vec2<f32>(n_dot_v, r), 0.0).rg;
    let factor = maps.clearcoat.x * extension_texel(ext, PROPERTY_CLEARCOAT).r;
    let albedo = clearcoat_albedo(dfg, specular_energy.x);
    return vec4<f32>(finite_layer(light * factor), 1.0 - clearcoat_base_weight(factor, albedo));
}

// A relit base (its lobe from relit_base.wgsl; maps.translucency: the diffuse
// transmission, scaled by its extension textures): the
// whole surface (emission, diffuse and the relit specular lobe, every light and the
// indirect terms) from its material (forward_surface.wgsl), with alpha 1: it replaces
// the deferred pass's light.
@fragment
fn fs_relit(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let ext = extension_texels(in.uv0, in.uv1);
    let fragment = forward_surface(in, front);
    if masked_out(fragment.alpha) {
        discard;
    }
    relight_base(ext, in.world_tangent, front, fragment.point, fragment.surface.perceptual_roughness);
    translucency = vec4<f32>(maps.translucency.rgb * extension_texel(ext, PROPERTY_DIFFUSE_TRANSMISSION_COLOR).rgb,
                             maps.translucency.w * extension_texel(ext, PROPERTY_DIFFUSE_TRANSMISSION).a);
    diffuse_weight = 1.0 - translucency.w;
    var surface = fragment.surface;
    surface.specular_level *= extension_texel(ext, PROPERTY_SPECULAR).a;
    let light = fragment.emissive + surface_light(fragment.point, surface);
    return vec4<f32>(finite_layer(light), 1.0);
}

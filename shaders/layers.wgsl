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
#import layer_light
#import relit_base

@group(0) @binding(0) var<uniform> view: View;
// The sheen lobe's directional albedo table (sheen_table.wgsl).
@group(0) @binding(1) var<uniform> sheen_table: SheenTable;

// The point a layer of fragment `in` is lit at: on the mesh's interpolated normal, facing
// the viewer, with the material's occlusion; `kept` is false where a masked material
// drops the texel (no base, no layer).
struct LayerPoint {
    point: ShadingPoint,
    kept: bool,
}

fn layer_point(in: TexturedOutput, front: bool) -> LayerPoint {
    let fragment = forward_surface(in, front);
    var point = fragment.point;
    point.n = fragment.layer_n;
    return LayerPoint(point, !masked_out(fragment.alpha));
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

// A layer over the lit base: (L_layer, 1 − w), composited as dst ← src + dst · (1 − α).
fn composited(layer: LayerLight) -> vec4<f32> {
    return vec4<f32>(finite_layer(layer.light), 1.0 - layer.through);
}

// The sheen (SHEEN_LOBE).
@fragment
fn fs_sheen(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let lp = layer_point(in, front);
    if !lp.kept {
        discard;
    }
    return composited(sheen_layer(extension_texels(in.uv0, in.uv1), lp.point));
}

// The coat.
@fragment
fn fs_coat(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let lp = layer_point(in, front);
    if !lp.kept {
        discard;
    }
    return composited(coat_layer(extension_texels(in.uv0, in.uv1), lp.point, in.world_tangent));
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
    var surface = fragment.surface;
    surface.specular_level *= extension_texel(ext, PROPERTY_SPECULAR).a;
    let light = fragment.emissive + surface_light(fragment.point, surface);
    return vec4<f32>(finite_layer(light), 1.0);
}

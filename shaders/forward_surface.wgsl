// A forward pass's fragment as the surface_light code lights it: the material from the
// instance and its maps (base colour × texel, metallic, roughness, normal map, occlusion,
// emission), as the G-buffer's textured variant reads them, and the shading point at the
// fragment. Shared by the transparent pass (transparent.wgsl) and the layers pass's
// relit base (layers.wgsl). The entry module declares `view` and the maps' group.
#import common
#import brdf
#import mesh_vertex
#import material_maps
#import surface_light

struct ForwardSurface {
    surface: Surface,
    point: ShadingPoint,
    // The base colour's coverage (factor × vertex colour × texel).
    alpha: f32,
    // Pre-exposed emitted luminance (cd/m² × exposure).
    emissive: vec3<f32>,
    // The mesh's interpolated normal (unit, facing the viewer), without the normal map:
    // the normal a layer over the surface is lit on (layer_light.wgsl).
    layer_n: vec3<f32>,
}

// The surface of fragment `in`; back faces (double-sided materials only) are lit from
// the side the viewer sees.
fn forward_surface(in: TexturedOutput, front: bool) -> ForwardSurface {
    let ng = safe_normalize(in.world_normal * select(-1.0, 1.0, front), vec3<f32>(0.0, 0.0, 1.0));
    let base = in.base_color * base_color_texel(in.uv0, in.uv1);
    let mapped = mapped_material(in.uv0, in.uv1, ng, in.world_tangent, in.params, in.emissive_occlusion);
    var out: ForwardSurface;
    out.surface.base_color = clamp(base.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    out.surface.perceptual_roughness = mapped.roughness;
    out.surface.metallic = mapped.metallic;
    out.surface.specular_level = clamp(in.params.z, 0.0, 1.0);
    let world = fragment_world(in.clip);
    out.point.world = world;
    out.point.n = mapped.n;
    out.point.v = safe_normalize(view.position_exposure.xyz - world, mapped.n);
    out.point.frag = in.clip.xy;
    out.point.occlusion = mapped.occlusion;
    out.point.receives = select(0.0, 1.0, in.params.w > 0.5);
    out.alpha = base.a;
    out.emissive = mapped.emissive;
    out.layer_n = ng;
    return out;
}

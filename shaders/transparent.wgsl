// Transparent pass (engine/src/render/transparent.rs): an alpha-blended primitive over the
// lit frame. Each fragment's material comes from its maps (group 4, MAPS_GROUP) and the
// instance's factors, as in the G-buffer's textured variant; it is lit by
// surface_light.wgsl, the deferred pass's code, and leaves premultiplied: (L·α, α), which
// the pipeline composites with "over", dst ← src + dst·(1 − α) (Porter & Duff 1984).
// `fs_weighted` (--transparency weighted) writes the same premultiplied colour, weighted
// (transparency.wgsl), into the accumulation and revealage targets of weighted blended OIT
// instead. A transmissive fragment (TRANSMISSION, and a transmission factor in its maps)
// covers what is behind it and passes on the opaque frame seen along its refracted ray
// (transmission.wgsl): its diffuse lobe is scaled by 1 − transmission, as glTF mixes
// them. A blended surface with an anisotropy, a specular tint or an iridescent film is
// drawn by a variant compiled with RELIT_BASE, its lobe set by relit_base.wgsl as the
// layers pass sets an opaque one's; one with a diffuse transmission too. A blended or
// transmissive surface with a sheen or a clearcoat is drawn by a variant whose
// over_layers (blended_layers.wgsl) lights them over the base, its transmitted light
// included, in the same fragment. Header constants: those of
// surface_light.wgsl, with SCREEN_AO and LIGHT_CULLING off (the AO pass's occlusion and
// the light tiles belong to the opaque surface behind), TRANSMISSION and RELIT_BASE.
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
#import transparency
#import transmission
#import relit_base
#import sheen_table
#import blended_layers

@group(0) @binding(0) var<uniform> view: View;
// The opaque frame and its mip chain (a 1 × 1 texture without TRANSMISSION).
@group(0) @binding(1) var opaque_frame: texture_2d<f32>;
// Binding 2: the anisotropic lobe's split-sum table (anisotropic_dfg.wgsl).
@group(0) @binding(3) var opaque_sampler: sampler;
// The sheen lobe's directional albedo table (sheen_table.wgsl), for layered surfaces.
@group(0) @binding(4) var<uniform> sheen_table: SheenTable;

@vertex
fn vs_main(in: VertexInput, inst: InstanceInput) -> TexturedOutput {
    return textured_vertex(in, inst);
}

// Pre-exposed radiance a transmissive fragment passes from the opaque frame behind it:
// the frame where the refracted ray leaves a slab of the material's thickness, at the
// mip level of its roughness, × (1 − metallic) × transmission × (1 − max(F)) × the base
// colour (F Schlick's at n·v, tinted and filmed with RELIT_BASE; glTF's fresnel_mix)
// × the volume's Beer–Lambert transmittance over the path (KHR_materials_transmission
// and _volume; one interface, as the Khronos sample renderer).
fn transmitted_light(p: ShadingPoint, surface: Surface) -> vec3<f32> {
    let t = transmission_here;
    let n_dot_v = max(dot(p.n, p.v), MIN_N_DOT_V);
    // What the interface reflects, of its dielectric F0; with RELIT_BASE tinted and under
    // its film (relit_fresnel), the light through it keeping 1 − its largest channel.
    var dielectric = surface;
    dielectric.metallic = 0.0;
    var fresnel = f_schlick(compute_f0(surface.base_color, 0.0, surface.specular_level), n_dot_v);
    if RELIT_BASE {
        fresnel = relit_fresnel(dielectric, relit_lobe, n_dot_v);
    }
    let through = 1.0 - max(fresnel.r, max(fresnel.g, fresnel.b));
    let weight = (1.0 - clamp(surface.metallic, 0.0, 1.0)) * t.x;
    // With dispersion (KHR_materials_dispersion), red, green and blue each refract by
    // their own index and sample the frame where their own ray leaves.
    var behind = seen_through(p, surface, t.y, t.z);
    if maps.attenuation.w > 0.0 {
        let iors = dispersion_iors(t.y, maps.attenuation.w);
        behind = vec3<f32>(seen_through(p, surface, iors.x, t.z).r, behind.g,
                           seen_through(p, surface, iors.z, t.z).b);
    }
    return weight * through * surface.base_color * behind;
}

// The opaque frame seen through a slab of index `ior` and thickness `thickness_m` (world
// m) from `p`, where the refracted ray leaves it, at the mip of the roughness, × the
// volume's transmittance over the path.
fn seen_through(p: ShadingPoint, surface: Surface, ior: f32, thickness_m: f32) -> vec3<f32> {
    let path_m = refraction_path_m(p.n, p.v, ior, thickness_m);
    let exit = p.world + refracted_direction(p.n, p.v, ior) * path_m;
    let clip = view.clip_from_world * vec4<f32>(exit, 1.0);
    let ndc = clip.xy / max(clip.w, 1e-6);
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let lod = transmission_lod(surface.perceptual_roughness, ior, f32(textureDimensions(opaque_frame).x));
    let behind = textureSampleLevel(opaque_frame, opaque_sampler, uv, lod).rgb;
    return volume_transmittance(maps.attenuation.rgb, maps.transmission.w, path_m) * behind;
}

// The fragment's transmission (as `Maps.transmission`: factor, index, thickness in m,
// attenuation distance), the factor × transmissionTexture's red and the thickness ×
// thicknessTexture's green.
var<private> transmission_here: vec4<f32>;

// A blended fragment's premultiplied colour and coverage, and its view depth (m).
struct BlendedFragment {
    color: vec4<f32>,
    depth_m: f32,
}

fn blended_fragment(in: TexturedOutput, front: bool) -> BlendedFragment {
    let ext = extension_texels(in.uv0, in.uv1);
    transmission_here = maps.transmission * vec4<f32>(extension_texel(ext, PROPERTY_TRANSMISSION).r, 1.0,
                                                      extension_texel(ext, PROPERTY_THICKNESS).g, 1.0);
    let fragment = forward_surface(in, front);
    var surface = fragment.surface;
    let point = fragment.point;
    // A blended surface's own lobe: anisotropic, tinted, iridescent or translucent
    // (relit_base.wgsl).
    if RELIT_BASE {
        relight_base(ext, in.world_tangent, front, point, surface.perceptual_roughness);
        surface.specular_level *= extension_texel(ext, PROPERTY_SPECULAR).a;
    }
    let world = point.world;
    // Coverage: the base alpha where blended, else whole.
    var alpha = select(1.0, fragment.alpha, maps.params.w > 0.5);
    var transmitted = vec3<f32>(0.0);
    if TRANSMISSION && maps.transmission.x > 0.0 {
        if masked_out(fragment.alpha) {
            alpha = 0.0;
        }
        // The diffuse share the transmission leaves is split between reflection and a
        // diffuse transmission (relight_base), as glTF mixes them.
        diffuse_weight *= 1.0 - transmission_here.x;
        translucency.w *= 1.0 - transmission_here.x;
        transmitted = transmitted_light(point, surface);
    }
    // An unlit surface (KHR_materials_unlit) shows its base colour as it is, pre-exposed.
    // A sheen and a clearcoat lie over the rest (blended_layers.wgsl).
    let layered = over_layers(ext, in, point, fragment.layer_n, fragment.emissive + surface_light(point, surface) + transmitted);
    let lit = select(layered, surface.base_color, is_unlit(in.params.z));
    let color = premultiplied(lit, alpha);
    return BlendedFragment(color, dot(world - view.position_exposure.xyz, view.forward.xyz));
}

@fragment
fn fs_main(in: TexturedOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return blended_fragment(in, front).color;
}

// The sums of weighted blended OIT: Σ w·(Lα, α) and, through the blend state, Π(1 − α).
struct WeightedOutput {
    @location(0) accum: vec4<f32>,
    @location(1) reveal: vec4<f32>,
}

@fragment
fn fs_weighted(in: TexturedOutput, @builtin(front_facing) front: bool) -> WeightedOutput {
    let f = blended_fragment(in, front);
    let w = oit_weight(f.depth_m, f.color.a);
    // Kept finite in the f16 accumulation.
    return WeightedOutput(min(f.color * w, vec4<f32>(HALF_MAX)), vec4<f32>(f.color.a));
}

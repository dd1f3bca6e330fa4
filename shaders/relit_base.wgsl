// A relit base's lobe from its material (engine/src/render/layers.rs and
// engine/src/render/transparent/mod.rs): what surface_light.wgsl reads with RELIT_BASE,
// set from the material maps (maps.anisotropy: strength, cos and sin of the direction's
// angle; maps.specular_tint: the dielectric F0's tint; maps.film: the iridescent film;
// maps.translucency: the diffuse transmission),
// each scaled by its extension texture (anisotropyTexture also turns the direction;
// iridescenceThicknessTexture picks the film's thickness). Shared by the layers pass's
// relit base (an opaque surface) and the transparent pass (a blended one). The entry
// module declares `view` and the maps' group.
#import common
#import brdf
#import material_maps
#import surface_light
#import anisotropy
#import iridescence
#import anisotropic_dfg

// Sets anisotropy_t, relit_lobe, relit_dfg, translucency and diffuse_weight for the fragment at `point` whose
// interpolated tangent is `tangent` (handedness in w), on a front or back face, of
// perceptual roughness `perceptual_roughness`, with the extension texels `ext`.
fn relight_base(ext: ExtensionTexels, tangent: vec4<f32>, front: bool, point: ShadingPoint, perceptual_roughness: f32) {
    var anisotropy = vec3<f32>(maps.anisotropy.x, maps.anisotropy.yz);
    if extension_unit(PROPERTY_ANISOTROPY) < EXTENSION_UNITS {
        anisotropy = textured_anisotropy(maps.anisotropy.x, maps.anisotropy.yz,
                                         extension_texel(ext, PROPERTY_ANISOTROPY).rgb);
    }
    var film = maps.film.xyz;
    film.x *= extension_texel(ext, PROPERTY_IRIDESCENCE).r;
    if extension_unit(PROPERTY_IRIDESCENCE_THICKNESS) < EXTENSION_UNITS {
        film.z = film_thickness(maps.extension_params.x, maps.film.z,
                                extension_texel(ext, PROPERTY_IRIDESCENCE_THICKNESS).g);
    }
    // On a back face the normal is turned, so the handedness turns too: the grain is the
    // front's.
    let handedness = tangent.w * select(-1.0, 1.0, front);
    anisotropy_t = anisotropy_direction(point.n, tangent.xyz, handedness, anisotropy.yz);
    // An anisotropic material's split sum and energy compensation read its own table
    // (also where its texture takes the strength to 0: the lobe keeps its Smith term).
    if maps.anisotropy.x > 0.0 {
        relit_dfg = anisotropic_dfg(max(dot(point.n, point.v), MIN_N_DOT_V),
                                    view_azimuth(anisotropy_t, cross(point.n, anisotropy_t), point.v),
                                    clamp_perceptual_roughness(perceptual_roughness), anisotropy.x);
    }
    relit_lobe = RelitLobe(anisotropy.x, maps.specular_tint.rgb * extension_texel(ext, PROPERTY_SPECULAR_COLOR).rgb, film);
    // The diffuse lobe's transmitted share, scaled by its textures.
    translucency = vec4<f32>(maps.translucency.rgb * extension_texel(ext, PROPERTY_DIFFUSE_TRANSMISSION_COLOR).rgb,
                             maps.translucency.w * extension_texel(ext, PROPERTY_DIFFUSE_TRANSMISSION).a);
    diffuse_weight = 1.0 - translucency.w;
}

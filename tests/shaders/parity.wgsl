// Evaluates every shared shader function on the inputs of one case; the test
// tests/shader_parity.rs evaluates the Rust twins on the same inputs and compares.
#import common
#import brdf
#import punctual
#import color
#import encoding
#import ibl
#import camera
#import ambient_occlusion
#import irradiance_volume
#import reflection_probe
#import antialiasing
#import shadow_kernel
#import transparency
#import transmission
#import skinning
#import clearcoat
#import sheen
#import anisotropy
#import iridescence
#import diffuse_transmission

struct Case {
    n: vec4<f32>,
    v: vec4<f32>,
    l: vec4<f32>,
    // Base colour (rgb), metallic (w).
    base_metallic: vec4<f32>,
    // Perceptual roughness, specular level, visibility model, x.
    params: vec4<f32>,
    // α, n·h, |n × h|², k.
    scalars: vec4<f32>,
}

const OUTPUTS: u32 = 68u;

@group(0) @binding(0) var<storage, read> cases: array<Case>;
@group(0) @binding(1) var<storage, read_write> results: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let c = cases[i];
    let alpha = c.scalars.x;
    let n_dot_h = c.scalars.y;
    let nxh2 = c.scalars.z;
    let k = c.scalars.w;
    let r = c.params.x;
    let spec = c.params.y;
    let model = u32(c.params.z);
    let x = c.params.w;
    var s: Surface;
    s.base_color = c.base_metallic.rgb;
    s.metallic = c.base_metallic.w;
    s.perceptual_roughness = r;
    s.specular_level = spec;
    let o = i * OUTPUTS;
    results[o + 0u] = vec4<f32>(d_ggx(alpha, n_dot_h, nxh2), g1_schlick_ggx(n_dot_h, k),
                                v_schlick_ggx(n_dot_h, x, k), v_smith_ggx_correlated(n_dot_h, x, alpha));
    results[o + 1u] = vec4<f32>(v_smith_ggx_correlated_fast(n_dot_h, x, alpha), k_direct(r), k_ibl(r),
                                pow5_one_minus(x));
    results[o + 2u] = vec4<f32>(f_schlick(c.base_metallic.rgb, x), fd_lambert());
    results[o + 3u] = vec4<f32>(surface_brdf(c.n.xyz, c.v.xyz, c.l.xyz, s, model),
                                visibility(model, n_dot_h, x, r));
    results[o + 4u] = vec4<f32>(compute_f0(c.base_metallic.rgb, c.base_metallic.w, spec), dielectric_f0(spec));
    results[o + 5u] = vec4<f32>(inverse_square(x * 10.0), range_window(n_dot_h * 10.0, k),
                                distance_attenuation(x * 10.0, k), spot_attenuation(x, alpha * 10.0, -k));
    let e = oct_encode(c.n.xyz);
    results[o + 6u] = vec4<f32>(e, clamp_perceptual_roughness(r), perceptual_roughness_to_alpha(r));
    results[o + 7u] = vec4<f32>(oct_decode(e), luminance(c.base_metallic.rgb));
    results[o + 8u] = vec4<f32>(tonemap_reinhard(c.base_metallic.rgb * 4.0), srgb_encode(x));
    results[o + 9u] = vec4<f32>(tonemap_aces_fitted(c.base_metallic.rgb * 4.0), srgb_decode(x));
    results[o + 10u] = vec4<f32>(tonemap_none(c.base_metallic.rgb * 2.0 - vec3<f32>(0.5)), g_smith_schlick_ggx(n_dot_h, x, k));
    results[o + 11u] = vec4<f32>(safe_normalize(c.v.xyz * x, vec3<f32>(0.0, 1.0, 0.0)), 0.0);
    let packed = pack_occlusion_receiver(x, c.base_metallic.w);
    let stored = round(packed * 255.0) / 255.0;
    results[o + 12u] = vec4<f32>(packed, unpack_receives_shadows(stored), unpack_occlusion(stored),
                                 stored_specular_level(x * 2.5 - 1.0));
    results[o + 13u] = vec4<f32>(equirect_uv(c.v.xyz), rotate_y(c.l.xyz, x * 6.0).xz);
    var sh: array<vec4<f32>, 9>;
    for (var k = 0u; k < 9u; k++) {
        sh[k] = vec4<f32>(c.base_metallic.xyz * (f32(k) * 0.3 + 0.1) - vec3<f32>(0.05 * f32(k)), 0.0);
    }
    results[o + 14u] = vec4<f32>(sh_irradiance(sh, c.n.xyz), radical_inverse(i));
    let dfg = dfg_integrate(n_dot_h, r, 32u);
    results[o + 15u] = vec4<f32>(dfg, energy_compensation(c.base_metallic.xyz, dfg).x, specular_occlusion(n_dot_h, x, r));
    results[o + 16u] = vec4<f32>(importance_sample_ggx(hammersley(i % 64u, 64u), alpha), 0.0);
    results[o + 17u] = vec4<f32>(tonemap_agx(c.base_metallic.rgb * 4.0),
                                 circle_of_confusion(x * 20.0, coc_focus(i), 0.05, k * 0.05));
    results[o + 18u] = vec4<f32>(tonemap_pbr_neutral(c.base_metallic.rgb * 4.0), vignetting(x * 3.0, n_dot_h));
    let projected = gtao_projected_normal(c.n.xyz, c.v.xyz, c.l.xyz);
    results[o + 19u] = vec4<f32>(projected, gtao_open_horizons(x * 3.0 - 1.5));
    results[o + 20u] = vec4<f32>(gtao_slice(projected, vec2<f32>(2.0 * x - 1.0, 2.0 * n_dot_h - 1.0)),
                                 gtao_slice_visibility(-1.5 * x, 1.5 * n_dot_h, 2.0 * k - 1.0),
                                 ao_falloff(2.0 * x, n_dot_h + 0.1), combine_occlusion(x, n_dot_h));
    results[o + 21u] = vec4<f32>(gtao_multi_bounce(x, c.base_metallic.rgb), 0.0);
    // The view direction in the local frame, above the surface.
    let local_v = vec3<f32>(c.v.xy, abs(c.v.z) + 1e-3);
    results[o + 22u] = vec4<f32>(sample_ggx_vndf(normalize(local_v), alpha, hammersley(i % 64u, 64u)), 0.0);
    results[o + 23u] = vec4<f32>(backface_weight(c.v.xyz, c.n.xyz),
                                 chebyshev_visibility(x * 2.0, x * x * 4.0 + k * 0.1, n_dot_h * 4.0),
                                 cube_texel_solid_angle(vec2<f32>(2.0 * x - 1.0, 2.0 * n_dot_h - 1.0), 16.0),
                                 moment_weight(c.n.xyz, c.l.xyz));
    var basis = sh_basis(c.n.xyz);
    results[o + 24u] = vec4<f32>(oct_texel_direction(vec2<u32>(i % 8u, (i / 8u) % 8u), 6u + i % 3u), basis[8]);
    results[o + 26u] = vec4<f32>(parallax_corrected(c.v.xyz * 2.0, c.l.xyz, vec3<f32>(-3.0, -2.5, -4.0), vec3<f32>(3.5, 2.0, 3.0), c.n.xyz),
                                 box_weight(c.v.xyz * 3.0, c.n.xyz, vec3<f32>(2.5, 2.0, 3.0), k));
    results[o + 27u] = vec4<f32>(specular_aa_roughness(r, x * x * 4.0, 1.0, 0.3, 0.2),
                                 specular_aa_roughness(r, x * x * 4.0, 0.5 + 0.5 * n_dot_h, 0.159, k),
                                 toksvig_variance(0.5 + 0.5 * x),
                                 specular_aa_roughness(r, 0.0, 1.0, 0.3, 0.2));
    results[o + 28u] = running_mean(vec4<f32>(c.base_metallic.rgb, x), vec4<f32>(c.n.xyz, k) * 3.0,
                                    select(n_dot_h, 1.0, i % 4u == 0u));
    let compressed = compress_hdr(c.base_metallic.rgb * (x * 40.0));
    results[o + 29u] = vec4<f32>(compressed, perceptual_luma(compressed));
    results[o + 30u] = vec4<f32>(expand_hdr(compressed), 0.0);
    let y = rgb_to_ycocg(c.base_metallic.rgb);
    results[o + 31u] = vec4<f32>(ycocg_to_rgb(y * vec3<f32>(1.0, 0.5, 2.0)), y.y);
    results[o + 32u] = vec4<f32>(clip_towards_mean(c.v.xyz, c.base_metallic.rgb * 0.2, vec3<f32>(0.1, 0.2, 0.3) * (k + 0.01)), 0.0);
    let column = floor(x * 8.0);
    let ends = smaa_ends(i);
    results[o + 33u] = vec4<f32>(smaa_coverage(column, column + 1.0 + floor(n_dot_h * 8.0), ends, vec2<f32>(k * 8.0, r * 8.0)),
                                 line_coverage(x * 3.0, vec2<f32>(0.4 * k, c.v.x), vec2<f32>(4.0, c.v.y)));
    results[o + 34u] = vec4<f32>(smaa_edge(x, n_dot_h, 0.1), ends, 0.0);
    let lo = c.base_metallic.rgb * 0.5;
    let cas = cas_weight(lo, c.base_metallic.rgb, k);
    results[o + 35u] = vec4<f32>(cas_apply(c.base_metallic.rgb * 0.8, lo * 4.0, cas, abs(x) + 0.1), cas.y);
    let tent_s = fract(abs(x) * 3.7);
    let tent_w = shadow_tent_weights(tent_s);
    let tent_o = shadow_tent_offsets(tent_s);
    results[o + 36u] = vec4<f32>(tent_w.x, tent_w.z, tent_o.x, tent_o.z + tent_o.y);
    results[o + 37u] = premultiplied(c.base_metallic.rgb * (k * 1e5), x);
    results[o + 38u] = vec4<f32>(blended_shadow_threshold(vec2<u32>(i, i / 7u)), f32(bayer2(i & 1u, (i >> 1u) & 1u)),
                                 shadow_mask_weight(k, 8.0 + x, 8.0 + n_dot_h), shadow_mask_weight(r, -1.0, 0.5 + x * 20.0));
    results[o + 39u] = vec4<f32>(oit_weight(x * 400.0 - 5.0, k), oit_weight(r * 3.0, 1.0), 0.0, 0.0);
    results[o + 40u] = oit_resolve(vec4<f32>(c.base_metallic.rgb * 50.0, k * 100.0), x);
    results[o + 41u] = vec4<f32>(refracted_direction(c.n.xyz, c.v.xyz, 1.0 + x * 3.0),
                                 refraction_path_m(c.n.xyz, c.v.xyz, 1.0 + x * 3.0, r * 0.5));
    results[o + 42u] = vec4<f32>(volume_transmittance(c.base_metallic.rgb, x * 3.0, k * 2.0),
                                 transmission_lod(r, 1.0 + x, 256.0));
    results[o + 43u] = vec4<f32>(dispersion_iors(1.0 + x * 3.0, r * 30.0), 0.0);
    let ja = mat4x4<f32>(vec4<f32>(c.n.xyz, 0.0), vec4<f32>(c.v.xyz, 0.0), vec4<f32>(c.l.xyz, 0.0),
                         vec4<f32>(c.base_metallic.xyz, 1.0));
    let jb = mat4x4<f32>(vec4<f32>(c.v.xyz, 0.0), vec4<f32>(c.l.xyz, 0.0), vec4<f32>(c.n.xyz, 0.0),
                         vec4<f32>(0.5, -1.0, 2.0, 1.0));
    let skin = skin_matrix(ja, jb, ja * 0.5, jb * -0.25, vec4<f32>(x, n_dot_h, k, r));
    results[o + 44u] = skin * vec4<f32>(c.v.xyz, 1.0);
    let skin3 = mat3x3<f32>(skin[0].xyz, skin[1].xyz, skin[2].xyz);
    results[o + 45u] = vec4<f32>(skin_normal_matrix(skin3) * c.n.xyz, 0.0);
    let nan = bitcast<f32>(0x7fc00000u);
    results[o + 46u] = vec4<f32>(clearcoat_albedo(vec2<f32>(x, n_dot_h * 0.3), 1.0 + k),
                                 clearcoat_base_weight(x * 1.5 - 0.25, n_dot_h),
                                 clearcoat_base_weight(nan, n_dot_h), 0.0);
    results[o + 47u] = vec4<f32>(d_charlie(r, n_dot_h), v_neubelt(n_dot_h, x),
                                 sheen_base_weight(c.base_metallic.rgb, k), clamp_sheen_roughness(r * 1.2 - 0.1));
    results[o + 48u] = vec4<f32>(sheen_brdf(c.base_metallic.rgb, r, n_dot_h, x, sqrt(alpha)), 0.0);
    let alphas = anisotropic_alphas(alpha, x * 1.2 - 0.1);
    results[o + 49u] = vec4<f32>(alphas, d_ggx_anisotropic(alphas, c.n.xyz),
                                 v_smith_ggx_correlated_anisotropic(alphas, c.v.xyz, c.l.xyz));
    let rotation = vec2<f32>(n_dot_h, sqrt(max(1.0 - n_dot_h * n_dot_h, 0.0)));
    let t = anisotropy_direction(c.n.xyz, c.l.xyz, x - 0.5, rotation);
    let lobes = relit_brdf_lobes(c.n.xyz, c.v.xyz, c.l.xyz, t, s,
                                       RelitLobe(k, c.base_metallic.bgr * 1.2, vec3<f32>(x, 1.0 + r, 800.0 * n_dot_h)));
    results[o + 50u] = vec4<f32>(lobes.specular, lobes.diffuse.x);
    results[o + 51u] = vec4<f32>(anisotropic_bent_normal(c.n.xyz, c.v.xyz, t, k * 1.2 - 0.1, r), 0.0);
    results[o + 52u] = vec4<f32>(t, 0.0);
    results[o + 54u] = vec4<f32>(iridescent_fresnel(n_dot_h, 1.0 + 2.0 * r, 500.0 * x, c.base_metallic.rgb),
                                 interface_f0(1.0 + r, 1.5));
    results[o + 55u] = vec4<f32>(film_sensitivity(500.0 * x, c.base_metallic.rgb * 3.0), 0.0);
    results[o + 56u] = vec4<f32>(iridescent_mix(c.base_metallic.rgb, n_dot_h, vec3<f32>(k, 1.0 + r, 500.0 * x)), 0.0);
    results[o + 57u] = vec4<f32>(schlick_f0_of(c.base_metallic.rgb, n_dot_h), 0.0);
    results[o + 58u] = vec4<f32>(film_f0(c.base_metallic.rgb, n_dot_h, vec3<f32>(k, 1.0 + r, 500.0 * x)), 0.0);
    let below = c.l.xyz - 2.0 * dot(c.n.xyz, c.l.xyz) * c.n.xyz;
    results[o + 59u] = vec4<f32>(diffuse_transmission_lobe(c.n.xyz, c.v.xyz, below, s,
                                 RelitLobe(k, c.base_metallic.bgr * 1.2, vec3<f32>(x, 1.0 + r, 800.0 * n_dot_h)),
                                 x * 1.2 - 0.1, c.base_metallic.gbr * 1.1), 0.0);
    results[o + 60u] = vec4<f32>(relit_fresnel(s, RelitLobe(k, c.base_metallic.bgr * 1.2, vec3<f32>(x, 1.0 + r, 800.0 * n_dot_h)),
                                               n_dot_h * 1.2 - 0.1), 0.0);
    results[o + 61u] = vec4<f32>(textured_anisotropy(k, vec2<f32>(r, spec), c.base_metallic.rgb * 1.2 - vec3<f32>(0.1)),
                                 film_thickness(100.0 * x, 800.0 * n_dot_h, spec * 1.2 - 0.1));
    results[o + 62u] = vec4<f32>(normal_from_map(c.n.xyz, vec4<f32>(c.l.xyz, x - 0.5), c.base_metallic.brg, k * 3.0 - 1.0), 0.0);
    results[o + 63u] = vec4<f32>(
        depth_bend(x, k, r, spec, n_dot_h),
        depth_bend(x, 4.0 * k, r, spec, x),
        depth_bend(0.0, 0.0, 0.0, 0.0, 0.0),
        SILHOUETTE_BEND,
    );
    results[o + 64u] = vec4<f32>(
        select(0.0, 1.0, creased(c.n.xyz, c.v.xyz)),
        select(0.0, 1.0, creased(c.n.xyz, c.l.xyz)),
        dot(c.n.xyz, c.v.xyz),
        CREASE_COSINE,
    );
    results[o + 65u] = vec4<f32>(
        upsample_normal_weight(c.n.xyz, c.v.xyz),
        upsample_normal_weight(c.n.xyz, c.l.xyz),
        upsample_normal_weight(c.n.xyz, c.n.xyz),
        upsample_normal_weight(c.n.xyz, -c.n.xyz),
    );
    let fade_low = vec3<f32>(-1.0, -0.5, -2.0);
    let fade_high = vec3<f32>(1.5, 0.5, 1.0);
    let fade_spacing = vec3<f32>(0.5, 0.25, 1.0);
    results[o + 66u] = vec4<f32>(
        irradiance_weight(c.n.xyz, c.l.xyz),
        irradiance_weight(c.n.xyz, c.v.xyz),
        volume_fade(c.v.xyz * 3.0, fade_low, fade_high, fade_spacing),
        volume_fade(c.l.xyz * 2.0 + c.n.xyz, fade_low, fade_high, fade_spacing),
    );
    results[o + 53u] = vec4<f32>(tinted_f0(c.base_metallic.rgb, c.base_metallic.w, spec, vec3<f32>(x * 1.2 - 0.1, k, r)), 0.0);
    results[o + 67u] = vec4<f32>(equirect_direction(vec2<f32>(x, n_dot_h)), 0.0);
    results[o + 25u] = vec4<f32>(atlas_position(vec2<f32>(f32(i % 7u) * 8.0, 3.0), 6.0, c.n.xyz), basis[1], basis[6]);
}

// The same segment ends as smaa_ends in tests/shader_parity.rs.
fn smaa_ends(i: u32) -> vec2<f32> {
    let bits = vec4<f32>(vec4<u32>(i, i >> 1u, i >> 2u, i >> 3u) & vec4<u32>(1u));
    let beyond = vec4<f32>(vec4<u32>(i >> 4u, i >> 5u, i >> 6u, i >> 7u) & vec4<u32>(1u));
    return vec2<f32>(smaa_end_height(bits.xy, beyond.xy), smaa_end_height(bits.zw, beyond.zw));
}

// The same focus distances as coc_focus in tests/shader_parity.rs.
fn coc_focus(i: u32) -> f32 {
    switch i % 9u {
        case 0u: { return 0.05; }
        case 1u: { return 0.0; }
        case 2u: { return 3.4028235e38; }
        default: { return f32(i % 97u) * 0.25; }
    }
}

// Anisotropic GGX (KHR_materials_anisotropy): the WGSL twins of engine/src/shading/anisotropy.rs,
// with the same names. Widths α_t = mix(α, 1, s²) along the anisotropy direction t and
// α_b = α across it; D and the height-correlated Smith V in their anisotropic forms
// (Heitz 2014, Burley 2012); the environment read about a bent normal (McAuley 2015).
#import common
#import brdf
#import iridescence

// What a relit base adds to its surface: the anisotropy's strength (0..1), the
// dielectric F0's tint, the iridescent film (factor, index, thickness nm).
struct RelitLobe {
    strength: f32,
    tint: vec3<f32>,
    film: vec3<f32>,
}

// (α_t, α_b) of a lobe of width `alpha` and strength `strength` (0..1, clamped; NaN: 0).
fn anisotropic_alphas(alpha: f32, strength: f32) -> vec2<f32> {
    var s = clamp(strength, 0.0, 1.0);
    if !(strength == strength) {
        s = 0.0;
    }
    return vec2<f32>(alpha + (1.0 - alpha) * s * s, alpha);
}

// The view's azimuth (rad, 0..π/2) from t towards b, folded: atan2(|b·v|, |t·v|); 0
// along n.
fn view_azimuth(t: vec3<f32>, b: vec3<f32>, v: vec3<f32>) -> f32 {
    let x = abs(dot(t, v));
    let y = abs(dot(b, v));
    return select(0.0, atan2(y, x), x + y > 0.0);
}

// D (1/sr) for h = (t·h, b·h, n·h) in the lobe's frame.
fn d_ggx_anisotropic(alphas: vec2<f32>, h: vec3<f32>) -> f32 {
    let a2 = alphas.x * alphas.y;
    let f = vec3<f32>(alphas.y * h.x, alphas.x * h.y, a2 * clamp(h.z, 0.0, 1.0));
    let w2 = a2 / max(dot(f, f), 1e-30);
    return a2 * w2 * w2 / PI;
}

// V = G / (4 (n·v)(n·l)) for v and l in the lobe's frame (t, b, n).
fn v_smith_ggx_correlated_anisotropic(alphas: vec2<f32>, v: vec3<f32>, l: vec3<f32>) -> f32 {
    let nv = max(v.z, 0.0);
    let nl = max(l.z, 0.0);
    let lambda_v = nl * length(vec3<f32>(alphas.x * v.x, alphas.y * v.y, nv));
    let lambda_l = nv * length(vec3<f32>(alphas.x * l.x, alphas.y * l.y, nl));
    return 0.5 / max(lambda_v + lambda_l, 1e-8);
}

// The unit anisotropy direction: the tangent made perpendicular to n, turned towards the
// bitangent n × t · handedness by the angle of cosine and sine `rotation`.
fn anisotropy_direction(n: vec3<f32>, tangent: vec3<f32>, handedness: f32, rotation: vec2<f32>) -> vec3<f32> {
    let fallback = safe_normalize(cross(n, vec3<f32>(0.0, 1.0, 0.0)), vec3<f32>(1.0, 0.0, 0.0));
    let t = safe_normalize(tangent - n * dot(n, tangent), fallback);
    let b = cross(n, t) * select(1.0, -1.0, handedness < 0.0);
    return safe_normalize(t * rotation.x + b * rotation.y, t);
}

// The anisotropy at a texel of anisotropyTexture (engine/src/shading/anisotropy.rs,
// `textured_anisotropy`): x the strength × blue; y, z the cosine and sine of the
// direction (red and green × 2 − 1, the tangent where 0) turned by `rotation`.
fn textured_anisotropy(strength: f32, rotation: vec2<f32>, texel: vec3<f32>) -> vec3<f32> {
    let d = texel.xy * 2.0 - vec2<f32>(1.0);
    let len = length(d);
    var unit = vec2<f32>(1.0, 0.0);
    if len > 1e-6 {
        unit = d / len;
    }
    let turned = vec2<f32>(rotation.x * unit.x - rotation.y * unit.y, rotation.y * unit.x + rotation.x * unit.y);
    return vec3<f32>(strength * clamp(texel.z, 0.0, 1.0), turned);
}

// The Fresnel reflectance of a relit base at the cosine v·h (clamped): the tinted F0
// mixed with the film's. Shared with the diffuse transmission.
fn relit_fresnel(surface: Surface, lobe: RelitLobe, v_dot_h: f32) -> vec3<f32> {
    let f0 = tinted_f0(surface.base_color, clamp(surface.metallic, 0.0, 1.0), surface.specular_level, lobe.tint);
    return iridescent_mix(f0, clamp(v_dot_h, 0.0, 1.0), lobe.film);
}

// The lobes (1/sr) of a relit base: the anisotropic specular lobe along the unit
// direction t (strength 0: isotropic, height-correlated Smith), the dielectric F0 tinted,
// the Fresnel mixed with the film's.
fn relit_brdf_lobes(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, t: vec3<f32>, surface: Surface,
                          lobe: RelitLobe) -> BrdfLobes {
    var lobes: BrdfLobes;
    lobes.diffuse = vec3<f32>(0.0);
    lobes.specular = vec3<f32>(0.0);
    if !(dot(n, l) > 0.0) {
        return lobes;
    }
    let b = cross(n, t);
    let h = safe_normalize(v + l, n);
    let r = clamp_perceptual_roughness(surface.perceptual_roughness);
    let alphas = anisotropic_alphas(r * r, lobe.strength);
    let metallic = clamp(surface.metallic, 0.0, 1.0);
    let f = relit_fresnel(surface, lobe, dot(v, h));
    let lv = vec3<f32>(dot(t, v), dot(b, v), max(dot(n, v), MIN_N_DOT_V));
    let d = d_ggx_anisotropic(alphas, vec3<f32>(dot(t, h), dot(b, h), dot(n, h)));
    let vis = v_smith_ggx_correlated_anisotropic(alphas, lv, vec3<f32>(dot(t, l), dot(b, l), dot(n, l)));
    let k_d = (vec3<f32>(1.0) - f) * (1.0 - metallic);
    lobes.diffuse = k_d * surface.base_color * fd_lambert();
    lobes.specular = f * (d * vis);
    return lobes;
}

// The normal about which v's mirror reflection reads the prefiltered environment: n
// bent towards (b × v) × b by 1 − (1 − s (1 − r))⁴.
fn anisotropic_bent_normal(n: vec3<f32>, v: vec3<f32>, t: vec3<f32>, strength: f32,
                           perceptual_roughness: f32) -> vec3<f32> {
    var s = clamp(strength, 0.0, 1.0);
    if !(strength == strength) {
        s = 0.0;
    }
    let r = clamp_perceptual_roughness(perceptual_roughness);
    let b = cross(n, t);
    let bent = safe_normalize(cross(cross(b, v), b), n);
    let k = 1.0 - s * (1.0 - r);
    let keep = k * k * k * k;
    return safe_normalize(bent + (n - bent) * keep, n);
}

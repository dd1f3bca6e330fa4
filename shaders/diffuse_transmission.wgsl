// Diffuse transmission (KHR_materials_diffuse_transmission): the WGSL twin of
// engine/src/shading/diffuse_transmission.rs, with the same names. The factor d moves that share
// of the diffuse lobe from reflection (of the base colour) to a Lambertian transmission
// of the transmission colour; a light behind the surface is weighted by the Fresnel of
// its mirror image through the surface (l' = l − 2 (n·l) n).
#import common
#import brdf
#import iridescence
#import anisotropy

// The transmitted lobe (1/sr) for a light along l below the horizon of n, seen from v
// above it: d · (1 − F(v·h'))(1 − metallic) · colour / π; zero above the horizon.
fn diffuse_transmission_lobe(n: vec3<f32>, v: vec3<f32>, l: vec3<f32>, surface: Surface, lobe: RelitLobe,
                             factor: f32, color: vec3<f32>) -> vec3<f32> {
    let n_dot_l = dot(n, l);
    if !(n_dot_l < 0.0) {
        return vec3<f32>(0.0);
    }
    var d = clamp(factor, 0.0, 1.0);
    if !(factor == factor) {
        d = 0.0;
    }
    let mirrored = l - 2.0 * n_dot_l * n;
    let h = safe_normalize(v + mirrored, n);
    let metallic = clamp(surface.metallic, 0.0, 1.0);
    let f = relit_fresnel(surface, lobe, dot(v, h));
    let k_d = (vec3<f32>(1.0) - f) * (1.0 - metallic);
    return k_d * clamp(color, vec3<f32>(0.0), vec3<f32>(1.0)) * (d * fd_lambert());
}

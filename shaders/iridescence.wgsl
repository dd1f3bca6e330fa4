// Thin-film iridescence (KHR_materials_iridescence): the WGSL twins of
// engine/src/shading/iridescence.rs, with the same names. Belcour & Barla 2017: the Airy series
// of an air–film–base stack to second order, integrated against Gaussian fits of the
// colour-matching functions; F = mix(F_Schlick, F_film, factor).
#import common
#import brdf

// F0 of an interface between media of indices a and b.
fn interface_f0(a: f32, b: f32) -> f32 {
    let r = (a - b) / (a + b);
    return r * r;
}

fn film_gauss(v: f32, p: f32, s: f32, phase: f32, shift: f32) -> f32 {
    return v * sqrt(2.0 * PI * s) * cos(p * phase + shift) * exp(-phase * phase * s);
}

// Rec. 709 RGB sensitivity to an optical path difference (nm) with phase shifts `shift`.
fn film_sensitivity(opd_nm: f32, shift: vec3<f32>) -> vec3<f32> {
    let phase = 2.0 * PI * opd_nm * 1e-9;
    var xyz = vec3<f32>(film_gauss(5.4856e-13, 1.6810e6, 4.3278e9, phase, shift.x),
                        film_gauss(4.4201e-13, 1.7953e6, 9.3046e9, phase, shift.y),
                        film_gauss(5.2481e-13, 2.2084e6, 6.6121e9, phase, shift.z));
    xyz.x += film_gauss(9.7470e-14, 2.2399e6, 4.5282e9, phase, shift.x);
    xyz = xyz / 1.0685e-7;
    let xyz_to_rgb = mat3x3<f32>(vec3<f32>(3.2404542, -0.9692660, 0.0556434),
                                 vec3<f32>(-1.5371385, 1.8760108, -0.2040259),
                                 vec3<f32>(-0.4985314, 0.0415560, 1.0572252));
    return xyz_to_rgb * xyz;
}

// The Fresnel reflectance (RGB) of a film of index `film_ior` and thickness
// `thickness_nm` between air and a base of F0 `base_f0`, at cosine `cos_theta1`.
fn iridescent_fresnel(cos_theta1: f32, film_ior: f32, thickness_nm: f32, base_f0: vec3<f32>) -> vec3<f32> {
    var d = max(thickness_nm, 0.0);
    if !(thickness_nm == thickness_nm) || thickness_nm > 3.0e38 {
        d = 0.0;
    }
    var ior = max(film_ior, 1.0);
    if !(film_ior == film_ior) || film_ior > 3.0e38 {
        ior = 1.0;
    }
    let t = clamp(d / 0.03, 0.0, 1.0);
    let fade = t * t * (3.0 - 2.0 * t);
    let eta = 1.0 + (ior - 1.0) * fade;
    var cos1 = clamp(cos_theta1, 0.0, 1.0);
    if !(cos_theta1 == cos_theta1) {
        cos1 = 1.0;
    }
    // No film is exactly the base (Lumen fades the result as glTF fades the index).
    let bare = f_schlick(clamp(base_f0, vec3<f32>(0.0), vec3<f32>(1.0)), cos1);
    if fade == 0.0 {
        return bare;
    }
    // η ≥ 1: light entering the film from air always refracts.
    let cos2 = sqrt(max(1.0 - (1.0 - cos1 * cos1) / (eta * eta), 0.0));
    let r12 = f_schlick(vec3<f32>(interface_f0(eta, 1.0)), cos1).x;
    let t121 = 1.0 - r12;
    let phi21 = PI;
    let root = sqrt(clamp(base_f0, vec3<f32>(0.0), vec3<f32>(0.9999)));
    let base_ior = (vec3<f32>(1.0) + root) / (vec3<f32>(1.0) - root);
    let r1 = vec3<f32>(interface_f0(base_ior.x, eta), interface_f0(base_ior.y, eta), interface_f0(base_ior.z, eta));
    let r23 = f_schlick(r1, cos2);
    let phi23 = select(vec3<f32>(0.0), vec3<f32>(PI), base_ior < vec3<f32>(eta));
    let opd = 2.0 * eta * d * cos2;
    let phi = vec3<f32>(phi21) + phi23;
    let r123 = clamp(r23 * r12, vec3<f32>(1e-5), vec3<f32>(0.9999));
    let r123_root = sqrt(r123);
    let rs = t121 * t121 * r23 / (vec3<f32>(1.0) - r123);
    var reflectance = vec3<f32>(r12) + rs;
    var cm = rs - vec3<f32>(t121);
    for (var m = 1; m <= 2; m++) {
        cm *= r123_root;
        let order = f32(m);
        reflectance += cm * 2.0 * film_sensitivity(order * opd, order * phi);
    }
    return mix(bare, clamp(reflectance, vec3<f32>(0.0), vec3<f32>(1.0)), fade);
}

// The base's Fresnel under a film of strength factor: mix(F_Schlick, F_film, factor).
// `film`: (factor, index, thickness nm).
fn iridescent_mix(f0: vec3<f32>, cos_theta: f32, film: vec3<f32>) -> vec3<f32> {
    var k = clamp(film.x, 0.0, 1.0);
    if !(film.x == film.x) {
        k = 0.0;
    }
    let schlick = f_schlick(f0, clamp(cos_theta, 0.0, 1.0));
    if k == 0.0 {
        return schlick;
    }
    return mix(schlick, iridescent_fresnel(cos_theta, film.y, film.z, f0), k);
}

// The F0 the split sum and the compensation use under the film (factor, index,
// thickness): mix(f0, schlick_f0_of(the film's Fresnel at cos_theta), factor).
fn film_f0(f0: vec3<f32>, cos_theta: f32, film: vec3<f32>) -> vec3<f32> {
    var k = clamp(film.x, 0.0, 1.0);
    if !(film.x == film.x) {
        k = 0.0;
    }
    if k == 0.0 {
        return f0;
    }
    let fresnel = iridescent_fresnel(cos_theta, film.y, film.z, f0);
    return mix(f0, schlick_f0_of(fresnel, cos_theta), k);
}

// The F0 that makes Schlick's Fresnel at cos_theta equal `fresnel`.
fn schlick_f0_of(fresnel: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let x = pow5_one_minus(cos_theta);
    return clamp((fresnel - vec3<f32>(x)) / max(1.0 - x, 1e-4), vec3<f32>(0.0), vec3<f32>(1.0));
}

// The film's thickness (nm) at green `g` of iridescenceThicknessTexture
// (engine/src/shading/iridescence.rs, `film_thickness`): the minimum at 0, the maximum at 1.
fn film_thickness(min_nm: f32, max_nm: f32, g: f32) -> f32 {
    return min_nm + (max_nm - min_nm) * clamp(g, 0.0, 1.0);
}

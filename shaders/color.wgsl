// Colour: sRGB curve and tone mappers, the same as engine/src/shading/color.rs (same names).

const TONEMAP_NONE: u32 = 0u;
const TONEMAP_REINHARD: u32 = 1u;
const TONEMAP_ACES_FITTED: u32 = 2u;
const TONEMAP_AGX: u32 = 3u;
const TONEMAP_PBR_NEUTRAL: u32 = 4u;

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// Exact piecewise sRGB encoding (IEC 61966-2-1), input clamped to [0, 1].
fn srgb_encode(x_in: f32) -> f32 {
    var x = 0.0;
    if x_in == x_in {
        x = clamp(x_in, 0.0, 1.0);
    }
    if x <= 0.0031308 {
        return 12.92 * x;
    }
    return 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

fn srgb_decode(x_in: f32) -> f32 {
    let x = clamp(x_in, 0.0, 1.0);
    if x <= 0.04045 {
        return x / 12.92;
    }
    return pow((x + 0.055) / 1.055, 2.4);
}

fn tonemap_none(c: vec3<f32>) -> vec3<f32> {
    return clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Reinhard c / (c + 1) (seed 002).
fn tonemap_reinhard(c_in: vec3<f32>) -> vec3<f32> {
    let c = max(c_in, vec3<f32>(0.0));
    return c / (c + vec3<f32>(1.0));
}

fn aces_rrt_odt_fit(v: vec3<f32>) -> vec3<f32> {
    let a = v * (v + vec3<f32>(0.0245786)) - vec3<f32>(0.000090537);
    let b = v * (0.983729 * v + vec3<f32>(0.432951)) + vec3<f32>(0.238081);
    return a / b;
}

// ACES fitted (Stephen Hill, BakingLab 2016). WGSL matrices are built from columns.
fn tonemap_aces_fitted(c: vec3<f32>) -> vec3<f32> {
    let input_matrix = mat3x3<f32>(
        vec3<f32>(0.59719, 0.07600, 0.02840),
        vec3<f32>(0.35458, 0.90834, 0.13383),
        vec3<f32>(0.04823, 0.01566, 0.83777),
    );
    let output_matrix = mat3x3<f32>(
        vec3<f32>(1.60475, -0.10208, -0.00327),
        vec3<f32>(-0.53108, 1.10813, -0.07276),
        vec3<f32>(-0.07367, -0.00605, 1.07602),
    );
    let v = aces_rrt_odt_fit(input_matrix * max(c, vec3<f32>(0.0)));
    return clamp(output_matrix * v, vec3<f32>(0.0), vec3<f32>(1.0));
}

// Wrensch's fit of AgX's default contrast curve.
fn agx_contrast(x: vec3<f32>) -> vec3<f32> {
    let x2 = x * x;
    let x4 = x2 * x2;
    return 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x - vec3<f32>(0.00232);
}

// AgX (Sobotka 2023; Wrensch's minimal approximation).
fn tonemap_agx(c: vec3<f32>) -> vec3<f32> {
    let min_ev = -12.473931;
    let max_ev = 4.026069;
    let inset = mat3x3<f32>(
        vec3<f32>(0.84247906, 0.04232824, 0.042375655),
        vec3<f32>(0.0784336, 0.8784686, 0.0784336),
        vec3<f32>(0.079223745, 0.07916613, 0.879143),
    );
    let outset = mat3x3<f32>(
        vec3<f32>(1.196879, -0.05289685, -0.052971635),
        vec3<f32>(-0.09802088, 1.1519031, -0.09804345),
        vec3<f32>(-0.09902974, -0.09896118, 1.1510737),
    );
    var v = inset * max(c, vec3<f32>(0.0));
    v = clamp(log2(max(v, vec3<f32>(1e-10))), vec3<f32>(min_ev), vec3<f32>(max_ev));
    v = (v - vec3<f32>(min_ev)) / (max_ev - min_ev);
    v = outset * agx_contrast(v);
    return min(pow(max(v, vec3<f32>(0.0)), vec3<f32>(2.2)), vec3<f32>(1.0));
}

// Khronos PBR Neutral (2024).
fn tonemap_pbr_neutral(c_in: vec3<f32>) -> vec3<f32> {
    let start_compression = 0.8 - 0.04;
    let desaturation = 0.15;
    var c = max(c_in, vec3<f32>(0.0));
    let x = min(c.r, min(c.g, c.b));
    var offset = 0.04;
    if x < 0.08 {
        offset = x - 6.25 * x * x;
    }
    c -= vec3<f32>(offset);
    let peak = max(c.r, max(c.g, c.b));
    if peak < start_compression {
        return c;
    }
    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    c *= new_peak / peak;
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return c * (1.0 - g) + vec3<f32>(new_peak * g);
}

fn tonemap(op: u32, c: vec3<f32>) -> vec3<f32> {
    if op == TONEMAP_REINHARD {
        return tonemap_reinhard(c);
    }
    if op == TONEMAP_ACES_FITTED {
        return tonemap_aces_fitted(c);
    }
    if op == TONEMAP_AGX {
        return tonemap_agx(c);
    }
    if op == TONEMAP_PBR_NEUTRAL {
        return tonemap_pbr_neutral(c);
    }
    return tonemap_none(c);
}

// Largest finite f16, the limit of the half-precision HDR target.
const HALF_MAX: f32 = 65504.0;

// A blended surface's premultiplied colour and coverage (Porter & Duff 1984): `lit` is the
// radiance it reflects and emits (cd/m² × exposure), `alpha` the fraction of the pixel it
// covers (clamped to 0..1). NaN radiance becomes 0 and the colour stays finite in f16.
// The target then composites it with "over": dst ← src + dst·(1 − α).
fn premultiplied(lit: vec3<f32>, alpha: f32) -> vec4<f32> {
    let a = clamp(alpha, 0.0, 1.0);
    let finite = select(lit, vec3<f32>(0.0), lit != lit);
    return vec4<f32>(min(finite, vec3<f32>(HALF_MAX)) * a, a);
}

// Colour: sRGB curve and tone mappers, the same as engine/src/color.rs (same names).

const TONEMAP_NONE: u32 = 0u;
const TONEMAP_REINHARD: u32 = 1u;
const TONEMAP_ACES_FITTED: u32 = 2u;

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

fn tonemap(op: u32, c: vec3<f32>) -> vec3<f32> {
    if op == TONEMAP_REINHARD {
        return tonemap_reinhard(c);
    }
    if op == TONEMAP_ACES_FITTED {
        return tonemap_aces_fitted(c);
    }
    return tonemap_none(c);
}

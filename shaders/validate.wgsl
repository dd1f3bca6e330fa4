// The PBR texture validator's metal/roughness rules per texel, the same as
// engine/src/validate.rs (same names and numbers; see its documentation). Used by the
// `validation` debug views. Needs color.wgsl.
#import color

const VERDICT_NOT_APPLICABLE: u32 = 0u;
const VERDICT_VALID: u32 = 1u;
const VERDICT_BORDERLINE: u32 = 2u;
const VERDICT_INVALID: u32 = 3u;

const DARK_FLOOR: u32 = 30u;
const DARK_FLOOR_STRICT: u32 = 50u;
const BRIGHT_CEILING: u32 = 240u;
const METAL_METALLIC: u32 = 235u;
const DIELECTRIC_METALLIC: u32 = 10u;
const METAL_FLOOR: u32 = 180u;
const BORDER_CODES: u32 = 10u;

// The 8-bit sRGB code of a linear colour's luminance.
fn brightness_code(linear: vec3<f32>) -> u32 {
    var y = luminance(linear);
    if !(y == y) || abs(y) > 3.0e38 {
        y = 0.0;
    }
    return u32(round(srgb_encode(y) * 255.0));
}

// The code value of a linear data channel.
fn data_code(v: f32) -> u32 {
    var x = 0.0;
    if v == v {
        x = clamp(v, 0.0, 1.0);
    }
    return u32(round(x * 255.0));
}

fn in_range(value: u32, low: u32, high: u32) -> u32 {
    if value < low || value > high {
        return VERDICT_INVALID;
    }
    if value < low + BORDER_CODES || value + BORDER_CODES > high {
        return VERDICT_BORDERLINE;
    }
    return VERDICT_VALID;
}

fn dark_floor(strict: bool) -> u32 {
    return select(DARK_FLOOR, DARK_FLOOR_STRICT, strict);
}

// The worst verdict of the four metal/roughness rules (base-color-range,
// metal-reflectance, partial-metal, dirt-as-metal).
fn metal_rough_verdict(base: vec3<f32>, metallic: f32, strict: bool) -> u32 {
    let b = brightness_code(base);
    let m = data_code(metallic);
    if m >= METAL_METALLIC {
        if b < METAL_FLOOR {
            // Below the metal floor (dirt-as-metal, under 100, is invalid too).
            return VERDICT_INVALID;
        }
        return select(VERDICT_VALID, VERDICT_BORDERLINE, b < METAL_FLOOR + BORDER_CODES);
    }
    var worst = in_range(b, dark_floor(strict), BRIGHT_CEILING);
    if m >= DIELECTRIC_METALLIC {
        var partial = VERDICT_VALID;
        if b >= METAL_FLOOR {
            partial = VERDICT_INVALID;
        } else if b + BORDER_CODES >= METAL_FLOOR {
            partial = VERDICT_BORDERLINE;
        }
        worst = max(worst, partial);
    }
    return worst;
}

// The heat-map colour of a verdict, as display values (Verdict::color / 255).
fn verdict_color(verdict: u32) -> vec3<f32> {
    switch verdict {
        case VERDICT_VALID: {
            return vec3<f32>(0.0, 200.0, 0.0) / 255.0;
        }
        case VERDICT_BORDERLINE: {
            return vec3<f32>(255.0, 220.0, 0.0) / 255.0;
        }
        case VERDICT_INVALID: {
            return vec3<f32>(255.0, 0.0, 0.0) / 255.0;
        }
        default: {
            return vec3<f32>(48.0) / 255.0;
        }
    }
}

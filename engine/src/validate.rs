//! The PBR texture validator: the practical rules of seed 001 (the Allegorithmic PBR
//! guide) with the thresholds of docs/src/formulas.md#measured-texture-ranges, checked texel by texel.
//!
//! Brightness is judged, as the guide's figures are, in 8-bit sRGB code values: a
//! colour's *brightness* is `round(255 · srgb_encode(luminance(linear colour)))`, so a grey
//! texel's brightness is its own code value and a coloured one's that of the grey of the
//! same luminance (gold, 255/195/86, counts as 204 rather than failing on its blue).
//! The metallic map is judged by its code value `round(255 · metallic)`.
//!
//! | rule | where | valid | borderline (yellow) |
//! | --- | --- | --- | --- |
//! | `base-color-range` | metallic < 235 | brightness 30 (50 with `strict`) ..= 240 | within 10 codes inside a bound |
//! | `metal-reflectance` | metallic ≥ 235 | brightness ≥ 180 (70–100 % reflectance) | 180..190 |
//! | `partial-metal` | 10 ≤ metallic < 235 | brightness < 180: the base colour was lowered under the covering dielectric | 170..180 |
//! | `dirt-as-metal` | metallic ≥ 235 | brightness ≥ 100: darker is a dielectric colour (dirt, rust, paint) marked as metal | — |
//! | `specular-class` | every spec/gloss texel | F0 = luminance of the specular in 0.02 ..= 0.17 (dielectrics and liquids 0.02–0.05, gems 0.05–0.17), or brightness ≥ 180 (metal); F0 < 0.02 and the gap between gems and metals are invalid | within 10 % inside 0.02 or 0.17, or metal brightness 180..190 |
//! | `energy` | every spec/gloss texel | diffuse + specular ≤ 1 in every channel (linear) | sum above 0.98 |
//! | `diffuse-range` | spec/gloss texels whose specular is not metal | brightness 30 (50 with `strict`) ..= 240: black diffuse only under metal specular | within 10 codes inside a bound |
//!
//! A metallic value below 10 (4 %) reads as 0, the noise of compressed maps. The numbers
//! 10 (that noise floor) and 100 (the dirt bound, far under the 180 of bare metal) are
//! Lumen's; every other number is docs/src/formulas.md#measured-texture-ranges.

use crate::scene::{ColorSpace, TextureData};
use crate::shading::color::{luminance, srgb_decode, srgb_encode};
use glam::Vec3;

/// Darkest dielectric colour, tolerant (sRGB code).
pub const DARK_FLOOR: u32 = 30;
/// Darkest dielectric colour, strict (sRGB code).
pub const DARK_FLOOR_STRICT: u32 = 50;
/// Brightest dielectric colour (sRGB code).
pub const BRIGHT_CEILING: u32 = 240;
/// Metallic code from which a texel is bare metal.
pub const METAL_METALLIC: u32 = 235;
/// Metallic code below which a texel is a dielectric (compression noise).
pub const DIELECTRIC_METALLIC: u32 = 10;
/// Darkest bare-metal reflectance (sRGB code; 70 % in the guide's words).
pub const METAL_FLOOR: u32 = 180;
/// Base colour darker than this under bare metal is a dielectric colour (sRGB code).
pub const DIRT_CEILING: u32 = 100;
/// Lowest measured dielectric F0 (linear).
pub const F0_MIN: f32 = 0.02;
/// Highest dielectric (liquid, common material) F0 (linear).
pub const F0_DIELECTRIC_MAX: f32 = 0.05;
/// Highest gem F0 (linear).
pub const F0_GEM_MAX: f32 = 0.17;
/// Width of the borderline band inside a code bound.
const BORDER_CODES: u32 = 10;

/// One rule of the validator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rule {
    /// Dielectric (and partly metal) base colour brightness range.
    BaseColorRange,
    /// Bare-metal reflectance range.
    MetalReflectance,
    /// Grey metallic whose base colour was not lowered.
    PartialMetal,
    /// A dark (dielectric) colour under high metallic.
    DirtAsMetal,
    /// Specular (F0) in a measured class, not in a gap.
    SpecularClass,
    /// Diffuse + specular ≤ 1.
    Energy,
    /// Diffuse brightness range; black only under metal specular.
    DiffuseRange,
}

impl Rule {
    /// The metal/roughness rules.
    pub const METAL_ROUGH: [Rule; 4] = [
        Rule::BaseColorRange,
        Rule::MetalReflectance,
        Rule::PartialMetal,
        Rule::DirtAsMetal,
    ];
    /// The specular/glossiness rules.
    pub const SPEC_GLOSS: [Rule; 3] = [Rule::SpecularClass, Rule::Energy, Rule::DiffuseRange];

    /// Name used in reports, JSON and heat-map file names.
    pub fn name(self) -> &'static str {
        match self {
            Rule::BaseColorRange => "base-color-range",
            Rule::MetalReflectance => "metal-reflectance",
            Rule::PartialMetal => "partial-metal",
            Rule::DirtAsMetal => "dirt-as-metal",
            Rule::SpecularClass => "specular-class",
            Rule::Energy => "energy",
            Rule::DiffuseRange => "diffuse-range",
        }
    }
}

/// A rule's verdict on one texel. The numeric values are the WGSL constants.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Verdict {
    /// The rule does not apply here.
    #[default]
    NotApplicable = 0,
    /// Valid.
    Valid = 1,
    /// Valid, but within the borderline band of a bound.
    Borderline = 2,
    /// Invalid.
    Invalid = 3,
}

impl Verdict {
    /// The heat-map colour: green valid, yellow borderline, red invalid, dark grey where
    /// the rule does not apply.
    pub fn color(self) -> [u8; 3] {
        match self {
            Verdict::NotApplicable => [48, 48, 48],
            Verdict::Valid => [0, 200, 0],
            Verdict::Borderline => [255, 220, 0],
            Verdict::Invalid => [255, 0, 0],
        }
    }
}

/// The 8-bit sRGB code of a linear colour's luminance (see the module documentation).
pub fn brightness_code(linear: Vec3) -> u32 {
    let y = luminance(linear);
    let y = if y.is_finite() { y } else { 0.0 };
    (srgb_encode(y) * 255.0).round() as u32
}

/// The code value of a linear data channel.
pub fn data_code(v: f32) -> u32 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    (v * 255.0).round() as u32
}

/// `value` within `[low, high]` (codes): valid, borderline within the band inside either
/// bound, invalid outside.
fn in_range(value: u32, low: u32, high: u32) -> Verdict {
    if value < low || value > high {
        Verdict::Invalid
    } else if value < low + BORDER_CODES || value + BORDER_CODES > high {
        Verdict::Borderline
    } else {
        Verdict::Valid
    }
}

/// The dark floor in force.
pub fn dark_floor(strict: bool) -> u32 {
    if strict {
        DARK_FLOOR_STRICT
    } else {
        DARK_FLOOR
    }
}

/// The four metal/roughness verdicts of a texel, in [`Rule::METAL_ROUGH`] order.
/// `base` is the linear base colour, `metallic` the linear metallic value.
pub fn metal_rough_verdicts(base: Vec3, metallic: f32, strict: bool) -> [Verdict; 4] {
    let b = brightness_code(base);
    let m = data_code(metallic);
    let metal = m >= METAL_METALLIC;
    let base_range = if metal {
        Verdict::NotApplicable
    } else {
        in_range(b, dark_floor(strict), BRIGHT_CEILING)
    };
    let reflectance = match (metal, b) {
        (false, _) => Verdict::NotApplicable,
        (true, b) if b < METAL_FLOOR => Verdict::Invalid,
        (true, b) if b < METAL_FLOOR + BORDER_CODES => Verdict::Borderline,
        (true, _) => Verdict::Valid,
    };
    let partial = match (m, b) {
        (m, _) if !(DIELECTRIC_METALLIC..METAL_METALLIC).contains(&m) => Verdict::NotApplicable,
        (_, b) if b >= METAL_FLOOR => Verdict::Invalid,
        (_, b) if b + BORDER_CODES >= METAL_FLOOR => Verdict::Borderline,
        _ => Verdict::Valid,
    };
    let dirt = match (metal, b) {
        (false, _) => Verdict::NotApplicable,
        (true, b) if b < DIRT_CEILING => Verdict::Invalid,
        (true, _) => Verdict::Valid,
    };
    [base_range, reflectance, partial, dirt]
}

/// The worst of a texel's metal/roughness verdicts (the viewer's heat map). Twin of
/// `metal_rough_verdict` in `shaders/validate.wgsl`.
pub fn metal_rough_verdict(base: Vec3, metallic: f32, strict: bool) -> Verdict {
    metal_rough_verdicts(base, metallic, strict)
        .into_iter()
        .max()
        .unwrap_or_default()
}

/// Where a specular colour falls among the measured classes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecularClass {
    /// F0 below 0.02: no measured material.
    TooLow,
    /// Dielectrics and liquids, F0 0.02–0.05.
    Dielectric,
    /// Gems, F0 0.05–0.17.
    Gem,
    /// Between gems and bare metal.
    Gap,
    /// Bare metal, brightness ≥ 180.
    Metal,
}

/// The class of a linear specular colour.
pub fn specular_class(specular: Vec3) -> SpecularClass {
    let f0 = luminance(specular);
    if brightness_code(specular) >= METAL_FLOOR {
        SpecularClass::Metal
    } else if f0.is_nan() || f0 < F0_MIN {
        SpecularClass::TooLow
    } else if f0 <= F0_DIELECTRIC_MAX {
        SpecularClass::Dielectric
    } else if f0 <= F0_GEM_MAX {
        SpecularClass::Gem
    } else {
        SpecularClass::Gap
    }
}

/// The three spec/gloss verdicts of a texel, in [`Rule::SPEC_GLOSS`] order (linear
/// colours).
pub fn spec_gloss_verdicts(diffuse: Vec3, specular: Vec3, strict: bool) -> [Verdict; 3] {
    let class = specular_class(specular);
    let f0 = luminance(specular);
    let class_verdict = match class {
        SpecularClass::TooLow | SpecularClass::Gap => Verdict::Invalid,
        SpecularClass::Metal if brightness_code(specular) < METAL_FLOOR + BORDER_CODES => {
            Verdict::Borderline
        }
        SpecularClass::Metal => Verdict::Valid,
        _ if !(F0_MIN * 1.1..=F0_GEM_MAX / 1.1).contains(&f0) => Verdict::Borderline,
        _ => Verdict::Valid,
    };
    let sum = (diffuse + specular).max_element();
    let energy = if !sum.is_finite() || sum > 1.0 + 1e-5 {
        Verdict::Invalid
    } else if sum > 0.98 {
        Verdict::Borderline
    } else {
        Verdict::Valid
    };
    let diffuse_range = if class == SpecularClass::Metal {
        Verdict::NotApplicable
    } else {
        in_range(brightness_code(diffuse), dark_floor(strict), BRIGHT_CEILING)
    };
    [class_verdict, energy, diffuse_range]
}

/// Scales a linear colour (keeping its hue) so that its brightness lies in
/// `[low, high]` codes; a colour that cannot reach `low` by scaling (black, or a channel
/// saturating first) is blended towards the grey of that brightness. Returns the colour
/// unchanged when it is in range.
pub fn clamp_brightness(c: Vec3, low: u32, high: u32) -> Vec3 {
    let c = Vec3::new(
        if c.x.is_finite() {
            c.x.clamp(0.0, 1.0)
        } else {
            0.0
        },
        if c.y.is_finite() {
            c.y.clamp(0.0, 1.0)
        } else {
            0.0
        },
        if c.z.is_finite() {
            c.z.clamp(0.0, 1.0)
        } else {
            0.0
        },
    );
    let b = brightness_code(c);
    if (low..=high).contains(&b) {
        return c;
    }
    let target_code = if b < low { low } else { high };
    // Aim at the middle of the target code so that rounding lands on it.
    let target = srgb_decode(target_code as f32 / 255.0);
    let y = luminance(c);
    let scaled = if y > 1e-6 {
        (c * (target / y)).min(Vec3::ONE)
    } else {
        Vec3::splat(target)
    };
    if (low..=high).contains(&brightness_code(scaled)) {
        return scaled;
    }
    // Saturated channels: move towards the grey of the target until it is in range.
    let grey = Vec3::splat(target);
    (1..=16)
        .map(|k| scaled.lerp(grey, k as f32 / 16.0))
        .find(|m| (low..=high).contains(&brightness_code(*m)))
        .unwrap_or(grey)
}

/// The "PBR safe colour" fix of a metal/roughness texel's base colour: into
/// [180, 255] under bare metal, under 180 for partial metal, and into the dielectric range
/// elsewhere (the dark floor as `strict` says).
pub fn safe_base_color(base: Vec3, metallic: f32, strict: bool) -> Vec3 {
    let m = data_code(metallic);
    if m >= METAL_METALLIC {
        clamp_brightness(base, METAL_FLOOR, 255)
    } else if m >= DIELECTRIC_METALLIC {
        clamp_brightness(base, dark_floor(strict), METAL_FLOOR - 1)
    } else {
        clamp_brightness(base, dark_floor(strict), BRIGHT_CEILING)
    }
}

/// The safe-colour fix of a spec/gloss texel's diffuse: into the dielectric range unless
/// the specular is metal (then it is left as it is).
pub fn safe_diffuse(diffuse: Vec3, specular: Vec3, strict: bool) -> Vec3 {
    if specular_class(specular) == SpecularClass::Metal {
        diffuse
    } else {
        clamp_brightness(diffuse, dark_floor(strict), BRIGHT_CEILING)
    }
}

/// A colour map: an sRGB texture (or none) times a linear factor.
#[derive(Clone, Debug)]
pub struct ColorInput {
    /// The texture (its colour space says how to decode it).
    pub texture: Option<TextureData>,
    /// Linear factor, multiplied in.
    pub factor: Vec3,
}

/// A scalar map: one channel of a texture (or none) times a factor.
#[derive(Clone, Debug)]
pub struct ScalarInput {
    /// The texture (linear).
    pub texture: Option<TextureData>,
    /// The channel read: 0 red … 3 alpha.
    pub channel: usize,
    /// Factor, multiplied in.
    pub factor: f32,
}

/// A material to validate or convert, in either workflow.
#[derive(Clone, Debug)]
pub enum MaterialInput {
    /// Base colour, metallic, roughness.
    MetalRough {
        /// Base colour.
        base_color: ColorInput,
        /// Metallic.
        metallic: ScalarInput,
        /// Perceptual roughness.
        roughness: ScalarInput,
    },
    /// Diffuse, specular, glossiness.
    SpecGloss {
        /// Diffuse colour.
        diffuse: ColorInput,
        /// Specular colour (F0).
        specular: ColorInput,
        /// Glossiness.
        glossiness: ScalarInput,
    },
}

/// One texel of a material, linear.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Texel {
    /// Base colour, metallic, roughness.
    MetalRough(Vec3, f32, f32),
    /// Diffuse, specular, glossiness.
    SpecGloss(Vec3, Vec3, f32),
}

fn sample(texture: &TextureData, u: f32, v: f32) -> [f32; 4] {
    let x = ((u * texture.width as f32) as u32).min(texture.width - 1);
    let y = ((v * texture.height as f32) as u32).min(texture.height - 1);
    let i = ((y * texture.width + x) * 4) as usize;
    let mut out = [1.0f32; 4];
    for (c, o) in out.iter_mut().enumerate() {
        let byte = texture.rgba8.get(i + c).copied().unwrap_or(255);
        let value = f32::from(byte) / 255.0;
        *o = match (texture.color_space, c) {
            (ColorSpace::Srgb, 0..=2) => srgb_decode(value),
            _ => value,
        };
    }
    out
}

impl ColorInput {
    fn at(&self, u: f32, v: f32) -> Vec3 {
        let t = self
            .texture
            .as_ref()
            .map_or(Vec3::ONE, |t| Vec3::from_slice(&sample(t, u, v)[..3]));
        t * self.factor
    }
}

impl ScalarInput {
    fn at(&self, u: f32, v: f32) -> f32 {
        let t = self
            .texture
            .as_ref()
            .map_or(1.0, |t| sample(t, u, v)[self.channel.min(3)]);
        t * self.factor
    }
}

impl MaterialInput {
    fn textures(&self) -> Vec<&TextureData> {
        let (a, b, c) = match self {
            MaterialInput::MetalRough {
                base_color,
                metallic,
                roughness,
            } => (&base_color.texture, &metallic.texture, &roughness.texture),
            MaterialInput::SpecGloss {
                diffuse,
                specular,
                glossiness,
            } => (&diffuse.texture, &specular.texture, &glossiness.texture),
        };
        [a, b, c].into_iter().flatten().collect()
    }

    /// The size the material is checked at: the largest texture's, 1×1 with factors only.
    /// Every map is sampled there (nearest texel), so maps of other sizes line up by UV.
    pub fn size(&self) -> (u32, u32) {
        self.textures()
            .iter()
            .fold((1, 1), |(w, h), t| (w.max(t.width), h.max(t.height)))
    }

    /// The texel at `(x, y)` of a grid of `size` texels ([`MaterialInput::size`], which
    /// callers compute once).
    pub fn texel(&self, x: u32, y: u32, (w, h): (u32, u32)) -> Texel {
        let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        match self {
            MaterialInput::MetalRough {
                base_color,
                metallic,
                roughness,
            } => Texel::MetalRough(base_color.at(u, v), metallic.at(u, v), roughness.at(u, v)),
            MaterialInput::SpecGloss {
                diffuse,
                specular,
                glossiness,
            } => Texel::SpecGloss(diffuse.at(u, v), specular.at(u, v), glossiness.at(u, v)),
        }
    }

    /// The rules of the material's workflow.
    pub fn rules(&self) -> &'static [Rule] {
        match self {
            MaterialInput::MetalRough { .. } => &Rule::METAL_ROUGH,
            MaterialInput::SpecGloss { .. } => &Rule::SPEC_GLOSS,
        }
    }
}

/// What one rule found in one material.
#[derive(Clone, Debug, PartialEq)]
pub struct RuleReport {
    /// The rule.
    pub rule: Rule,
    /// Texels it applies to.
    pub checked: u64,
    /// Texels that fail it.
    pub invalid: u64,
    /// Texels in its borderline band.
    pub borderline: u64,
    /// Heat map (RGB8, the material's size): the rule's verdict per texel.
    pub heatmap: image::RgbImage,
}

impl RuleReport {
    /// Failing share of the texels the rule applies to (0 when it applies nowhere).
    pub fn invalid_share(&self) -> f64 {
        if self.checked == 0 {
            0.0
        } else {
            self.invalid as f64 / self.checked as f64
        }
    }
}

/// The validator's findings for one material.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Checked size in texels.
    pub size: (u32, u32),
    /// One entry per rule of the workflow.
    pub rules: Vec<RuleReport>,
    /// Heat map of the worst verdict per texel.
    pub heatmap: image::RgbImage,
}

impl Report {
    /// True when no texel fails any rule.
    pub fn passes(&self) -> bool {
        self.rules.iter().all(|r| r.invalid == 0)
    }
}

/// Checks every texel of `material` against its workflow's rules.
pub fn validate(material: &MaterialInput, strict: bool) -> Report {
    validate_with_progress(material, strict, &|| {})
}

/// The verdicts of a texel's rules, padded to four (spec/gloss has three).
fn padded_verdicts(texel: Texel, strict: bool) -> [Verdict; 4] {
    match texel {
        Texel::MetalRough(base, metallic, _) => metal_rough_verdicts(base, metallic, strict),
        Texel::SpecGloss(diffuse, specular, _) => {
            let [a, b, c] = spec_gloss_verdicts(diffuse, specular, strict);
            [a, b, c, Verdict::NotApplicable]
        }
    }
}

/// [`validate`], rows in parallel, calling `row_done` after each row.
pub fn validate_with_progress(
    material: &MaterialInput,
    strict: bool,
    row_done: &(dyn Fn() + Sync),
) -> Report {
    use rayon::prelude::*;
    let (w, h) = material.size();
    let rules = material.rules();
    let rows: Vec<Vec<[Verdict; 4]>> = (0..h)
        .into_par_iter()
        .map(|y| {
            let row = (0..w)
                .map(|x| padded_verdicts(material.texel(x, y, (w, h)), strict))
                .collect();
            row_done();
            row
        })
        .collect();
    let mut reports: Vec<RuleReport> = rules
        .iter()
        .map(|&rule| RuleReport {
            rule,
            checked: 0,
            invalid: 0,
            borderline: 0,
            heatmap: image::RgbImage::new(w, h),
        })
        .collect();
    let mut worst_map = image::RgbImage::new(w, h);
    for (y, row) in (0u32..).zip(&rows) {
        for (x, found) in (0u32..).zip(row) {
            let mut worst = Verdict::NotApplicable;
            for (report, verdict) in reports.iter_mut().zip(found) {
                report.heatmap.put_pixel(x, y, image::Rgb(verdict.color()));
                report.checked += u64::from(*verdict != Verdict::NotApplicable);
                report.invalid += u64::from(*verdict == Verdict::Invalid);
                report.borderline += u64::from(*verdict == Verdict::Borderline);
                worst = worst.max(*verdict);
            }
            worst_map.put_pixel(x, y, image::Rgb(worst.color()));
        }
    }
    Report {
        size: (w, h),
        rules: reports,
        heatmap: worst_map,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The linear grey whose brightness is `code`.
    fn grey(code: u32) -> Vec3 {
        Vec3::splat(srgb_decode(code as f32 / 255.0))
    }

    #[test]
    fn brightness_of_grey_is_its_code_and_gold_passes_as_metal() {
        for code in 0..=255 {
            assert_eq!(brightness_code(grey(code)), code);
        }
        let gold = Vec3::new(1.0, srgb_decode(195.0 / 255.0), srgb_decode(86.0 / 255.0));
        assert!(
            brightness_code(gold) >= METAL_FLOOR,
            "{}",
            brightness_code(gold)
        );
    }

    #[test]
    fn specular_classes_follow_the_measured_ranges() {
        let f = Vec3::splat;
        assert_eq!(specular_class(f(0.019)), SpecularClass::TooLow);
        assert_eq!(specular_class(f(0.02)), SpecularClass::Dielectric);
        assert_eq!(specular_class(f(0.05)), SpecularClass::Dielectric);
        assert_eq!(specular_class(f(0.051)), SpecularClass::Gem);
        assert_eq!(specular_class(f(0.17)), SpecularClass::Gem);
        assert_eq!(specular_class(f(0.171)), SpecularClass::Gap);
        assert_eq!(specular_class(grey(179)), SpecularClass::Gap);
        assert_eq!(specular_class(grey(180)), SpecularClass::Metal);
        assert_eq!(specular_class(f(f32::NAN)), SpecularClass::TooLow);
    }

    #[test]
    fn safe_colors_land_in_range_and_leave_valid_ones_alone() {
        for code in [0, 5, 29, 30, 120, 240, 241, 255] {
            for tint in [
                Vec3::ONE,
                Vec3::new(1.0, 0.2, 0.05),
                Vec3::new(0.0, 0.0, 1.0),
            ] {
                let c = grey(code) * tint;
                for (metallic, strict) in [(0.0, false), (0.0, true), (0.5, false), (1.0, false)] {
                    let fixed = safe_base_color(c, metallic, strict);
                    let v = metal_rough_verdicts(fixed, metallic, strict);
                    assert!(
                        !v.contains(&Verdict::Invalid),
                        "{c} m {metallic}: {fixed} {v:?}"
                    );
                    if !metal_rough_verdicts(c, metallic, strict).contains(&Verdict::Invalid) {
                        assert_eq!(fixed, c, "a valid colour is kept");
                    }
                }
            }
        }
        let black = safe_diffuse(Vec3::ZERO, Vec3::splat(0.04), false);
        assert_eq!(brightness_code(black), DARK_FLOOR);
        assert_eq!(safe_diffuse(Vec3::ZERO, Vec3::ONE, false), Vec3::ZERO);
    }

    #[test]
    fn every_verdict_is_finite_input_safe() {
        for v in [f32::NAN, f32::INFINITY, -1.0, 0.0, 1.0, 2.0] {
            let c = Vec3::splat(v);
            let _ = metal_rough_verdicts(c, v, false);
            let _ = spec_gloss_verdicts(c, c, true);
        }
    }
}

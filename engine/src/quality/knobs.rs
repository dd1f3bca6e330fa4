//! The built-in knobs, each declared once (see [`super::knob`] for what is derived from a
//! declaration). [`builtin`] lists them in the order `--help`, the viewer's panel and
//! `lumen quality show` give them; a new knob is its `static` here (or in a plugin's own
//! module) and one line in that list (or one [`Knobs::with`]).

use super::knob::{Acts, Group, Kind, Knob, Knobs, Value};
use super::{
    AaMethod, AoResolution, HdrPrecision, ShadowFilter, ShadowMask, SpecularAaForm, Transparency,
};
use super::{
    AaSettings, AoSettings, GiSettings, Quality, ReflectionProbeSettings, SpecularAaSettings,
    SsrSettings,
};
use crate::choice::Choice;
use crate::pass_id::PassId;
use crate::shading::brdf::VisibilityModel;
use std::sync::LazyLock;

/// `shadows`: Shadows for the whole frame; off skips the shadow pass.
pub static SHADOWS: Knob = Knob {
    name: "shadows",
    path: "shadows",
    group: Group::SHADOWS,
    doc: "Shadows for the whole frame; off skips the shadow pass",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::Shadow, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `shadow-filter`: Shadow filtering: hardware (2×2 PCF), tent (3×3 bilinear taps), pcf (16 taps), pcss (soft, from the light's size).
pub static SHADOW_FILTER: Knob = Knob {
    name: "shadow-filter",
    path: "shadow_filter",
    group: Group::SHADOWS,
    doc: "Shadow filtering: hardware (2×2 PCF), tent (3×3 bilinear taps), pcf (16 taps), pcss (soft, from the light's size)",
    kind: Kind::Choice(ShadowFilter::NAMES),
    default: Value::Name("tent"),
    passes: &[PassId::ShadowMask, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[
        Value::Name("hardware"),
        Value::Name("pcf"),
        Value::Name("pcss"),
    ],
    sweep_with: &[],
};

/// `shadow-mask`: Where the sun's shadows are filtered: half (a mask pass at half resolution, upsampled by depth), full (a mask pass per pixel), off (in the lighting pass's light loop).
pub static SHADOW_MASK: Knob = Knob {
    name: "shadow-mask",
    path: "shadow_mask",
    group: Group::SHADOWS,
    doc: "Where the sun's shadows are filtered: half (a mask pass at half resolution, upsampled by depth), full (a mask pass per pixel), off (in the lighting pass's light loop)",
    kind: Kind::Choice(ShadowMask::NAMES),
    default: Value::Name("half"),
    passes: &[PassId::ShadowMask, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Name("off"), Value::Name("full")],
    sweep_with: &[],
};

/// `light-shadows`: Which lights cast shadows: scene (each light's own setting) or all (every light, as the path tracer sees them).
pub static LIGHT_SHADOWS: Knob = Knob {
    name: "light-shadows",
    path: "all_lights_cast_shadows",
    group: Group::SHADOWS,
    doc: "Which lights cast shadows: scene (each light's own setting) or all (every light, as the path tracer sees them)",
    kind: Kind::Switch {
        off: "scene",
        on: "all",
    },
    default: Value::Bool(false),
    passes: &[PassId::Shadow, PassId::Lighting],
    acts: Acts::FRAME.and(Acts::TRACE),
    sweep: &[Value::Bool(true)],
    sweep_with: &[],
};

/// `shadow-resolution-scale`: Multiplier of every light's shadow-map resolution.
pub static SHADOW_RESOLUTION_SCALE: Knob = Knob {
    name: "shadow-resolution-scale",
    path: "shadow_resolution_scale",
    group: Group::SHADOWS,
    doc: "Multiplier of every light's shadow-map resolution",
    kind: Kind::Float {
        min: 0.125,
        max: 4.0,
    },
    default: Value::Float(1.0),
    passes: &[PassId::Shadow],
    acts: Acts::FRAME,
    sweep: &[Value::Float(0.5), Value::Float(2.0)],
    sweep_with: &[],
};

/// `cascades`: Most cascades a directional light gets.
pub static CASCADES: Knob = Knob {
    name: "cascades",
    path: "max_cascades",
    group: Group::SHADOWS,
    doc: "Most cascades a directional light gets",
    kind: Kind::Int { min: 1, max: 4 },
    default: Value::Int(4),
    passes: &[PassId::Shadow, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Int(1), Value::Int(2)],
    sweep_with: &[],
};

/// `shadow-cache`: Keep the shadow atlas while no shadow view or caster changed; off draws it every frame (an exact optimisation).
pub static SHADOW_CACHE: Knob = Knob {
    name: "shadow-cache",
    path: "shadow_cache",
    group: Group::SHADOWS,
    doc: "Keep the shadow atlas while no shadow view or caster changed; off draws it every frame (an exact optimisation)",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::Shadow],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `visibility`: Specular visibility term: schlick-ggx, smith-correlated (two more square roots per light) or smith-correlated-fast.
pub static VISIBILITY: Knob = Knob {
    name: "visibility",
    path: "visibility",
    group: Group::SHADING,
    doc: "Specular visibility term: schlick-ggx, smith-correlated (two more square roots per light) or smith-correlated-fast",
    kind: Kind::Choice(VisibilityModel::NAMES),
    default: Value::Name("schlick-ggx"),
    passes: &[PassId::Lighting, PassId::Layers, PassId::Transparent],
    acts: Acts::FRAME.and(Acts::TRACE),
    sweep: &[
        Value::Name("smith-correlated"),
        Value::Name("smith-correlated-fast"),
    ],
    sweep_with: &[],
};

/// `energy-compensation`: Multiple-scattering energy compensation of the specular lobe (one table lookup per pixel).
pub static ENERGY_COMPENSATION: Knob = Knob {
    name: "energy-compensation",
    path: "energy_compensation",
    group: Group::SHADING,
    doc: "Multiple-scattering energy compensation of the specular lobe (one table lookup per pixel)",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::Lighting, PassId::Layers, PassId::Transparent],
    acts: Acts::FRAME.and(Acts::TRACE),
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `light-culling`: Tiled culling of unshadowed point and spot lights; off, every pixel loops over every light (an exact optimisation).
pub static LIGHT_CULLING: Knob = Knob {
    name: "light-culling",
    path: "light_culling",
    group: Group::SHADING,
    doc: "Tiled culling of unshadowed point and spot lights; off, every pixel loops over every light (an exact optimisation)",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::LightCulling, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `ibl-samples`: GGX samples per texel when prefiltering the environment.
pub static IBL_SAMPLES: Knob = Knob {
    name: "ibl-samples",
    path: "ibl_samples",
    group: Group::ENVIRONMENT,
    doc: "GGX samples per texel when prefiltering the environment",
    kind: Kind::Int { min: 1, max: 4096 },
    default: Value::Int(64),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[Value::Int(16), Value::Int(256)],
    sweep_with: &[],
};

/// `brdf-lut-size`: Side of the split-sum BRDF table in texels.
pub static BRDF_LUT_SIZE: Knob = Knob {
    name: "brdf-lut-size",
    path: "brdf_lut_size",
    group: Group::ENVIRONMENT,
    doc: "Side of the split-sum BRDF table in texels",
    kind: Kind::Int { min: 8, max: 512 },
    default: Value::Int(64),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[Value::Int(32)],
    sweep_with: &[],
};

/// `brdf-lut-samples`: Samples per texel of the split-sum BRDF table.
pub static BRDF_LUT_SAMPLES: Knob = Knob {
    name: "brdf-lut-samples",
    path: "brdf_lut_samples",
    group: Group::ENVIRONMENT,
    doc: "Samples per texel of the split-sum BRDF table",
    kind: Kind::Int { min: 1, max: 65536 },
    default: Value::Int(512),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `ao`: Screen-space ambient occlusion on indirect light: off, half or full resolution.
pub static AO: Knob = Knob {
    name: "ao",
    path: "ao.resolution",
    group: Group::INDIRECT,
    doc: "Screen-space ambient occlusion on indirect light: off, half or full resolution",
    kind: Kind::Choice(AoResolution::NAMES),
    default: Value::Name("half"),
    passes: &[PassId::AmbientOcclusion, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Name("off"), Value::Name("full")],
    sweep_with: &[],
};

/// `ao-slices`: AO slices (screen directions) per pixel; each costs 2 × steps depth reads.
pub static AO_SLICES: Knob = Knob {
    name: "ao-slices",
    path: "ao.slices",
    group: Group::INDIRECT,
    doc: "AO slices (screen directions) per pixel; each costs 2 × steps depth reads",
    kind: Kind::Int { min: 1, max: 8 },
    default: Value::Int(3),
    passes: &[PassId::AmbientOcclusion],
    acts: Acts::FRAME,
    sweep: &[Value::Int(1), Value::Int(6)],
    sweep_with: &[],
};

/// `ao-steps`: AO depth samples per side of a slice.
pub static AO_STEPS: Knob = Knob {
    name: "ao-steps",
    path: "ao.steps",
    group: Group::INDIRECT,
    doc: "AO depth samples per side of a slice",
    kind: Kind::Int { min: 1, max: 32 },
    default: Value::Int(6),
    passes: &[PassId::AmbientOcclusion],
    acts: Acts::FRAME,
    sweep: &[Value::Int(3), Value::Int(12)],
    sweep_with: &[],
};

/// `ao-radius`: AO radius in metres: geometry farther than this does not occlude.
pub static AO_RADIUS: Knob = Knob {
    name: "ao-radius",
    path: "ao.radius_m",
    group: Group::INDIRECT,
    doc: "AO radius in metres: geometry farther than this does not occlude",
    kind: Kind::Float {
        min: 0.001,
        max: 1000.0,
    },
    default: Value::Float(1.0),
    passes: &[PassId::AmbientOcclusion],
    acts: Acts::FRAME.and(Acts::TRACE),
    sweep: &[Value::Float(0.5), Value::Float(2.0)],
    sweep_with: &[],
};

/// `ao-denoise`: A 4×4 depth-aware filter over the AO; off, each pixel keeps its own noisy estimate.
pub static AO_DENOISE: Knob = Knob {
    name: "ao-denoise",
    path: "ao.denoise",
    group: Group::INDIRECT,
    doc: "A 4×4 depth-aware filter over the AO; off, each pixel keeps its own noisy estimate",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::AmbientOcclusion],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `ao-multi-bounce`: Multiple-bounce AO: bright surfaces are occluded less than dark ones.
pub static AO_MULTI_BOUNCE: Knob = Knob {
    name: "ao-multi-bounce",
    path: "ao.multi_bounce",
    group: Group::INDIRECT,
    doc: "Multiple-bounce AO: bright surfaces are occluded less than dark ones",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `ssr`: Screen-space reflections; off, smooth surfaces reflect only the environment and probes.
pub static SSR: Knob = Knob {
    name: "ssr",
    path: "ssr.enabled",
    group: Group::INDIRECT,
    doc: "Screen-space reflections; off, smooth surfaces reflect only the environment and probes",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::DepthPyramid, PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `ssr-max-roughness`: Roughest surface (perceptual roughness) that gets traced reflections.
pub static SSR_MAX_ROUGHNESS: Knob = Knob {
    name: "ssr-max-roughness",
    path: "ssr.max_roughness",
    group: Group::INDIRECT,
    doc: "Roughest surface (perceptual roughness) that gets traced reflections",
    kind: Kind::Float { min: 0.0, max: 1.0 },
    default: Value::Float(0.35),
    passes: &[PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[Value::Float(0.25), Value::Float(0.8)],
    sweep_with: &[],
};

/// `ssr-rays`: Reflection rays per pixel.
pub static SSR_RAYS: Knob = Knob {
    name: "ssr-rays",
    path: "ssr.rays",
    group: Group::INDIRECT,
    doc: "Reflection rays per pixel",
    kind: Kind::Int { min: 1, max: 16 },
    default: Value::Int(1),
    passes: &[PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[Value::Int(1), Value::Int(8)],
    sweep_with: &[],
};

/// `ssr-steps`: Iterations per reflection ray over the depth pyramid.
pub static SSR_STEPS: Knob = Knob {
    name: "ssr-steps",
    path: "ssr.steps",
    group: Group::INDIRECT,
    doc: "Iterations per reflection ray over the depth pyramid",
    kind: Kind::Int { min: 8, max: 256 },
    default: Value::Int(32),
    passes: &[PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[Value::Int(16)],
    sweep_with: &[],
};

/// `ssr-thickness`: How far (m) behind a surface a reflection ray may pass and still hit it.
pub static SSR_THICKNESS: Knob = Knob {
    name: "ssr-thickness",
    path: "ssr.thickness_m",
    group: Group::INDIRECT,
    doc: "How far (m) behind a surface a reflection ray may pass and still hit it",
    kind: Kind::Float {
        min: 0.001,
        max: 100.0,
    },
    default: Value::Float(0.3),
    passes: &[PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `ssr-resolution`: Where reflections are traced: half (one pixel per 2×2 block) or full.
pub static SSR_RESOLUTION: Knob = Knob {
    name: "ssr-resolution",
    path: "ssr.half_resolution",
    group: Group::INDIRECT,
    doc: "Where reflections are traced: half (one pixel per 2×2 block) or full",
    kind: Kind::Switch {
        off: "full",
        on: "half",
    },
    default: Value::Bool(true),
    passes: &[PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `gi`: Diffuse global illumination from an irradiance volume of probes.
pub static GI: Knob = Knob {
    name: "gi",
    path: "gi.enabled",
    group: Group::INDIRECT,
    doc: "Diffuse global illumination from an irradiance volume of probes",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::VolumeIrradiance, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `gi-density`: Probes along the longest side of an irradiance volume without its own spacing.
pub static GI_DENSITY: Knob = Knob {
    name: "gi-density",
    path: "gi.density",
    group: Group::INDIRECT,
    doc: "Probes along the longest side of an irradiance volume without its own spacing",
    kind: Kind::Int { min: 1, max: 16 },
    default: Value::Int(4),
    passes: &[PassId::VolumeIrradiance, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Int(2), Value::Int(8)],
    sweep_with: &[],
};

/// `gi-face`: Side in pixels of each cube face a probe captures.
pub static GI_FACE: Knob = Knob {
    name: "gi-face",
    path: "gi.face_size",
    group: Group::INDIRECT,
    doc: "Side in pixels of each cube face a probe captures",
    kind: Kind::Int { min: 4, max: 64 },
    default: Value::Int(32),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[Value::Int(8), Value::Int(16)],
    sweep_with: &[],
};

/// `gi-bounces`: Capture passes of the irradiance volume, one bounce each.
pub static GI_BOUNCES: Knob = Knob {
    name: "gi-bounces",
    path: "gi.bounces",
    group: Group::INDIRECT,
    doc: "Capture passes of the irradiance volume, one bounce each",
    kind: Kind::Int { min: 1, max: 4 },
    default: Value::Int(3),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[Value::Int(2), Value::Int(4)],
    sweep_with: &[],
};

/// `gi-resolution`: Where the irradiance volume is looked up: half (once per 2×2 pixels, upsampled by depth) or full (per pixel).
pub static GI_RESOLUTION: Knob = Knob {
    name: "gi-resolution",
    path: "gi.half_resolution",
    group: Group::INDIRECT,
    doc: "Where the irradiance volume is looked up: half (once per 2×2 pixels, upsampled by depth) or full (per pixel)",
    kind: Kind::Switch {
        off: "full",
        on: "half",
    },
    default: Value::Bool(true),
    passes: &[PassId::VolumeIrradiance, PassId::Lighting],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `gi-budget`: Probes captured per frame in view and bench while the volume converges (0: all at once).
pub static GI_BUDGET: Knob = Knob {
    name: "gi-budget",
    path: "gi.probes_per_frame",
    group: Group::INDIRECT,
    doc: "Probes captured per frame in view and bench while the volume converges (0: all at once)",
    kind: Kind::Int { min: 0, max: 4096 },
    default: Value::Int(8),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `gi-auto`: Place an irradiance volume around all meshes when the scene has none.
pub static GI_AUTO: Knob = Knob {
    name: "gi-auto",
    path: "gi.auto_place",
    group: Group::INDIRECT,
    doc: "Place an irradiance volume around all meshes when the scene has none",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `reflection-probes`: Reflection probes: cube maps of the lit scene for reflections the environment cannot give.
pub static REFLECTION_PROBES: Knob = Knob {
    name: "reflection-probes",
    path: "reflection_probes.enabled",
    group: Group::INDIRECT,
    doc: "Reflection probes: cube maps of the lit scene for reflections the environment cannot give",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[PassId::Lighting, PassId::Reflections],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(false)],
    sweep_with: &[],
};

/// `reflection-probe-size`: Side in pixels of each cube face a reflection probe captures (rounded up to a power of two).
pub static REFLECTION_PROBE_SIZE: Knob = Knob {
    name: "reflection-probe-size",
    path: "reflection_probes.face_size",
    group: Group::INDIRECT,
    doc: "Side in pixels of each cube face a reflection probe captures (rounded up to a power of two)",
    kind: Kind::Int { min: 16, max: 256 },
    default: Value::Int(64),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[Value::Int(128)],
    sweep_with: &[],
};

/// `reflection-probes-auto`: Place a reflection probe among all meshes when the scene has none.
pub static REFLECTION_PROBES_AUTO: Knob = Knob {
    name: "reflection-probes-auto",
    path: "reflection_probes.auto_place",
    group: Group::INDIRECT,
    doc: "Place a reflection probe among all meshes when the scene has none",
    kind: Kind::ON_OFF,
    default: Value::Bool(true),
    passes: &[],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `aa`: Anti-aliasing: none, fxaa, smaa or taa.
pub static AA: Knob = Knob {
    name: "aa",
    path: "aa.method",
    group: Group::ANTI_ALIASING,
    doc: "Anti-aliasing: none, fxaa, smaa or taa",
    kind: Kind::Choice(AaMethod::NAMES),
    default: Value::Name("none"),
    passes: &[PassId::Fxaa, PassId::Smaa, PassId::Taa],
    acts: Acts::FRAME,
    sweep: &[
        Value::Name("none"),
        Value::Name("fxaa"),
        Value::Name("smaa"),
        Value::Name("taa"),
    ],
    sweep_with: &[],
};

/// `accumulate`: Average N renders, each with the camera jittered inside the pixel: the box-filtered pixel of the reference, for N frames' cost.
pub static ACCUMULATE: Knob = Knob {
    name: "accumulate",
    path: "aa.accumulate",
    group: Group::ANTI_ALIASING,
    doc: "Average N renders, each with the camera jittered inside the pixel: the box-filtered pixel of the reference, for N frames' cost",
    kind: Kind::Int { min: 1, max: 1024 },
    default: Value::Int(1),
    passes: &[PassId::Accumulate],
    acts: Acts::FRAME,
    sweep: &[Value::Int(4), Value::Int(16)],
    sweep_with: &[],
};

/// `specular-aa`: Geometric specular anti-aliasing: the normal's variation inside a pixel widens its roughness (less flicker).
pub static SPECULAR_AA: Knob = Knob {
    name: "specular-aa",
    path: "aa.specular.enabled",
    group: Group::ANTI_ALIASING,
    doc: "Geometric specular anti-aliasing: the normal's variation inside a pixel widens its roughness (less flicker)",
    kind: Kind::ON_OFF,
    default: Value::Bool(false),
    passes: &[PassId::GBuffer],
    acts: Acts::FRAME,
    sweep: &[Value::Bool(true)],
    sweep_with: &[],
};

/// `specular-aa-form`: Specular AA's kernel: 2021 (projected space) or 2019 (slope space, Filament's).
pub static SPECULAR_AA_FORM: Knob = Knob {
    name: "specular-aa-form",
    path: "aa.specular.form",
    group: Group::ANTI_ALIASING,
    doc: "Specular AA's kernel: 2021 (projected space) or 2019 (slope space, Filament's)",
    kind: Kind::Choice(SpecularAaForm::NAMES),
    default: Value::Name("2021"),
    passes: &[PassId::GBuffer],
    acts: Acts::FRAME,
    sweep: &[Value::Name("2019")],
    sweep_with: &[(&SPECULAR_AA, Value::Bool(true))],
};

/// `specular-aa-variance`: Specular AA's pixel filter variance σ² (form: the form's, 1/(2π) for 2021, 0.15 for 2019).
pub static SPECULAR_AA_VARIANCE: Knob = Knob {
    name: "specular-aa-variance",
    path: "aa.specular.variance",
    group: Group::ANTI_ALIASING,
    doc: "Specular AA's pixel filter variance σ² (form: the form's, 1/(2π) for 2021, 0.15 for 2019)",
    kind: Kind::OptionalFloat {
        none: "form",
        min: 0.0,
        max: 1.0,
    },
    default: Value::None,
    passes: &[PassId::GBuffer],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `specular-aa-threshold`: Specular AA's largest added α² κ (form: the form's, 0.18 for 2021, 0.2 for 2019).
pub static SPECULAR_AA_THRESHOLD: Knob = Knob {
    name: "specular-aa-threshold",
    path: "aa.specular.threshold",
    group: Group::ANTI_ALIASING,
    doc: "Specular AA's largest added α² κ (form: the form's, 0.18 for 2021, 0.2 for 2019)",
    kind: Kind::OptionalFloat {
        none: "form",
        min: 0.0,
        max: 1.0,
    },
    default: Value::None,
    passes: &[PassId::GBuffer],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `taa-sharpen`: Contrast-adaptive sharpening of TAA's output (0: none).
pub static TAA_SHARPEN: Knob = Knob {
    name: "taa-sharpen",
    path: "aa.taa_sharpen",
    group: Group::ANTI_ALIASING,
    doc: "Contrast-adaptive sharpening of TAA's output (0: none)",
    kind: Kind::Float { min: 0.0, max: 1.0 },
    default: Value::Float(0.0),
    passes: &[PassId::Taa],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `dof-rings`: Depth-of-field sample rings of every camera with DoF (camera: each camera's own).
pub static DOF_RINGS: Knob = Knob {
    name: "dof-rings",
    path: "dof_rings",
    group: Group::CAMERA,
    doc: "Depth-of-field sample rings of every camera with DoF (camera: each camera's own)",
    kind: Kind::OptionalInt {
        none: "camera",
        min: 1,
        max: 5,
    },
    default: Value::None,
    passes: &[PassId::Dof],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `hdr`: Precision of the HDR target: f16 or f32 (twice the bandwidth).
pub static HDR: Knob = Knob {
    name: "hdr",
    path: "hdr_precision",
    group: Group::CAMERA,
    doc: "Precision of the HDR target: f16 or f32 (twice the bandwidth)",
    kind: Kind::Choice(HdrPrecision::NAMES),
    default: Value::Name("f16"),
    passes: &[PassId::Lighting, PassId::Sky, PassId::Dof, PassId::Tonemap],
    acts: Acts::FRAME,
    sweep: &[Value::Name("f32")],
    sweep_with: &[],
};

/// `transparency`: How blended surfaces are composited: sorted (back to front) or weighted (weighted blended order-independent).
pub static TRANSPARENCY: Knob = Knob {
    name: "transparency",
    path: "transparency",
    group: Group::TRANSPARENCY,
    doc: "How blended surfaces are composited: sorted (back to front) or weighted (weighted blended order-independent)",
    kind: Kind::Choice(Transparency::NAMES),
    default: Value::Name("sorted"),
    passes: &[PassId::Transparent],
    acts: Acts::FRAME,
    sweep: &[],
    sweep_with: &[],
};

/// `max-texture-size`: Texture budget: the longest side in texels a loaded texture keeps; larger ones are downscaled with a warning.
pub static MAX_TEXTURE_SIZE: Knob = Knob {
    name: "max-texture-size",
    path: "max_texture_size",
    group: Group::RESOURCES,
    doc: "Texture budget: the longest side in texels a loaded texture keeps; larger ones are downscaled with a warning",
    kind: Kind::Int {
        min: 16,
        max: 16384,
    },
    default: Value::Int(4096),
    passes: &[],
    acts: Acts::LOAD,
    sweep: &[],
    sweep_with: &[],
};

/// Every built-in knob, in order of heading.
pub fn builtin() -> Knobs {
    BUILTIN.clone()
}

/// [`builtin`], checked once.
static BUILTIN: LazyLock<Knobs> = LazyLock::new(|| {
    Knobs::new(vec![
        &SHADOWS,
        &SHADOW_FILTER,
        &SHADOW_MASK,
        &LIGHT_SHADOWS,
        &SHADOW_RESOLUTION_SCALE,
        &CASCADES,
        &SHADOW_CACHE,
        &VISIBILITY,
        &ENERGY_COMPENSATION,
        &LIGHT_CULLING,
        &IBL_SAMPLES,
        &BRDF_LUT_SIZE,
        &BRDF_LUT_SAMPLES,
        &AO,
        &AO_SLICES,
        &AO_STEPS,
        &AO_RADIUS,
        &AO_DENOISE,
        &AO_MULTI_BOUNCE,
        &SSR,
        &SSR_MAX_ROUGHNESS,
        &SSR_RAYS,
        &SSR_STEPS,
        &SSR_THICKNESS,
        &SSR_RESOLUTION,
        &GI,
        &GI_DENSITY,
        &GI_FACE,
        &GI_BOUNCES,
        &GI_RESOLUTION,
        &GI_BUDGET,
        &GI_AUTO,
        &REFLECTION_PROBES,
        &REFLECTION_PROBE_SIZE,
        &REFLECTION_PROBES_AUTO,
        &AA,
        &ACCUMULATE,
        &SPECULAR_AA,
        &SPECULAR_AA_FORM,
        &SPECULAR_AA_VARIANCE,
        &SPECULAR_AA_THRESHOLD,
        &TAA_SHARPEN,
        &DOF_RINGS,
        &HDR,
        &TRANSPARENCY,
        &MAX_TEXTURE_SIZE,
    ])
    .unwrap_or_else(|e| panic!("the built-in knobs are inconsistent: {e}"))
});

/// The built-in knobs' defaults, applied once: [`Quality::default`].
static DEFAULT: LazyLock<Quality> = LazyLock::new(|| {
    let mut tree = toml::Table::new();
    for knob in builtin().iter() {
        super::knob::store_default(&mut tree, knob);
    }
    Quality::from_tree(tree)
        .unwrap_or_else(|e| panic!("the built-in knobs do not declare every field of Quality: {e}"))
});

impl Default for Knobs {
    /// The built-in knobs.
    fn default() -> Self {
        builtin()
    }
}

impl Default for Quality {
    /// Every built-in knob at its declared default (the `high` preset).
    fn default() -> Self {
        DEFAULT.clone()
    }
}

impl Default for AoSettings {
    /// The knobs' defaults.
    fn default() -> Self {
        Quality::default().ao
    }
}

impl Default for SsrSettings {
    /// The knobs' defaults.
    fn default() -> Self {
        Quality::default().ssr
    }
}

impl Default for SpecularAaSettings {
    /// The knobs' defaults.
    fn default() -> Self {
        Quality::default().aa.specular
    }
}

impl Default for AaSettings {
    /// The knobs' defaults.
    fn default() -> Self {
        Quality::default().aa
    }
}

impl Default for GiSettings {
    /// The knobs' defaults.
    fn default() -> Self {
        Quality::default().gi
    }
}

impl Default for ReflectionProbeSettings {
    /// The knobs' defaults.
    fn default() -> Self {
        Quality::default().reflection_probes
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quality::Quality;

    /// The dotted paths of every leaf of `tree`.
    fn leaves(tree: &toml::Table, prefix: &str, out: &mut Vec<String>) {
        for (key, value) in tree {
            let path = if prefix.is_empty() {
                key.clone()
            } else {
                format!("{prefix}.{key}")
            };
            match value {
                toml::Value::Table(t) => leaves(t, &path, out),
                _ => out.push(path),
            }
        }
    }

    #[test]
    fn every_field_of_quality_is_exactly_one_knob() {
        let knobs = builtin();
        // Optional knobs are absent from the tree while none: set each to a value first.
        let mut quality = Quality::default();
        for k in knobs.iter() {
            let some = match k.kind {
                Kind::OptionalInt { min, .. } => Value::Int(min),
                Kind::OptionalFloat { min, .. } => Value::Float(min),
                _ => continue,
            };
            k.set(&mut quality, some).expect("in range");
        }
        let mut fields = Vec::new();
        leaves(&quality.to_tree(), "", &mut fields);
        let mut paths: Vec<String> = knobs.iter().map(|k| k.path.to_string()).collect();
        fields.sort();
        paths.sort();
        assert_eq!(fields, paths, "fields of Quality against the knobs' paths");
    }

    #[test]
    fn every_knob_reads_back_what_it_sets_and_parses_what_it_prints() {
        let knobs = builtin();
        for k in knobs.iter() {
            assert_eq!(k.get(&Quality::default()), k.default, "{}", k.name);
            for &v in k.sweep.iter().chain([&k.default]) {
                let mut q = Quality::default();
                k.set(&mut q, v).expect("in range");
                assert_eq!(k.get(&q), v, "{} = {v:?}", k.name);
                assert_eq!(k.parse(&k.format(v)), Ok(v), "{}: {}", k.name, k.format(v));
                assert_eq!(k.from_toml(&k.to_toml(v)), Ok(v), "{}", k.name);
                // Only this knob moved.
                let moved: Vec<&str> = knobs
                    .differences(&Quality::default(), &q)
                    .iter()
                    .map(|(k, _)| k.name)
                    .collect();
                assert!(
                    moved.is_empty() || moved == [k.name],
                    "{}: {moved:?}",
                    k.name
                );
            }
        }
    }

    #[test]
    fn values_out_of_range_or_of_another_kind_are_refused() {
        assert!(AO_SLICES.parse("9").is_err());
        assert!(AO_SLICES.parse("three").is_err());
        assert_eq!(AO_SLICES.parse(" 8 "), Ok(Value::Int(8)));
        assert!(SSR_MAX_ROUGHNESS.parse("nan").is_err());
        assert!(SSR_MAX_ROUGHNESS.parse("1.5").is_err());
        assert_eq!(SSR.parse("OFF"), Ok(Value::Bool(false)));
        assert!(SSR.parse("maybe").is_err());
        assert_eq!(SSR_RESOLUTION.parse("full"), Ok(Value::Bool(false)));
        assert_eq!(AO.parse("Full"), Ok(Value::Name("full")));
        assert_eq!(DOF_RINGS.parse("camera"), Ok(Value::None));
        assert!(DOF_RINGS.parse("0").is_err());
        let err = AO.parse("quarter").expect_err("unknown");
        assert!(err.to_string().contains("off, half, full"), "{err}");
        let mut q = Quality::default();
        assert!(AO_STEPS.set(&mut q, Value::Int(33)).is_err());
        assert!(AO_STEPS.set(&mut q, Value::Bool(true)).is_err());
        assert_eq!(q, Quality::default(), "a refused value changes nothing");
    }

    #[test]
    fn a_registry_refuses_twins_and_bad_names() {
        static TWIN: Knob = Knob {
            name: "ao",
            path: "extensions.twin",
            ..DOF_RINGS_LIKE
        };
        static BAD_NAME: Knob = Knob {
            name: "Bad Name",
            path: "extensions.bad",
            ..DOF_RINGS_LIKE
        };
        static BAD_DEFAULT: Knob = Knob {
            name: "bad-default",
            path: "extensions.bad-default",
            default: Value::Int(9),
            ..DOF_RINGS_LIKE
        };
        const DOF_RINGS_LIKE: Knob = Knob {
            name: "",
            path: "",
            group: Group::CAMERA,
            doc: "test",
            kind: Kind::OptionalInt {
                none: "none",
                min: 1,
                max: 5,
            },
            default: Value::None,
            passes: &[],
            acts: Acts::FRAME,
            sweep: &[],
            sweep_with: &[],
        };
        assert!(builtin().with(&TWIN).is_err());
        assert!(builtin().with(&BAD_NAME).is_err());
        assert!(builtin().with(&BAD_DEFAULT).is_err());
    }
}

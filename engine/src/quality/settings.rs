//! The quality settings as typed fields: [`Quality`], its nested settings and the enums
//! its knobs choose from. Each field is one knob ([`super::knobs`]), whose declaration
//! gives its default ([`super::knobs`] implements `Default` from them).

use crate::choice::choices;
use crate::shading::brdf::VisibilityModel;
use bevy_ecs::prelude::Resource;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

choices! {
/// How shadow maps are filtered (README, "Shadows", for the measured cost of each).
/// The numeric values are the shader constant `SHADOW_FILTER`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowFilter: "shadow filter" {
    /// One comparison tap: the hardware's bilinear 2×2 percentage-closer filter.
    Hardware2x2(0) = "hardware",
    /// A 5×5-texel kernel ([1 3 4 3 1] per axis) read with 9 bilinear comparison taps,
    /// no noise (Castaño 2013's optimised PCF; [`crate::shading::shadow_kernel`]). The default: as
    /// accurate as [`ShadowFilter::Pcf`] against the path tracer at three quarters of its
    /// lighting cost (README, "Shadows").
    #[default]
    Tent(3) = "tent",
    /// 16 hardware 2×2 taps on a Poisson disc of radius 1.5 texels, rotated per pixel
    /// (Reeves et al. 1987, percentage-closer filtering).
    Pcf(1) = "pcf",
    /// Percentage-closer soft shadows (Fernando 2005): a 16-tap blocker search, then a
    /// 16-tap filter whose radius grows with the light's size and the distance between
    /// blocker and receiver (contact hardening).
    Pcss(2) = "pcss",
}
}

choices! {
/// Where the shadowed directional lights' visibility is resolved (README, "Shadows", for
/// the measured cost and error of each; [`crate::render::shadow::mask`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowMask: "shadow mask" {
    /// No mask pass: the lighting pass's light loop filters the shadow map per pixel.
    Off = "off",
    /// One filtered lookup per 2×2 pixels in the mask pass, upsampled by the lighting
    /// pass with depth-aware weights ([`crate::shading::shadow_kernel::shadow_mask_weight`]).
    #[default]
    Half = "half",
    /// One filtered lookup per pixel in the mask pass: the same visibility as `off`.
    Full = "full",
}
}

impl ShadowMask {
    /// Pixels per mask texel along each axis (0 when off).
    pub fn scale(self) -> u32 {
        match self {
            ShadowMask::Off => 0,
            ShadowMask::Half => 2,
            ShadowMask::Full => 1,
        }
    }
}

choices! {
/// Where screen-space ambient occlusion is computed (README, "Indirect light", for the
/// measured cost of each).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AoResolution: "AO resolution" {
    /// No ambient-occlusion pass: indirect light sees only the materials' occlusion.
    Off = "off",
    /// One AO sample per 2×2 pixels, upsampled by the depth-aware resolve.
    #[default]
    Half = "half",
    /// One AO sample per pixel.
    Full = "full",
}
}

impl AoResolution {
    /// Full-resolution pixels per AO sample along each axis (0 when off).
    pub fn scale(self) -> u32 {
        match self {
            AoResolution::Off => 0,
            AoResolution::Half => 2,
            AoResolution::Full => 1,
        }
    }
}

/// Screen-space ambient occlusion (GTAO, [`crate::shading::ambient_occlusion`]): it darkens
/// environment light (and probe light) where the depth buffer shows nearby geometry;
/// direct lights are never occluded by it. It runs only when the frame has indirect light
/// to occlude.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AoSettings {
    /// Off, half or full resolution.
    pub resolution: AoResolution,
    /// Slices (screen directions) per pixel, 1..=8; each costs `2 × steps` depth reads.
    pub slices: u32,
    /// Depth samples per side of a slice, 1..=32.
    pub steps: u32,
    /// World-space radius in metres within which geometry occludes (with the falloff of
    /// [`crate::shading::ambient_occlusion::ao_falloff`]).
    pub radius_m: f32,
    /// A 4×4 depth-aware spatial filter that averages the 16 slice rotations of the
    /// per-pixel noise; off, each pixel keeps its own noisy estimate.
    pub denoise: bool,
    /// The multiple-bounce fit brightens occlusion on bright surfaces (Jimenez et al.
    /// 2016); off, the single-bounce visibility darkens them as much as dark ones.
    pub multi_bounce: bool,
}

/// Screen-space reflections ([`crate::render::indirect::reflections`]): the lit frame
/// seen in smooth surfaces, traced over a hierarchical depth pyramid. Where a ray misses
/// or leaves the screen, the environment's reflection stays.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SsrSettings {
    /// On or off.
    pub enabled: bool,
    /// Surfaces rougher than this (perceptual roughness) get no traced reflection; the
    /// reflection fades out over the last quarter below it.
    pub max_roughness: f32,
    /// Rays per pixel, 1..=16, importance-sampled from the GGX visible normals.
    pub rays: u32,
    /// Iterations per ray of the hierarchical trace, 8..=256.
    pub steps: u32,
    /// How far behind a surface in the depth buffer (m) a ray may pass and still count as
    /// hitting it.
    pub thickness_m: f32,
    /// Trace one pixel per 2×2 block and give its reflection to the block's pixels on the
    /// same surface (else every pixel traces its own).
    pub half_resolution: bool,
}

/// The renderer's quality settings. Every field is a [`crate::quality::Knob`] (the built-in ones are
/// in [`crate::quality::knobs`]); its default is the knob's, which is the `high` preset.
#[derive(Resource, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quality {
    /// Visibility (geometric) term of the specular lobe. `schlick-ggx` (the seeds',
    /// default) and `smith-correlated-fast` cost the same; `smith-correlated` adds two
    /// square roots per light and pixel.
    pub visibility: VisibilityModel,
    /// Shadows on or off for the whole frame; off skips the shadow pass.
    pub shadows: bool,
    /// Shadow filtering.
    pub shadow_filter: ShadowFilter,
    /// Where the shadowed directional lights' visibility is resolved.
    pub shadow_mask: ShadowMask,
    /// Every light casts shadows, whatever its own `cast_shadows` says: the frame then has
    /// the physical visibility the path tracer has. Each point light adds six shadow views
    /// (one cube) and each spot light one, plus their shadowed loop in the lighting pass.
    /// No preset turns it on yet: until the frame has bounce light, unshadowed lights
    /// below a floor stand in for the light the floor would bounce, and shadowing them
    /// raises the error against the full reference (docs/src/indirect.md).
    pub all_lights_cast_shadows: bool,
    /// Multiple-scattering energy compensation of the specular lobe (Kulla & Conty 2017),
    /// for environment and direct light. On: metals and rough surfaces keep their energy
    /// (the white furnace holds); costs one table lookup per pixel.
    pub energy_compensation: bool,
    /// GGX samples per texel when prefiltering an environment (once per image).
    pub ibl_samples: u32,
    /// Side of the split-sum BRDF table in texels (built once).
    pub brdf_lut_size: u32,
    /// Samples per texel of the split-sum BRDF table.
    pub brdf_lut_samples: u32,
    /// Multiplies every light's shadow-map resolution (`ShadowSettings::resolution`);
    /// the result is clamped to 64..=8192 texels.
    pub shadow_resolution_scale: f32,
    /// Most cascades any directional light gets (1..=4), whatever its `Cascades` asks.
    pub max_cascades: u32,
    /// Depth-of-field sample rings for every camera with DoF (1..=5); `None` keeps each
    /// camera's own `DepthOfField::rings`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dof_rings: Option<u32>,
    /// Precision of the HDR target that lighting, sky and DoF write and tone mapping
    /// reads.
    pub hdr_precision: HdrPrecision,
    /// Tiled light culling for scenes with many unshadowed point and spot lights (an
    /// exact optimisation: a light is skipped only where its range window is 0).
    pub light_culling: bool,
    /// The shadow atlas is drawn again only when its views or casters changed (an exact
    /// optimisation: equal views and casters draw an equal atlas). Off, it is drawn every
    /// frame, as to measure what drawing costs.
    pub shadow_cache: bool,
    /// Texture budget: the longest side, in texels, a texture keeps when it is loaded
    /// (larger ones are downscaled with a warning; the device's own limit applies too).
    pub max_texture_size: u32,
    /// Screen-space ambient occlusion.
    pub ao: AoSettings,
    /// Screen-space reflections.
    pub ssr: SsrSettings,
    /// Diffuse global illumination from an irradiance volume.
    pub gi: GiSettings,
    /// Reflection probes.
    pub reflection_probes: ReflectionProbeSettings,
    /// Anti-aliasing: geometric specular AA, post-process AA and accumulation.
    pub aa: AaSettings,
    /// How blended surfaces are composited.
    pub transparency: Transparency,
    /// The values of knobs that scripts and plugins register ([`crate::quality::Knobs::with`]), by knob
    /// name: a knob whose path is `extensions.NAME` lives here, and reads its default
    /// while it is absent.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub extensions: BTreeMap<String, toml::Value>,
}

impl Quality {
    /// The settings as a TOML tree of their serde form (the tree a [`crate::quality::Knob::path`] names
    /// a field of).
    pub fn to_tree(&self) -> toml::Table {
        toml::Table::try_from(self)
            .unwrap_or_else(|e| panic!("the quality settings have no TOML form: {e}"))
    }

    /// The settings a TOML tree of their serde form describes.
    pub fn from_tree(tree: toml::Table) -> Result<Quality, toml::de::Error> {
        Quality::deserialize(toml::Value::Table(tree))
    }
}

choices! {
/// How the transparent pass composites blended surfaces (docs/src/materials.md#blending).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Transparency: "transparency" {
    /// Sorted back to front per primitive and composited with "over": exact where the
    /// primitives do not interleave in depth.
    #[default]
    Sorted = "sorted",
    /// Weighted blended order-independent transparency (McGuire & Bavoil 2013): every
    /// blended fragment is accumulated in any order, weighted by its coverage and depth,
    /// then resolved once. No sort and no order artefacts where primitives interleave;
    /// the colour of overlapping layers is a weighted average, not the exact "over".
    WeightedBlended = "weighted",
}
}

choices! {
/// Which anti-aliasing filter runs on each finished frame (docs/src/antialiasing.md for
/// the measured cost and error of each).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AaMethod: "anti-aliasing" {
    /// No post-process anti-aliasing: every pixel is its centre's sample.
    #[default]
    None = "none",
    /// Fast approximate anti-aliasing (Lottes 2009): one full-screen pass that finds
    /// luminance edges and blends each edge pixel with its neighbour across the edge.
    Fxaa = "fxaa",
    /// Subpixel morphological anti-aliasing (Jimenez et al. 2012, SMAA 1x): edges found
    /// from luma, followed to their ends, and each edge pixel blended with its neighbour
    /// by the coverage of the silhouette's revectorized line.
    Smaa = "smaa",
    /// Temporal anti-aliasing (Karis 2014; Salvi 2016): every frame is jittered inside
    /// the pixel, and the history of earlier frames, reprojected by motion vectors and
    /// clipped to the current neighbourhood's colour range, is blended in.
    Taa = "taa",
}
}

/// Geometric specular anti-aliasing in the G-buffer pass
/// ([`crate::shading::brdf::specular_aa_roughness`]): where the normal varies across a pixel, the
/// stored roughness widens so the GGX lobe covers the normals the pixel sees, and a
/// highlight smaller than the pixel is spread over it instead of hit or missed. It calms
/// flicker (2.45× less on a turning bump-mapped sphere) but widens still highlights beyond
/// the pixel's footprint, which raises the error against the reference: off in every
/// preset (docs/src/antialiasing.md).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpecularAaSettings {
    /// On or off. Off, the G-buffer stores each material's roughness as it is.
    pub enabled: bool,
    /// The form of the filter kernel.
    pub form: SpecularAaForm,
    /// σ², the variance of the pixel filter, which scales the screen-space variation of
    /// the normal (dimensionless); `None` takes the form's default (1/(2π) for 2021,
    /// Filament's 0.15 for 2019).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub variance: Option<f32>,
    /// κ, the largest α² the filter may add (dimensionless); `None` takes the form's
    /// default (0.18 for 2021, 0.2 for 2019).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f32>,
}

impl SpecularAaSettings {
    /// σ²: the one set, else the form's default.
    pub fn variance(&self) -> f32 {
        self.variance
            .unwrap_or_else(|| self.form.default_variance())
    }

    /// κ: the one set, else the form's default.
    pub fn threshold(&self) -> f32 {
        self.threshold
            .unwrap_or_else(|| self.form.default_threshold())
    }

    /// The α² the kernel adds per unit of the normal's screen-space variation (the
    /// `screen_scale` of [`crate::shading::brdf::specular_aa_roughness`]): c · σ².
    pub fn screen_scale(&self) -> f32 {
        self.form.kernel_factor() * self.variance()
    }
}

choices! {
/// The isotropic kernel of geometric specular anti-aliasing for a deferred renderer
/// (Tokuyoshi & Kaplanyan). Both widen α² by the screen-space variation of the normal
/// times the pixel filter's variance σ²; they differ in the space the NDF is filtered in,
/// which sets the factor c (docs/src/antialiasing.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpecularAaForm: "specular AA form" {
    /// 2019, "Improved Geometric Specular Antialiasing": filtered in the slope space of
    /// the half vector, α²_k = 2σ²|∂n|² (Filament's form; σ² 0.15, κ 0.2).
    Slope2019 = "2019",
    /// 2021, "Stable Geometric Specular Antialiasing with Projected-Space NDF Filtering",
    /// eq. 14: filtered in the projected space of the half vector, α²_k = σ²|∂n|²
    /// (σ² = 1/(2π), the paper's pixel filter variance; κ 0.18). The default: it calms
    /// flicker as much as 2019's (2.40× against 2.45× on a turning bump-mapped sphere) with
    /// less error on still frames (docs/src/antialiasing.md).
    #[default]
    Projected2021 = "2021",
}
}

impl SpecularAaForm {
    /// c: the α² per unit of σ²|∂n|² (2 in slope space, 1 in projected space).
    pub fn kernel_factor(self) -> f32 {
        match self {
            SpecularAaForm::Slope2019 => 2.0,
            SpecularAaForm::Projected2021 => 1.0,
        }
    }

    /// The paper's (or Filament's) pixel filter variance σ².
    pub fn default_variance(self) -> f32 {
        match self {
            SpecularAaForm::Slope2019 => 0.15,
            SpecularAaForm::Projected2021 => 1.0 / std::f32::consts::TAU,
        }
    }

    /// The paper's (or Filament's) threshold κ.
    pub fn default_threshold(self) -> f32 {
        match self {
            SpecularAaForm::Slope2019 => 0.2,
            SpecularAaForm::Projected2021 => 0.18,
        }
    }
}

/// Most jittered renders one image may average (the `accumulate` knob).
pub const MAX_ACCUMULATE: u32 = 1024;

/// Anti-aliasing settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AaSettings {
    /// The post-process filter.
    pub method: AaMethod,
    /// Frames averaged per rendered image, 1..=1024: each is rendered with the camera
    /// jittered inside the pixel (Halton 2, 3), and their average is the box-filtered
    /// pixel the path-traced reference computes. 1 renders one centred frame.
    pub accumulate: u32,
    /// Geometric specular anti-aliasing.
    pub specular: SpecularAaSettings,
    /// Strength of the contrast-adaptive sharpening applied to TAA's output, 0..=1
    /// (Lottes 2019; dimensionless). 0, the default, shows the history as it is: the
    /// converged still image is then the box-filtered pixel of the reference, which
    /// sharpening moves away from.
    pub taa_sharpen: f32,
}

impl AaSettings {
    /// Whether temporal anti-aliasing runs: TAA without accumulation (which already
    /// filters every pixel, so TAA, its motion vectors and its history stay off).
    pub fn temporal(&self) -> bool {
        self.method == AaMethod::Taa && self.accumulate <= 1
    }
}

/// Diffuse global illumination from an irradiance volume
/// ([`crate::render::indirect::probe_volume`]): probes on a grid capture the lit
/// scene around them, and every point inside the grid takes its diffuse indirect light
/// from them. Each capture pass renders six low-resolution views per probe through the
/// frame's own shadow, G-buffer and lighting passes; the lighting of a pass includes the
/// probe light of the one before, so each pass adds one bounce.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GiSettings {
    /// On or off. Off, no probe is placed or captured and environment irradiance stays.
    pub enabled: bool,
    /// Probes along the longest side of a volume that gives no spacing of its own (the
    /// automatic one, or an [`crate::scene::IrradianceVolume`] with `spacing_m: None`),
    /// 1..=16.
    pub density: u32,
    /// Side of each captured cube face, in pixels, 4..=64.
    pub face_size: u32,
    /// Capture passes, 1..=4: the first brings light that bounced once (and the
    /// environment, occluded); each further pass one bounce more.
    pub bounces: u32,
    /// Probes captured per frame while the volume converges in the viewer and `bench`
    /// (0: all of them at once). A still render always converges before its frame.
    pub probes_per_frame: u32,
    /// Place a volume around all meshes when the scene has no
    /// [`crate::scene::IrradianceVolume`]; off, only the scene's own volume is used.
    pub auto_place: bool,
    /// Look the volume up once per 2×2 pixels in its own pass, which the lighting pass
    /// upsamples by depth ([`crate::render::indirect::volume_irradiance`]); off, the
    /// lighting pass looks it up per pixel.
    pub half_resolution: bool,
}

/// Reflection probes ([`crate::render::indirect::reflection_probes`]): cube maps of the lit
/// scene captured through the frame's own passes and prefiltered like an environment, for
/// the specular reflections the environment cannot give (the floor in a metal sphere).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReflectionProbeSettings {
    /// On or off. Off, no probe is placed or captured.
    pub enabled: bool,
    /// Side of each captured cube face, in pixels, 16..=256 (a power of two).
    pub face_size: u32,
    /// Place a probe among all meshes when the scene has no
    /// [`crate::scene::ReflectionProbe`]; off, only the scene's own probes are used.
    pub auto_place: bool,
}

choices! {
/// Format of the exposed HDR target.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HdrPrecision: "HDR precision" {
    /// `Rgba16Float`: 11 significant bits (relative step 2⁻¹¹), values up to 65504.
    /// Pre-exposure keeps a frame inside that range.
    #[default]
    Half = "f16",
    /// `Rgba32Float`: 24 significant bits; twice the bandwidth of every pass that writes
    /// or reads the target.
    Full = "f32",
}
}

impl HdrPrecision {
    /// The target's texture format.
    pub fn format(self) -> wgpu::TextureFormat {
        match self {
            HdrPrecision::Half => wgpu::TextureFormat::Rgba16Float,
            HdrPrecision::Full => wgpu::TextureFormat::Rgba32Float,
        }
    }
}

choices! {
/// Named sets of every knob, cheapest first, each a TOML file ([`crate::quality::preset`]). `High` is
/// [`Quality::default`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum QualityPreset: "quality preset" {
    /// Hardware 2×2 shadow filtering at half resolution with one cascade, no energy
    /// compensation, 16-sample IBL prefiltering, one DoF ring, no ambient occlusion,
    /// reflections, irradiance volume or reflection probes.
    Low = "low",
    /// The `tent` filter (half-resolution mask) with two cascades, energy compensation, 32 IBL
    /// samples, two DoF rings, half-resolution AO of 2 slices × 4 steps, a coarse
    /// one-bounce irradiance volume.
    Medium = "medium",
    /// The defaults: the `tent` filter, resolved for the sun in a half-resolution shadow
    /// mask, up to four cascades, 64 IBL samples, the camera's rings, half-resolution AO
    /// of 3 slices × 6 steps.
    #[default]
    High = "high",
    /// PCSS at twice the resolution in the light loop (no shadow mask), height-correlated
    /// Smith visibility, 256 IBL samples, a 128² BRDF table of 1024 samples, five DoF
    /// rings, an f32 HDR target, full-resolution AO of 4 slices × 8 steps and temporal
    /// anti-aliasing.
    Ultra = "ultra",
}
}

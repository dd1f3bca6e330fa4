//! Command-line arguments of `lumen`.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Lumen: a physically based deferred renderer.
#[derive(Parser, Debug)]
#[command(name = "lumen", version, about, long_about = None)]
pub struct Cli {
    /// What to do; without one, show the `showcase` scene in a window when a display is
    /// available, else render it to out/showcase.png.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Without a subcommand: render to out/showcase.png even when a display is available.
    #[arg(long)]
    pub headless: bool,
}

/// Subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render one frame to a PNG (display image) or EXR (linear HDR) file.
    Render(RenderArgs),
    /// Open the viewer: orbit and fly cameras, a panel with timings, knobs and debug
    /// views, screenshots, drag and drop, and shader hot reload.
    View(ViewArgs),
    /// Measure frame times: per pass (GPU) and per stage (CPU), with statistics.
    Bench(BenchArgs),
    /// Path-trace the ground truth of a scene on the CPU (linear EXR, comparable with
    /// `render --out F.exr`).
    Reference(ReferenceArgs),
    /// Time every preset and every quality knob, and measure each image's error against
    /// the path-traced reference.
    Tradeoff(TradeoffArgs),
    /// Merge the parts of a sharded reference, tradeoff or sequence (`--shard I/N`) into
    /// one image, table or frame manifest, after checking that they are every shard of one
    /// render.
    Merge(MergeArgs),
    /// Check PBR textures against the measured ranges (seed 001's rules): a glTF file's
    /// materials or texture files by role. Exit status 3 when any texel fails.
    Validate(ValidateArgs),
    /// Convert textures between metal/roughness and specular/glossiness (and glossiness ↔
    /// roughness), fix base colours into range (--safe-color), or convert an IOR or a
    /// specular level to F0.
    Convert(ConvertArgs),
    /// List the built-in scenes.
    Scenes,
}

/// Texture files by role (`validate` and `convert`).
#[derive(Args, Debug, Clone, Default)]
pub struct TextureRoles {
    /// Base colour (sRGB).
    #[arg(long, value_name = "FILE")]
    pub base_color: Option<PathBuf>,
    /// Metallic (linear, first channel).
    #[arg(long, value_name = "FILE")]
    pub metallic: Option<PathBuf>,
    /// Roughness (linear, first channel).
    #[arg(long, value_name = "FILE")]
    pub roughness: Option<PathBuf>,
    /// Packed occlusion (red), roughness (green) and metallic (blue), as glTF packs them.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["metallic", "roughness"])]
    pub orm: Option<PathBuf>,
    /// Diffuse (sRGB).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["base_color", "metallic", "orm"])]
    pub diffuse: Option<PathBuf>,
    /// Specular (sRGB; F0 per channel).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["base_color", "metallic", "orm"])]
    pub specular: Option<PathBuf>,
    /// Glossiness (linear, first channel; 1 − roughness).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["roughness", "orm"])]
    pub glossiness: Option<PathBuf>,
}

/// Arguments of `lumen validate`.
#[derive(Args, Debug, Clone)]
pub struct ValidateArgs {
    /// glTF files: every material in each.
    #[arg(value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Or one material's texture files by role.
    #[command(flatten)]
    pub textures: TextureRoles,
    /// The strict dark floor for dielectric colours: 50 sRGB instead of 30.
    #[arg(long)]
    pub strict: bool,
    /// Write heat maps (red invalid, yellow borderline, green valid, grey not checked)
    /// into this folder: one per material and one per material and rule.
    #[arg(long, value_name = "DIR")]
    pub heatmap: Option<PathBuf>,
    /// Write the report as JSON (schema lumen-validate/1) to this file ("-": standard
    /// output).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// What `lumen convert` produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConvertTarget {
    /// base_color.png, metallic.png, roughness.png.
    MetalRough,
    /// diffuse.png, specular.png, glossiness.png.
    SpecGloss,
    /// A roughness map from a glossiness map.
    Roughness,
    /// A glossiness map from a roughness map.
    Glossiness,
}

fn parse_convert_target(s: &str) -> Result<ConvertTarget, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "metal-rough" | "metal-roughness" => Ok(ConvertTarget::MetalRough),
        "spec-gloss" | "specular-glossiness" => Ok(ConvertTarget::SpecGloss),
        "roughness" => Ok(ConvertTarget::Roughness),
        "glossiness" => Ok(ConvertTarget::Glossiness),
        _ => Err(format!(
            "unknown target '{s}': expected metal-rough, spec-gloss, roughness or glossiness"
        )),
    }
}

/// Arguments of `lumen convert`.
#[derive(Args, Debug, Clone)]
pub struct ConvertArgs {
    /// A glTF file: every material is converted, into a folder per material.
    #[arg(value_name = "FILE")]
    pub file: Option<PathBuf>,
    /// Or one material's texture files by role.
    #[command(flatten)]
    pub textures: TextureRoles,
    /// What to write: metal-rough, spec-gloss, roughness (from --glossiness) or
    /// glossiness (from --roughness).
    #[arg(long, value_name = "TARGET", value_parser = parse_convert_target)]
    pub to: Option<ConvertTarget>,
    /// Output folder (default `out/converted`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Clamp base (or diffuse) colours into the valid range first, and say how many
    /// texels changed.
    #[arg(long)]
    pub safe_color: bool,
    /// With --safe-color: the strict dark floor (50 sRGB).
    #[arg(long)]
    pub strict: bool,
    /// Print the F0 of a dielectric of this index of refraction (1..=3).
    #[arg(long, value_name = "N", value_parser = parse_ior)]
    pub ior: Option<f32>,
    /// Print the F0 of this specular level (0..=1; 0.5 gives 0.04).
    #[arg(long, value_name = "L", value_parser = parse_unit)]
    pub specular_level: Option<f32>,
}

fn parse_ior(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number"))?;
    if (1.0..=3.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v} is out of range: an IOR is 1..=3"))
    }
}

/// What to render and how to expose it (shared by `render` and `view`).
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Built-in scene (see `lumen scenes`).
    #[arg(long, value_name = "NAME", conflicts_with = "file")]
    pub scene: Option<String>,
    /// A glTF 2.0 file (.gltf or .glb), or the name of a built-in scene.
    #[arg(value_name = "FILE|SCENE")]
    pub file: Option<PathBuf>,
    /// Pose an animated glTF file at this time of its first clip, in seconds (wrapped
    /// into the clip), and hold it there; without it the clip plays from 0 s.
    #[arg(long, value_name = "SECONDS", value_parser = parse_non_negative)]
    pub time: Option<f32>,
    /// Number of point lights of the `lights` scene (0..=65536, default 256).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=65536))]
    pub lights: Option<u32>,
    /// Exposure value at ISO 100 (−10..30); replaces the camera's.
    #[arg(long, value_name = "X", allow_hyphen_values = true, value_parser = parse_ev100)]
    pub ev100: Option<f32>,
    /// Linear exposure multiplier that replaces the camera's (1 = raw radiance).
    #[arg(long, value_name = "K", conflicts_with = "ev100", value_parser = parse_exposure)]
    pub exposure: Option<f32>,
    /// Aperture f-number (0.5..64); with --shutter and --iso the exposure follows the lens.
    #[arg(long, value_name = "N", value_parser = parse_positive)]
    pub aperture: Option<f32>,
    /// Shutter time in seconds (1/25000..60), e.g. 0.008 or 1/125.
    #[arg(long, value_name = "T", value_parser = parse_seconds)]
    pub shutter: Option<f32>,
    /// Sensor sensitivity, ISO (10..204800).
    #[arg(long, value_name = "S", value_parser = parse_positive)]
    pub iso: Option<f32>,
    /// Focal length in millimetres on the camera's sensor (sets the field of view).
    #[arg(long, value_name = "MM", value_parser = parse_positive)]
    pub focal_length: Option<f32>,
    /// Focus distance in metres (or "inf").
    #[arg(long, value_name = "M", value_parser = parse_focus)]
    pub focus: Option<f32>,
    /// Depth of field from the lens (thin-lens circle of confusion).
    #[arg(long)]
    pub dof: bool,
    /// Depth-of-field sample rings, 1..=5 (default 3); implies --dof.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=5))]
    pub dof_rings: Option<u32>,
    /// Turn depth of field off even where the scene's camera has it (no DoF pass runs).
    #[arg(long, conflicts_with_all = ["dof", "dof_rings"])]
    pub no_dof: bool,
    /// Natural (cos⁴) vignetting; an optional strength 0..1 (default 1).
    #[arg(long, value_name = "STRENGTH", num_args = 0..=1, default_missing_value = "1", value_parser = parse_unit)]
    pub vignette: Option<f32>,
    /// Automatic exposure from the frame's luminance histogram.
    #[arg(long, conflicts_with_all = ["ev100", "exposure"])]
    pub auto_exposure: bool,
    /// Exposure compensation in stops (+1 = twice as bright).
    #[arg(long, value_name = "STOPS", allow_hyphen_values = true, value_parser = parse_finite)]
    pub exposure_compensation: Option<f32>,
    /// Tone mapper: pbr-neutral (default), aces, agx, reinhard, none.
    #[arg(long, value_name = "NAME", value_parser = parse_tonemapper)]
    pub tonemap: Option<lumen::color::Tonemapper>,
    /// Specular visibility term: schlick-ggx (default), smith-correlated, smith-correlated-fast.
    #[arg(long, value_name = "NAME", value_parser = parse_visibility)]
    pub visibility: Option<lumen::brdf::VisibilityModel>,
    /// Turn every shadow off (no shadow pass runs).
    #[arg(long)]
    pub no_shadows: bool,
    /// Which lights cast shadows: scene (each light's own setting, the default) or all
    /// (every light, as the path tracer sees them).
    #[arg(long, value_name = "WHICH", value_parser = parse_light_shadows)]
    pub light_shadows: Option<bool>,
    /// The lights of a glTF file cast no shadows (they do by default).
    #[arg(long)]
    pub no_gltf_light_shadows: bool,
    /// Shadow filtering: hardware (2×2 PCF), tent (3×3 bilinear taps, default), pcf (16
    /// taps), pcss (soft, from the light's size).
    #[arg(long, value_name = "NAME", value_parser = parse_shadow_filter)]
    pub shadow_filter: Option<lumen::quality::ShadowFilter>,
    /// Where the shadowed directional lights' shadows are filtered: half (a mask pass at
    /// half resolution, upsampled by depth; default), full (a mask pass per pixel), off
    /// (in the lighting pass's light loop).
    #[arg(long, value_name = "RES", value_parser = parse_shadow_mask)]
    pub shadow_mask: Option<lumen::quality::ShadowMask>,
    /// Environment image (OpenEXR or Radiance .hdr, equirectangular) lighting the scene.
    #[arg(long, value_name = "FILE", conflicts_with = "env_color")]
    pub env: Option<std::path::PathBuf>,
    /// Uniform environment of this linear RGB radiance (cd/m² with --env-intensity 1).
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb)]
    pub env_color: Option<glam::Vec3>,
    /// Luminance in cd/m² of an environment value of 1 (default: 1000 for --env, 1 for --env-color).
    #[arg(long, value_name = "CD_M2", value_parser = parse_non_negative)]
    pub env_intensity: Option<f32>,
    /// Rotation of the environment about +Y, in degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    pub env_rotation: Option<f32>,
    /// Blur of the environment drawn as background, as a roughness 0..1 (0 = sharp).
    #[arg(long, value_name = "R", value_parser = parse_unit)]
    pub background_blur: Option<f32>,
    /// Light with the environment but draw the camera's background colour behind the scene.
    #[arg(long)]
    pub env_hidden: bool,
    /// Single-scattering GGX only: no multiple-scattering energy compensation.
    #[arg(long)]
    pub no_energy_compensation: bool,
    /// No tiled light culling: every pixel loops over every point and spot light.
    #[arg(long)]
    pub no_light_culling: bool,
    /// Draw the shadow atlas every frame, even when no shadow view or caster changed
    /// (by default an unchanged atlas is kept).
    #[arg(long)]
    pub no_shadow_cache: bool,
    /// Quality preset: low, medium, high (default), ultra. The options below override it.
    #[arg(long, value_name = "PRESET", value_parser = parse_preset)]
    pub quality: Option<lumen::quality::QualityPreset>,
    /// Multiplier of every light's shadow-map resolution (0.125..=4).
    #[arg(long, value_name = "X", value_parser = parse_shadow_scale)]
    pub shadow_resolution_scale: Option<f32>,
    /// Most cascades a directional light gets (1..=4).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4))]
    pub cascades: Option<u32>,
    /// GGX samples per texel when prefiltering the environment (1..=4096).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub ibl_samples: Option<u32>,
    /// Side of the split-sum BRDF table in texels (8..=512).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(8..=512))]
    pub brdf_lut_size: Option<u32>,
    /// Samples per texel of the split-sum BRDF table (1..=65536).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub brdf_lut_samples: Option<u32>,
    /// How blended surfaces are composited: sorted (back to front, the default) or
    /// weighted (weighted blended order-independent transparency).
    #[arg(long, value_name = "MODE", value_parser = parse_transparency)]
    pub transparency: Option<lumen::quality::Transparency>,
    /// Precision of the HDR target: f16 (default) or f32.
    #[arg(long, value_name = "P", value_parser = parse_hdr_precision)]
    pub hdr: Option<lumen::quality::HdrPrecision>,
    /// Screen-space ambient occlusion on environment light: off, half (default) or full
    /// resolution.
    #[arg(long, value_name = "RES", value_parser = parse_ao_resolution)]
    pub ao: Option<lumen::quality::AoResolution>,
    /// AO slices (screen directions) per pixel (1..=8).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=8))]
    pub ao_slices: Option<u32>,
    /// AO depth samples per side of a slice (1..=32).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=32))]
    pub ao_steps: Option<u32>,
    /// AO radius in metres: geometry farther than this does not occlude.
    #[arg(long, value_name = "M", value_parser = parse_positive)]
    pub ao_radius: Option<f32>,
    /// No spatial filter on the AO: each pixel keeps its own noisy estimate.
    #[arg(long)]
    pub no_ao_denoise: bool,
    /// Single-bounce AO: no multiple-bounce brightening of bright surfaces.
    #[arg(long)]
    pub no_ao_multi_bounce: bool,
    /// No screen-space reflections: smooth surfaces reflect only the environment.
    #[arg(long)]
    pub no_ssr: bool,
    /// Roughest surface (perceptual roughness 0..1) that gets traced reflections.
    #[arg(long, value_name = "R", value_parser = parse_unit)]
    pub ssr_max_roughness: Option<f32>,
    /// Reflection rays per pixel (1..=16).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=16))]
    pub ssr_rays: Option<u32>,
    /// Iterations per reflection ray over the depth pyramid (8..=256).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(8..=256))]
    pub ssr_steps: Option<u32>,
    /// Where reflections are traced: half (one pixel per 2×2 block, default) or full.
    #[arg(long, value_name = "RES", value_parser = parse_ssr_resolution)]
    pub ssr_resolution: Option<bool>,
    /// How far (m) behind a surface a reflection ray may pass and still hit it.
    #[arg(long, value_name = "M", value_parser = parse_positive)]
    pub ssr_thickness: Option<f32>,
    /// Diffuse global illumination from an irradiance volume: on (default from `medium`)
    /// or off.
    #[arg(long, value_name = "ON", value_parser = parse_on_off)]
    pub gi: Option<bool>,
    /// Probes along the longest side of an irradiance volume without its own spacing
    /// (1..=16).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=16))]
    pub gi_density: Option<u32>,
    /// Side in pixels of each cube face a probe captures (4..=64).
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(4..=64))]
    pub gi_face: Option<u32>,
    /// Capture passes of the irradiance volume, one bounce each (1..=4).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4))]
    pub gi_bounces: Option<u32>,
    /// Where the irradiance volume is looked up: half (once per 2×2 pixels, upsampled by
    /// depth; default) or full (per pixel, as `ultra`).
    #[arg(long, value_name = "RES", value_parser = parse_gi_resolution)]
    pub gi_resolution: Option<bool>,
    /// Probes captured per frame in `view` and `bench` while the volume converges (0: all
    /// at once).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=4096))]
    pub gi_budget: Option<u32>,
    /// No automatic irradiance volume or reflection probe: only those the scene places.
    #[arg(long)]
    pub no_auto_probes: bool,
    /// Reflection probes: on (default from `medium`) or off.
    #[arg(long, value_name = "ON", value_parser = parse_on_off)]
    pub reflection_probes: Option<bool>,
    /// Side in pixels of each cube face a reflection probe captures (16..=256, rounded up to
    /// a power of two).
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(16..=256))]
    pub reflection_probe_size: Option<u32>,
    /// Anti-aliasing: none, fxaa, smaa or taa (default: the preset's; TAA in `ultra`).
    #[arg(long, value_name = "METHOD", value_parser = parse_aa)]
    pub aa: Option<lumen::quality::AaMethod>,
    /// Average N renders, each with the camera jittered inside the pixel (1..=1024): the
    /// box-filtered pixel the path-traced reference computes. Costs N frames.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub accumulate: Option<u32>,
    /// Geometric specular anti-aliasing: the normal's variation inside a pixel widens its
    /// roughness (less flicker; off by default, see --no-specular-aa).
    #[arg(long, conflicts_with = "no_specular_aa")]
    pub specular_aa: bool,
    /// No geometric specular anti-aliasing (the default).
    #[arg(long)]
    pub no_specular_aa: bool,
    /// Specular AA's kernel: 2021 (projected space, the default) or 2019 (slope space,
    /// Filament's); sets σ² and κ to the form's defaults unless they are given.
    #[arg(long, value_name = "YEAR", value_parser = parse_specular_aa_form)]
    pub specular_aa_form: Option<lumen::quality::SpecularAaForm>,
    /// Specular AA's pixel filter variance σ² (0..=1, default 1/(2π); 0.15 with 2019).
    #[arg(long, value_name = "X", value_parser = parse_unit)]
    pub specular_aa_variance: Option<f32>,
    /// Specular AA's largest added α² κ (0..=1, default 0.18; 0.2 with 2019).
    #[arg(long, value_name = "X", value_parser = parse_unit)]
    pub specular_aa_threshold: Option<f32>,
    /// Sharpening of TAA's output, 0..=1 (contrast-adaptive; default 0, none)
    #[arg(long, value_name = "X", value_parser = parse_unit)]
    pub taa_sharpen: Option<f32>,
    /// Texture budget: longest side in texels a loaded texture keeps (16..=16384;
    /// default 4096); larger textures are downscaled with a warning
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub max_texture_size: Option<u32>,
    /// Show one channel instead of the image: albedo, normal, metallic, roughness,
    /// occlusion, depth, shadow-atlas or coc (README, "Debug views").
    #[arg(long, value_name = "VIEW", value_parser = lumen::render::debug_view::DebugView::parse)]
    pub debug_view: Option<lumen::render::debug_view::DebugView>,
}

impl SceneArgs {
    /// A positional `FILE` that is not a file but names a built-in scene (no extension)
    /// becomes `--scene NAME`, so `lumen bench spheres` works.
    pub fn resolve_builtin(&mut self) {
        if let Some(file) = &self.file
            && file.extension().is_none()
            && !file.exists()
            && let Some(name) = file.to_str()
            && crate::scenes::find(name).is_ok()
        {
            self.scene = Some(name.to_string());
            self.file = None;
        }
    }

    /// The name shown for the scene: the built-in name or the file's stem.
    pub fn label(&self) -> String {
        match (&self.file, &self.scene) {
            (Some(f), _) => f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into()),
            (None, Some(s)) => s.clone(),
            (None, None) => "spheres".into(),
        }
    }
}

/// Arguments of `lumen render`.
#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene and exposure.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Output file: .png (tone-mapped sRGB) or .exr (linear exposed radiance, f32 RGB).
    /// Default: `out/<scene>.png`.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON object with the adapter, passes and timings on stdout.
    #[arg(long)]
    pub json: bool,
    /// Print which passes and shader features run, and why, on stderr.
    #[arg(long)]
    pub explain: bool,
    /// A sequence: frames A to B (both included), frame k posed at k / fps seconds, each
    /// rendered on its own (as `--time k/fps` would) into `--out` with its `#`s replaced
    /// by the zero-padded frame number (`--out seq/frame-####.png`).
    #[arg(long, value_name = "A..B", value_parser = parse_frame_range, conflicts_with = "time")]
    pub frames: Option<(u32, u32)>,
    /// Frames per second of `--frames`.
    #[arg(long, value_name = "F", default_value = "30", value_parser = parse_positive, requires = "frames")]
    pub fps: f32,
    /// Render only shard I of N (from 0) of the `--frames` sequence: a contiguous share of
    /// its frames, listed with their checksums in `<name>.shard-I-of-N.json` beside them
    /// (for `lumen merge`); frames already written are skipped. Without it, an array job's index is
    /// read from SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX, AWS_BATCH_JOB_ARRAY_INDEX or
    /// HQ_TASK_ID.
    #[arg(long, value_name = "I/N", value_parser = crate::shard::parse_shard, requires = "frames")]
    pub shard: Option<(u32, u32)>,
    /// The number of shards where the environment gives only the index.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1_000_000), requires = "frames")]
    pub shards: Option<u32>,
}

/// Parses `A..B` (frame numbers, A ≤ B).
pub fn parse_frame_range(s: &str) -> Result<(u32, u32), String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("'{s}' is not a frame range A..B (e.g. 0..47)"))?;
    let number = |x: &str| {
        x.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{x}' in '{s}' is not a frame number"))
    };
    let (a, b) = (number(a)?, number(b)?);
    if a > b {
        return Err(format!("frame range {s} runs backwards"));
    }
    Ok((a, b))
}

/// Arguments of `lumen reference`.
#[derive(Args, Debug, Clone)]
pub struct ReferenceArgs {
    /// Scene and exposure.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "320x180", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Paths per pixel (1..=1048576).
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub spp: u32,
    /// Surface interactions per path (1 = direct light only; 1..=64).
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub max_bounces: u32,
    /// Random seed: the same seed gives the same image.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Which lights shadow rays test: physical (every light, default) or frame (only the
    /// lights whose shadow the rasterized frame draws).
    #[arg(long, value_name = "MODE", default_value = "physical", value_parser = parse_light_visibility)]
    pub light_visibility: lumen::reference::path::LightVisibility,
    /// Unidirectional paths only: no light connections (rays traced from point and spot
    /// lights to a surface, then joined to the path). The same expectation with more
    /// noise indoors; for comparing the estimators.
    #[arg(long)]
    pub no_light_connections: bool,
    /// Ray-trace ambient occlusion instead of radiance, within the AO radius
    /// (`--ao-radius`, default 1 m): the ground truth of `--debug-view occlusion`. A PNG
    /// shows it as grey (value × 255), as the debug view does.
    #[arg(long)]
    pub occlusion: bool,
    /// Output file: .exr (linear exposed radiance) or .png (tone mapped with the camera's
    /// tone mapper). Default: `out/<scene>-reference.exr`. A shard writes its part beside
    /// it instead: `<stem>.shard-I-of-N.exr` and its `.json` sidecar.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Trace only shard I of N (from 0) of the samples, into a part that `lumen merge`
    /// combines with the others. Without it, an array job's index is read from
    /// SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX, AWS_BATCH_JOB_ARRAY_INDEX or HQ_TASK_ID.
    #[arg(long, value_name = "I/N", value_parser = crate::shard::parse_shard)]
    pub shard: Option<(u32, u32)>,
    /// The number of shards where the environment gives only the index
    /// (JOB_COMPLETION_INDEX, HQ_TASK_ID).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub shards: Option<u32>,
}

/// Arguments of `lumen merge`.
#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// The parts: a reference's `*.shard-I-of-N.exr`, a tradeoff's `*.shard-I-of-N.json`
    /// or a sequence's frame manifests `*.shard-I-of-N.json`, each with its `.json`
    /// sidecar beside it.
    #[arg(value_name = "PART", required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged image (.exr); for tradeoff parts, the merged rows (.json, schema
    /// lumen-tradeoff/1; the Markdown table is printed); for sequence parts, the manifest
    /// of every frame (.json, schema lumen-sequence/1), once each frame is checked whole.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
}

/// Arguments of `lumen tradeoff`.
#[derive(Args, Debug, Clone)]
pub struct TradeoffArgs {
    /// Scene and exposure (quality options are what the rows vary).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "320x180", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Paths per pixel of the reference (cached in out/reference-cache/).
    #[arg(long, value_name = "N", default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub spp: u32,
    /// Measured frames per row (after 3 warm-up frames; TAA rows warm up to whole jitter
    /// sequences of 64 frames).
    #[arg(long, value_name = "N", default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Write the rows as JSON (schema lumen-tradeoff/1) to this file ("-": standard output).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write the table as Markdown to this file.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Draw time against error, with the Pareto front, into this PNG.
    #[arg(long, value_name = "FILE.png", conflicts_with = "decompose")]
    pub plot: Option<PathBuf>,
    /// Instead of the rows, split the error of one frame (the quality options given,
    /// default high) into its implementation's own error, what its unshadowed lights
    /// cost and what it does not transport.
    #[arg(long)]
    pub decompose: bool,
    /// Judge the rows against N renders of `high` accumulated with jitter (`--aa none
    /// --accumulate N`) instead of the path-traced reference: the error anti-aliasing
    /// leaves, without what the frame does not transport.
    #[arg(long, value_name = "N", conflicts_with = "decompose", value_parser = clap::value_parser!(u32).range(2..=1024))]
    pub against_accumulated: Option<u32>,
    /// Only the rows of these knobs (e.g. `--only preset --only --aa`; the kinds the
    /// table's first column names, `preset` for the presets).
    #[arg(long, value_name = "KNOB", allow_hyphen_values = true)]
    pub only: Vec<String>,
    /// Measure only shard I of N (from 0) of the rows, into a part beside `--json F`
    /// (`<stem>.shard-I-of-N.json` and its sidecar) that `lumen merge` joins with the
    /// others. Without it, an array job's index is read from the environment (as for
    /// `reference`).
    #[arg(long, value_name = "I/N", value_parser = crate::shard::parse_shard, conflicts_with = "decompose")]
    pub shard: Option<(u32, u32)>,
    /// The number of shards where the environment gives only the index.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1_000_000), conflicts_with = "decompose")]
    pub shards: Option<u32>,
}

/// Arguments of `lumen view`.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Scene and exposure.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Initial window size in pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Quit after this many frames (for scripts).
    #[arg(long, value_name = "N")]
    pub frames: Option<u64>,
    /// Save a screenshot (PNG or EXR) when the viewer quits.
    #[arg(long, value_name = "FILE")]
    pub screenshot: Option<PathBuf>,
    /// Open a glTF model (replacing the scene) or an HDR/EXR environment once the window
    /// is up; repeatable. Dropping a file on the window does the same.
    #[arg(long, value_name = "FILE")]
    pub open: Vec<PathBuf>,
    /// No on-screen panel.
    #[arg(long)]
    pub no_panel: bool,
    /// Folder of WGSL files to watch and reload when they change (default: `shaders/`
    /// of the working directory, else of the source tree the binary was built from).
    #[arg(long, value_name = "DIR")]
    pub shaders: Option<PathBuf>,
    /// Test hook: destroy the GPU device after this many frames, to exercise the
    /// recovery from a lost device.
    #[arg(long, value_name = "N", hide = true)]
    pub lose_device_after: Option<u64>,
}

impl ViewArgs {
    /// `scene` in a window of `size`, with the defaults of the other options.
    pub fn new(scene: SceneArgs, size: (u32, u32)) -> ViewArgs {
        ViewArgs {
            scene,
            size,
            frames: None,
            screenshot: None,
            open: Vec::new(),
            no_panel: false,
            shaders: None,
            lose_device_after: None,
        }
    }
}

/// Arguments of `lumen bench`.
#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// Scene, exposure and quality.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Measured frames.
    #[arg(long, value_name = "N", default_value_t = 100, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub frames: u32,
    /// Frames rendered before measuring (pipelines compile, caches fill, auto exposure adapts).
    #[arg(long, value_name = "N", default_value_t = 10, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub warmup: u32,
    /// Image (or window) size in pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Write the JSON report (schema lumen-bench/1) to this file ("-": standard output).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write one CSV row per measured frame to this file.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Draw a frame-time chart with the per-pass breakdown into this PNG.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
    /// Measure presented frames in a window (no vsync) instead of offscreen frames.
    #[arg(long)]
    pub window: bool,
    /// Compare two JSON reports: print B / A for the frame, every pass and every stage.
    #[arg(long, num_args = 2, value_names = ["A.json", "B.json"], conflicts_with_all = ["json", "csv", "plot", "window"])]
    pub compare: Option<Vec<PathBuf>>,
}

/// Largest image side accepted on the command line (the adapter may allow less).
pub const MAX_SIDE: u32 = 16384;

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH (e.g. 1280x720)"))?;
    let side = |v: &str| -> Result<u32, String> {
        let n: u32 = v
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not WxH (e.g. 1280x720)"))?;
        if n == 0 || n > MAX_SIDE {
            return Err(format!("'{s}': each side must be 1..={MAX_SIDE}"));
        }
        Ok(n)
    };
    Ok((side(w)?, side(h)?))
}

fn parse_ev100(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
    let (lo, hi) = lumen::scene::Exposure::EV100_RANGE;
    if !v.is_finite() || !(lo..=hi).contains(&v) {
        return Err(format!("EV100 {s} is outside {lo}..={hi}"));
    }
    Ok(v)
}

fn parse_exposure(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
    if !v.is_finite() || v <= 0.0 {
        return Err(format!("exposure {s} must be a finite number > 0"));
    }
    Ok(v)
}

fn parse_tonemapper(s: &str) -> Result<lumen::color::Tonemapper, String> {
    lumen::color::Tonemapper::from_name(s).ok_or_else(|| {
        format!(
            "unknown tone mapper '{s}' (use {})",
            lumen::color::Tonemapper::ALL
                .iter()
                .map(|t| t.name())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

fn parse_rgb(s: &str) -> Result<glam::Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not R,G,B (e.g. 1,1,1)"))?;
    match v[..] {
        [r, g, b] if v.iter().all(|c| c.is_finite() && *c >= 0.0) => Ok(glam::Vec3::new(r, g, b)),
        [_, _, _] => Err(format!("'{s}': each component must be a finite number ≥ 0")),
        _ => Err(format!("'{s}' is not R,G,B (e.g. 1,1,1)")),
    }
}

fn parse_positive(s: &str) -> Result<f32, String> {
    parse_finite(s).and_then(|v| {
        if v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{s} must be > 0"))
        }
    })
}

/// Seconds as a decimal or a fraction (`1/125`).
fn parse_seconds(s: &str) -> Result<f32, String> {
    match s.split_once('/') {
        Some((n, d)) => {
            let (n, d) = (parse_positive(n.trim())?, parse_positive(d.trim())?);
            Ok(n / d)
        }
        None => parse_positive(s),
    }
}

fn parse_focus(s: &str) -> Result<f32, String> {
    if s.eq_ignore_ascii_case("inf") || s.eq_ignore_ascii_case("infinity") {
        return Ok(f32::INFINITY);
    }
    parse_positive(s)
}

fn parse_finite(s: &str) -> Result<f32, String> {
    s.parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("'{s}' is not a finite number"))
}

fn parse_non_negative(s: &str) -> Result<f32, String> {
    parse_finite(s).and_then(|v| {
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{s} must be ≥ 0"))
        }
    })
}

fn parse_unit(s: &str) -> Result<f32, String> {
    parse_finite(s).and_then(|v| {
        if (0.0..=1.0).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{s} must be in 0..=1"))
        }
    })
}

fn parse_light_visibility(s: &str) -> Result<lumen::reference::path::LightVisibility, String> {
    lumen::reference::path::LightVisibility::from_name(s)
        .ok_or_else(|| format!("unknown light visibility '{s}' (use physical or frame)"))
}

fn parse_ao_resolution(s: &str) -> Result<lumen::quality::AoResolution, String> {
    lumen::quality::AoResolution::from_name(s)
        .ok_or_else(|| format!("unknown AO resolution '{s}' (use off, half, full)"))
}

fn parse_aa(s: &str) -> Result<lumen::quality::AaMethod, String> {
    lumen::quality::AaMethod::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = lumen::quality::AaMethod::ALL
            .iter()
            .map(|m| m.name())
            .collect();
        format!("unknown anti-aliasing '{s}' (use {})", names.join(", "))
    })
}

fn parse_specular_aa_form(s: &str) -> Result<lumen::quality::SpecularAaForm, String> {
    lumen::quality::SpecularAaForm::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = lumen::quality::SpecularAaForm::ALL
            .iter()
            .map(|f| f.name())
            .collect();
        format!(
            "unknown specular AA form '{s}' (use {})",
            names.join(" or ")
        )
    })
}

fn parse_on_off(s: &str) -> Result<bool, String> {
    match s.to_ascii_lowercase().as_str() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("'{s}': expected on or off")),
    }
}

/// `half` (true) or `full` (false), for a pass that `what` names in the error.
fn parse_half_full(s: &str, what: &str) -> Result<bool, String> {
    match s.to_ascii_lowercase().as_str() {
        "half" => Ok(true),
        "full" => Ok(false),
        _ => Err(format!("unknown {what} resolution '{s}' (use half, full)")),
    }
}

fn parse_ssr_resolution(s: &str) -> Result<bool, String> {
    parse_half_full(s, "reflection")
}

fn parse_gi_resolution(s: &str) -> Result<bool, String> {
    parse_half_full(s, "irradiance volume")
}

fn parse_light_shadows(s: &str) -> Result<bool, String> {
    match s.to_ascii_lowercase().as_str() {
        "all" => Ok(true),
        "scene" => Ok(false),
        _ => Err(format!("unknown light-shadow set '{s}' (use scene, all)")),
    }
}

fn parse_shadow_mask(s: &str) -> Result<lumen::quality::ShadowMask, String> {
    lumen::quality::ShadowMask::from_name(s).ok_or_else(|| {
        format!(
            "unknown shadow mask '{s}' (use {})",
            lumen::quality::ShadowMask::ALL
                .iter()
                .map(|m| m.name())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

fn parse_shadow_filter(s: &str) -> Result<lumen::quality::ShadowFilter, String> {
    lumen::quality::ShadowFilter::from_name(s).ok_or_else(|| {
        format!(
            "unknown shadow filter '{s}' (use {})",
            lumen::quality::ShadowFilter::ALL
                .iter()
                .map(|f| f.name())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

fn parse_preset(s: &str) -> Result<lumen::quality::QualityPreset, String> {
    use lumen::quality::QualityPreset;
    QualityPreset::from_name(s).ok_or_else(|| {
        format!(
            "unknown quality preset '{s}' (use {})",
            QualityPreset::ALL
                .iter()
                .map(|p| p.name())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

fn parse_shadow_scale(s: &str) -> Result<f32, String> {
    parse_finite(s).and_then(|v| {
        if (0.125..=4.0).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{s} must be in 0.125..=4"))
        }
    })
}

fn parse_transparency(s: &str) -> Result<lumen::quality::Transparency, String> {
    use lumen::quality::Transparency;
    Transparency::ALL
        .into_iter()
        .find(|t| t.name().eq_ignore_ascii_case(s))
        .ok_or_else(|| format!("unknown transparency '{s}' (use sorted, weighted)"))
}

fn parse_hdr_precision(s: &str) -> Result<lumen::quality::HdrPrecision, String> {
    use lumen::quality::HdrPrecision;
    [HdrPrecision::Half, HdrPrecision::Full]
        .into_iter()
        .find(|p| p.name().eq_ignore_ascii_case(s))
        .ok_or_else(|| format!("unknown HDR precision '{s}' (use f16, f32)"))
}

fn parse_visibility(s: &str) -> Result<lumen::brdf::VisibilityModel, String> {
    lumen::brdf::VisibilityModel::ALL
        .into_iter()
        .find(|m| m.name().eq_ignore_ascii_case(s))
        .ok_or_else(|| {
            format!(
                "unknown visibility term '{s}' (use {})",
                lumen::brdf::VisibilityModel::ALL
                    .iter()
                    .map(|m| m.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
        assert_eq!(parse_size("64X32"), Ok((64, 32)));
        for bad in ["0x10", "10x0", "x", "12", "-1x5", "axb", "99999x1", ""] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn colours_and_ranges() {
        assert_eq!(parse_rgb("1, 0.5,2"), Ok(glam::Vec3::new(1.0, 0.5, 2.0)));
        for bad in ["1,2", "1,2,3,4", "a,b,c", "-1,0,0", "nan,0,0", ""] {
            assert!(parse_rgb(bad).is_err(), "{bad}");
        }
        assert!(parse_unit("1.5").is_err() && parse_unit("0.3").is_ok());
        assert!(parse_non_negative("-2").is_err());
        assert!(parse_finite("inf").is_err());
    }

    #[test]
    fn camera_arguments() {
        assert_eq!(parse_seconds("1/125"), Ok(0.008));
        assert_eq!(parse_seconds("0.5"), Ok(0.5));
        assert!(parse_seconds("1/0").is_err() && parse_seconds("-1").is_err());
        assert_eq!(parse_focus("inf"), Ok(f32::INFINITY));
        assert!(parse_focus("0").is_err());
    }

    #[test]
    fn exposure_arguments() {
        assert_eq!(parse_ev100("-2.5"), Ok(-2.5));
        assert!(parse_ev100("nan").is_err());
        assert!(parse_ev100("45").is_err());
        assert!(parse_exposure("0").is_err());
        assert!(parse_exposure("inf").is_err());
        assert_eq!(parse_exposure("1"), Ok(1.0));
    }
}

//! Command-line arguments of `lumen`: the subcommands' own options (derived with clap),
//! and the quality knobs, whose flags are derived from their declarations
//! ([`knob_flags`]); [`parse_from`] reads both, after [`legacy`] has turned old spellings
//! into new ones.

pub mod knob_flags;
pub mod legacy;
pub mod values;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use lumen::quality::QualityPreset;
use lumen::quality::knob::{Acts, Knobs, Settings};
use std::ffi::OsString;
use std::path::PathBuf;
pub use values::MAX_SIDE;
use values::{choice, finite, non_negative, positive};

/// The subcommands that render frames with the rasterizer, and what their knobs act on.
const FRAME_COMMANDS: [&str; 4] = ["render", "view", "bench", "tradeoff"];

/// What the knobs of `lumen reference` act on: the path tracer and loading.
const REFERENCE_KNOBS: Acts = Acts::TRACE.and(Acts::LOAD);

/// What the knobs of the rasterizing subcommands act on.
const FRAME_KNOBS: Acts = Acts::FRAME.and(Acts::LOAD);

/// The whole command line of `lumen`: every subcommand, with the flags of the knobs of
/// `knobs` that act on it.
pub fn command(knobs: &Knobs) -> clap::Command {
    let mut cmd = Cli::command();
    for name in FRAME_COMMANDS {
        cmd = cmd.mut_subcommand(name, |c| knob_flags::augment(c, knobs, FRAME_KNOBS));
    }
    cmd.mut_subcommand("reference", |c| {
        knob_flags::augment(c, knobs, REFERENCE_KNOBS)
    })
}

/// Parses `args` (the program's name first) with the knobs of `knobs`.
pub fn parse_from(
    knobs: &Knobs,
    args: impl IntoIterator<Item = OsString>,
) -> Result<Cli, clap::Error> {
    let matches = command(knobs).try_get_matches_from(args)?;
    let mut cli = Cli::from_arg_matches(&matches)?;
    if let Some((_, sub)) = matches.subcommand() {
        let scene = match &mut cli.command {
            Some(Command::Render(a)) => Some((&mut a.scene, FRAME_KNOBS)),
            Some(Command::View(a)) => Some((&mut a.scene, FRAME_KNOBS)),
            Some(Command::Bench(a)) => Some((&mut a.scene, FRAME_KNOBS)),
            Some(Command::Tradeoff(a)) => Some((&mut a.scene, FRAME_KNOBS)),
            Some(Command::Reference(a)) => Some((&mut a.scene, REFERENCE_KNOBS)),
            _ => None,
        };
        if let Some((scene, acts)) = scene {
            scene.knobs = knob_flags::settings(sub, knobs, acts);
        }
    }
    Ok(cli)
}

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
    /// The quality presets as data: `lumen quality show high` prints one as the TOML that
    /// `--quality-file` reads.
    Quality(QualityArgs),
}

/// Arguments of `lumen quality`.
#[derive(Args, Debug, Clone)]
pub struct QualityArgs {
    /// What to do.
    #[command(subcommand)]
    pub command: QualityCommand,
}

/// Subcommands of `lumen quality`.
#[derive(Subcommand, Debug, Clone)]
pub enum QualityCommand {
    /// Print a preset, every knob with its value, doc line and range, as a quality file
    /// (TOML) to edit and load with `--quality-file`.
    Show {
        /// The preset.
        #[arg(value_name = "PRESET", default_value = "high", value_parser = choice::<QualityPreset>())]
        preset: QualityPreset,
    },
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

lumen::choice::choices! {
/// What `lumen convert` produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConvertTarget: "target" {
    /// base_color.png, metallic.png, roughness.png.
    MetalRough = "metal-rough" | "metal-roughness",
    /// diffuse.png, specular.png, glossiness.png.
    SpecGloss = "spec-gloss" | "specular-glossiness",
    /// A roughness map from a glossiness map.
    Roughness = "roughness",
    /// A glossiness map from a roughness map.
    Glossiness = "glossiness",
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
    #[arg(long, value_name = "TARGET", value_parser = choice::<ConvertTarget>())]
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
    #[arg(long, value_name = "N", value_parser = values::number(1.0, 3.0))]
    pub ior: Option<f32>,
    /// Print the F0 of this specular level (0..=1; 0.5 gives 0.04).
    #[arg(long, value_name = "L", value_parser = values::number(0.0, 1.0))]
    pub specular_level: Option<f32>,
}

/// What to render and how to expose it (shared by `render`, `view`, `bench`, `reference`
/// and `tradeoff`): the scene, the camera, the environment and the quality. The knobs'
/// flags are added to each subcommand by [`command`] and read into [`SceneArgs::knobs`].
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Built-in scene (see `lumen scenes`).
    #[arg(
        long,
        value_name = "NAME",
        conflicts_with = "file",
        help_heading = "Scene"
    )]
    pub scene: Option<String>,
    /// A glTF 2.0 file (.gltf or .glb), or the name of a built-in scene.
    #[arg(value_name = "FILE|SCENE", help_heading = "Scene")]
    pub file: Option<PathBuf>,
    /// Pose an animated glTF file at this time of its first clip, in seconds (wrapped
    /// into the clip), and hold it there; without it the clip plays from 0 s.
    #[arg(long, value_name = "SECONDS", value_parser = non_negative, help_heading = "Scene")]
    pub time: Option<f32>,
    /// Number of point lights of the `lights` scene (0..=65536, default 256).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=65536), help_heading = "Scene")]
    pub lights: Option<u32>,
    /// Whether the lights of a glTF file cast shadows [default: on].
    #[arg(long, value_name = "on|off", value_parser = values::on_off, help_heading = "Scene")]
    pub gltf_light_shadows: Option<bool>,
    /// Show one channel instead of the image: albedo, normal, metallic, roughness,
    /// occlusion, depth, shadow-atlas or coc (README, "Debug views").
    #[arg(long, value_name = "VIEW", value_parser = choice::<lumen::render::post::debug_view::DebugView>(), help_heading = "Scene")]
    pub debug_view: Option<lumen::render::post::debug_view::DebugView>,
    /// Exposure value at ISO 100 (−10..30); replaces the camera's.
    #[arg(long, value_name = "X", allow_hyphen_values = true, value_parser = values::ev100, help_heading = "Camera")]
    pub ev100: Option<f32>,
    /// Linear exposure multiplier that replaces the camera's (1 = raw radiance).
    #[arg(long, value_name = "K", conflicts_with = "ev100", value_parser = positive, help_heading = "Camera")]
    pub exposure: Option<f32>,
    /// Aperture f-number (0.5..64); with --shutter and --iso the exposure follows the lens.
    #[arg(long, value_name = "N", value_parser = positive, help_heading = "Camera")]
    pub aperture: Option<f32>,
    /// Shutter time in seconds (1/25000..60), e.g. 0.008 or 1/125.
    #[arg(long, value_name = "T", value_parser = values::seconds, help_heading = "Camera")]
    pub shutter: Option<f32>,
    /// Sensor sensitivity, ISO (10..204800).
    #[arg(long, value_name = "S", value_parser = positive, help_heading = "Camera")]
    pub iso: Option<f32>,
    /// Focal length in millimetres on the camera's sensor (sets the field of view).
    #[arg(long, value_name = "MM", value_parser = positive, help_heading = "Camera")]
    pub focal_length: Option<f32>,
    /// Focus distance in metres (or "inf").
    #[arg(long, value_name = "M", value_parser = values::focus, help_heading = "Camera")]
    pub focus: Option<f32>,
    /// Depth of field from the lens (thin-lens circle of confusion); off turns it off even
    /// where the scene's camera has it (no DoF pass runs) [default: the camera's].
    #[arg(long, value_name = "on|off", value_parser = values::on_off, help_heading = "Camera")]
    pub dof: Option<bool>,
    /// Natural (cos⁴) vignetting; an optional strength 0..1 (default 1).
    #[arg(long, value_name = "STRENGTH", num_args = 0..=1, default_missing_value = "1", value_parser = values::number(0.0, 1.0), help_heading = "Camera")]
    pub vignette: Option<f32>,
    /// Automatic exposure from the frame's luminance histogram.
    #[arg(long, conflicts_with_all = ["ev100", "exposure"], help_heading = "Camera")]
    pub auto_exposure: bool,
    /// Exposure compensation in stops (+1 = twice as bright).
    #[arg(long, value_name = "STOPS", allow_hyphen_values = true, value_parser = finite, help_heading = "Camera")]
    pub exposure_compensation: Option<f32>,
    /// Tone mapper [default: pbr-neutral].
    #[arg(long, value_name = "NAME", value_parser = choice::<lumen::shading::color::Tonemapper>(), help_heading = "Camera")]
    pub tonemap: Option<lumen::shading::color::Tonemapper>,
    /// Environment image (OpenEXR or Radiance .hdr, equirectangular) lighting the scene.
    #[arg(
        long,
        value_name = "FILE",
        conflicts_with = "env_color",
        help_heading = "Environment"
    )]
    pub env: Option<std::path::PathBuf>,
    /// Uniform environment of this linear RGB radiance (cd/m² with --env-intensity 1).
    #[arg(long, value_name = "R,G,B", value_parser = values::rgb, help_heading = "Environment")]
    pub env_color: Option<glam::Vec3>,
    /// Luminance in cd/m² of an environment value of 1 (default: 1000 for --env, 1 for --env-color).
    #[arg(long, value_name = "CD_M2", value_parser = non_negative, help_heading = "Environment")]
    pub env_intensity: Option<f32>,
    /// Rotation of the environment about +Y, in degrees.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = finite, help_heading = "Environment")]
    pub env_rotation: Option<f32>,
    /// Blur of the environment drawn as background, as a roughness 0..1 (0 = sharp).
    #[arg(long, value_name = "R", value_parser = values::number(0.0, 1.0), help_heading = "Environment")]
    pub background_blur: Option<f32>,
    /// Light with the environment but draw the camera's background colour behind the scene.
    #[arg(long, help_heading = "Environment")]
    pub env_hidden: bool,
    /// Quality preset: low, medium, high (default), ultra; the knobs' flags override it.
    #[arg(long, value_name = "PRESET", value_parser = choice::<QualityPreset>(), help_heading = "Quality")]
    pub quality: Option<QualityPreset>,
    /// A quality file (TOML, as `lumen quality show` prints it): a preset with any knob
    /// overridden; the knobs' flags override it in turn.
    #[arg(
        long,
        value_name = "FILE.toml",
        conflicts_with = "quality",
        help_heading = "Quality"
    )]
    pub quality_file: Option<PathBuf>,
    /// The knobs the command line sets (their flags are derived from the knobs'
    /// declarations, see [`command`]).
    #[arg(skip)]
    pub knobs: Settings,
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
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = values::size)]
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
    #[arg(long, value_name = "A..B", value_parser = values::frame_range, conflicts_with = "time")]
    pub frames: Option<(u32, u32)>,
    /// Frames per second of `--frames`.
    #[arg(long, value_name = "F", default_value = "30", value_parser = positive, requires = "frames")]
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

/// Arguments of `lumen reference`.
#[derive(Args, Debug, Clone)]
pub struct ReferenceArgs {
    /// Scene and exposure.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "320x180", value_parser = values::size)]
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
    #[arg(long, value_name = "MODE", default_value = "physical", value_parser = choice::<lumen::reference::path::LightVisibility>())]
    pub light_visibility: lumen::reference::path::LightVisibility,
    /// Unidirectional paths only: no light connections (rays traced from point and spot
    /// lights to a surface, then joined to the path). The same expectation with more
    /// noise indoors; for comparing the estimators.
    #[arg(long)]
    pub no_light_connections: bool,
    /// Where to path-trace: gpu (the GPU path tracer: the unidirectional estimator, for
    /// the materials, lights and environments it supports; an error otherwise), cpu, or
    /// auto (the GPU when the adapter is a hardware GPU and the GPU traces the whole
    /// scene, else the CPU; the choice and its reason are printed).
    #[arg(long, value_name = "DEVICE", default_value = "auto", value_parser = choice::<lumen::reference_gpu::TraceDevice>())]
    pub device: lumen::reference_gpu::TraceDevice,
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
    #[arg(long, value_name = "WxH", default_value = "320x180", value_parser = values::size)]
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
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = values::size)]
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
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = values::size)]
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
    /// Measure the ray-tracing core instead of frames: build the scene's acceleration
    /// structure after one frame (times, memory, bytes per triangle; and what a second,
    /// unchanged frame pays), then trace N rays through the scene on the GPU (software
    /// traversal) and on the CPU, and print rays per second.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000_000), conflicts_with_all = ["json", "csv", "plot", "window", "compare"])]
    pub rays: Option<u32>,
}

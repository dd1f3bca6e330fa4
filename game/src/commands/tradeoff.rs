//! `lumen tradeoff`: every preset, and every quality knob varied alone from `high`, timed
//! with the benchmark's machinery and compared with the path-traced reference (FLIP on
//! the tone-mapped images, relative MSE and PSNR on the linear HDR ones).

use crate::cli::knob_flags::flag;
use crate::cli::{SceneArgs, TradeoffArgs};
use crate::measure::{measure, stats::Summary};
use crate::setup::{build_scene, check_scene_args};
use anyhow::{Context, Result, anyhow};
use lumen::App;
use lumen::choice::Choice;
use lumen::quality::QualityPreset;
use lumen::quality::knob::{Acts, Knobs, Value};
use lumen::quality::knobs::{AA, ACCUMULATE, AO, GI, REFLECTION_PROBES, SSR};
use lumen::reference::path::{LightVisibility, ReferenceOptions, render};
use lumen::shading::brdf::VisibilityModel;
use lumen::shading::color::Tonemapper;
use lumen::trace_input::trace_scene;
use plotters::prelude::*;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Bounces of the reference's paths.
const REFERENCE_BOUNCES: u32 = 8;

/// One configuration and what it measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// `preset` or the knob's option name.
    pub kind: String,
    /// The preset or the knob's value.
    pub setting: String,
    /// Median wall time per frame (ms).
    pub frame_ms: f64,
    /// Median GPU time per frame (ms), where the adapter has timestamps.
    pub gpu_ms: Option<f64>,
    /// Mean FLIP error of the tone-mapped image against the tone-mapped reference (0..1).
    pub flip_mean: f64,
    /// PSNR of the linear image against the reference (dB), both clipped to [0, 1] (the
    /// exposed radiance of display white) and with a peak of 1. Unclipped, the few
    /// pixels of the sun's glint on smooth metals (exposed values of 10⁴ and more) decide
    /// it alone.
    pub psnr_db: f64,
    /// Relative MSE of the linear HDR image (Rousselle et al. 2011): the mean over pixels
    /// and channels of (image − reference)² / (reference² + 0.01).
    pub relative_mse: f64,
}

impl Row {
    /// `kind=setting`, or the preset's name.
    pub fn label(&self) -> String {
        if self.kind == "preset" || self.kind.is_empty() {
            self.setting.clone()
        } else if self.setting.is_empty() {
            self.kind.clone()
        } else {
            format!("{} {}", self.kind, self.setting)
        }
    }
}

/// Every row: the four presets, then each knob of `knobs` that acts on the frame, varied
/// alone from `high` to each value its declaration sweeps (with the other knobs' values
/// its sweep needs). A row's kind is the knob's flag.
pub fn configurations(base: &SceneArgs, knobs: &Knobs) -> Vec<(String, String, SceneArgs)> {
    let mut out = Vec::new();
    for &preset in QualityPreset::ALL {
        let mut a = base.clone();
        a.quality = Some(preset);
        a.quality_file = None;
        out.push(("preset".into(), preset.name().into(), a));
    }
    for knob in knobs.iter().filter(|k| k.acts.meets(Acts::FRAME)) {
        for &value in knob.sweep {
            let mut a = base.clone();
            a.quality = Some(QualityPreset::High);
            a.quality_file = None;
            for &(other, v) in knob.sweep_with {
                a.knobs.set(other, v);
            }
            a.knobs.set(knob, value);
            out.push((flag(knob), knob.format(value), a));
        }
    }
    out
}

/// Which reference: how many bounces its paths take and which lights its shadow rays
/// test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceKind {
    /// Surface interactions per path (1 = direct light only).
    pub bounces: u32,
    /// Every light's shadow (physical) or only those the frame draws.
    pub visibility: LightVisibility,
    /// The path tracer's seed: 0 for the references the rows are judged against, another
    /// for a second, independent estimate of the same image (its noise).
    pub seed: u64,
}

/// The ground truth the rows are judged against: 8 bounces, physical visibility.
pub const FULL_REFERENCE: ReferenceKind = ReferenceKind {
    bounces: REFERENCE_BOUNCES,
    visibility: LightVisibility::Physical,
    seed: 0,
};

/// The reference of `scene` at `size` and `spp`: from the cache (keyed by the scene's
/// name, a hash of its options, the size, samples, bounces and visibility) when it holds
/// it, else path-traced (Smith height-correlated visibility and energy compensation: Lumen's most
/// accurate BRDF) and cached.
fn reference(
    scene: &SceneArgs,
    size: (u32, u32),
    spp: u32,
    kind: ReferenceKind,
) -> Result<(image::Rgba32FImage, Tonemapper, bool)> {
    let mut app = App::headless()?;
    build_scene(&mut app, scene)?;
    // The frame's visibility depends on which lights the frame's quality shadows.
    let visibility = match kind.visibility {
        LightVisibility::Physical => "",
        LightVisibility::AsFrame
            if app
                .world()
                .resource::<lumen::prelude::Quality>()
                .all_lights_cast_shadows =>
        {
            "-frame-all"
        }
        LightVisibility::AsFrame => "-frame",
    };
    // The scene's options (environment, exposure, …) change the image as much as its
    // name: they are hashed into the file name.
    let options = {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        format!("{scene:?}").hash(&mut h);
        h.finish() as u32
    };
    let seed = if kind.seed == 0 {
        String::new()
    } else {
        format!("-seed{}", kind.seed)
    };
    let cache = PathBuf::from("out/reference-cache").join(format!(
        "{}-{options:08x}-{}x{}-{}spp-{}b{visibility}{seed}-{}.exr",
        scene.label(),
        size.0,
        size.1,
        spp,
        kind.bounces,
        lumen::reference::path::ESTIMATOR
    ));
    {
        let mut q = app.world_mut().resource_mut::<lumen::prelude::Quality>();
        q.visibility = VisibilityModel::SmithGgxCorrelated;
        q.energy_compensation = true;
    }
    if let Ok(img) = lumen::assets::image_io::load_rgba32f(&cache)
        && img.dimensions() == size
    {
        // One frame for the camera's tone mapper; no scene to trace.
        app.render_headless(size)?;
        return Ok((
            img,
            crate::commands::reference::frame_tonemapper(&app),
            true,
        ));
    }
    let mut traced = trace_scene(&mut app, size)?;
    traced.light_visibility = kind.visibility;
    let tonemapper = crate::commands::reference::frame_tonemapper(&app);
    let bar = crate::progress::bar(u64::from(size.1), "reference", "rows");
    let options = ReferenceOptions {
        size,
        samples_per_pixel: spp,
        max_bounces: kind.bounces,
        seed: kind.seed,
    };
    let result = render(&traced, &options, &|rows| bar.set_position(u64::from(rows)));
    bar.finish_and_clear();
    crate::commands::reference::warn_dropped(result.dropped_samples, &options);
    let img = result.image;
    lumen::assets::image_io::save_exr(&cache, &img)?;
    Ok((img, tonemapper, false))
}

/// The judge of `--against-accumulated N`: the scene at `high` with no post AA and N
/// jittered renders averaged, and its tone mapper (the third value: never cached).
fn accumulated_judge(
    scene: &SceneArgs,
    size: (u32, u32),
    n: u32,
) -> Result<(image::Rgba32FImage, Tonemapper, bool)> {
    let mut args = scene.clone();
    args.quality = Some(QualityPreset::High);
    args.quality_file = None;
    args.knobs.set(&AA, Value::Name("none"));
    args.knobs.set(&ACCUMULATE, Value::Int(i64::from(n)));
    let mut app = App::headless()?;
    build_scene(&mut app, &args)?;
    app.render_headless(size)?;
    Ok((
        app.read_hdr_image()?,
        crate::commands::reference::frame_tonemapper(&app),
        false,
    ))
}

/// The display image as 8-bit sRGB bytes (RGB), tone mapped with `tonemapper`.
fn display_rgb8(img: &image::Rgba32FImage, tonemapper: Tonemapper) -> Vec<u8> {
    img.pixels()
        .flat_map(|p| {
            let c = tonemapper.apply(glam::Vec3::new(p.0[0], p.0[1], p.0[2]));
            [c.x, c.y, c.z].map(|v| {
                (lumen::shading::color::srgb_encode(v.clamp(0.0, 1.0)) * 255.0).round() as u8
            })
        })
        .collect()
}

/// FLIP mean, PSNR (dB) and relative MSE of `img` against `reference`.
pub fn errors(
    img: &image::Rgba32FImage,
    reference: &image::Rgba32FImage,
    tonemapper: Tonemapper,
) -> Result<(f64, f64, f64)> {
    if img.dimensions() != reference.dimensions() {
        return Err(anyhow!("the image and the reference differ in size"));
    }
    let (w, h) = img.dimensions();
    let flip = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &display_rgb8(reference, tonemapper)),
        nv_flip::FlipImageRgb8::with_data(w, h, &display_rgb8(img, tonemapper)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let flip_mean = f64::from(nv_flip::FlipPool::from_image(&flip).mean());
    let (mut se, mut relative) = (0.0f64, 0.0f64);
    for (a, b) in img.pixels().zip(reference.pixels()) {
        for c in 0..3 {
            let (x, y) = (f64::from(a.0[c]), f64::from(b.0[c]));
            let clipped = x.clamp(0.0, 1.0) - y.clamp(0.0, 1.0);
            se += clipped * clipped;
            relative += (x - y) * (x - y) / (y * y + 0.01);
        }
    }
    let n = f64::from(3 * w * h);
    let psnr = 10.0 * (1.0 / (se / n).max(1e-30)).log10();
    Ok((flip_mean, psnr, relative / n))
}

/// Runs every configuration and writes the reports.
pub fn run(args: &TradeoffArgs) -> Result<()> {
    check_scene_args(&args.scene)?;
    if let Some(p) = &args.plot
        && !p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(anyhow!("{}: expected a .png file", p.display()));
    }
    if args.decompose {
        return decompose(args);
    }
    let (reference_image, tonemapper, cached) = match args.against_accumulated {
        Some(n) => accumulated_judge(&args.scene, args.size, n).context("the judge")?,
        None => {
            reference(&args.scene, args.size, args.spp, FULL_REFERENCE).context("the reference")?
        }
    };
    let mut configs = configurations(&args.scene, &Knobs::default());
    if !args.only.is_empty() {
        // A knob is named by its flag or its name (`--aa` or `aa`).
        configs.retain(|(kind, _, _)| {
            args.only
                .iter()
                .any(|o| o == kind || kind.strip_prefix("--") == Some(o.as_str()))
        });
        if configs.is_empty() {
            return Err(anyhow!(
                "--only {}: no row has that knob (the first column's names, e.g. preset, --aa)",
                args.only.join(", ")
            ));
        }
    }
    let shard = crate::shard::resolve(args.shard, args.shards, &crate::shard::process_env)?;
    let total_rows = configs.len() as u32;
    let part = match shard {
        Some(spec) => {
            let json = args
                .json
                .as_ref()
                .filter(|p| p.as_os_str() != "-")
                .context(
                    "a tradeoff shard writes its rows as a part beside --json FILE: give --json",
                )?;
            let settings = format!(
                "{:?}; {}x{}; {} spp; {} frames; judge {:?}; only {:?}",
                args.scene,
                args.size.0,
                args.size.1,
                args.spp,
                args.frames,
                args.against_accumulated,
                args.only
            );
            let scene_hash = crate::shard::scene_hash(&settings, args.scene.file.as_deref())?;
            let part = crate::shard::part_path(json, spec.index, spec.count);
            if let crate::shard::PartState::Done(s) =
                crate::shard::part_state(&part, &settings, &scene_hash, spec.count)
            {
                crate::output::print(&format!(
                    "shard {}/{} ({}): {} is already done (rows {}..{}): skipped\n",
                    spec.index,
                    spec.count,
                    spec.source,
                    part.display(),
                    s.share[0],
                    s.share[1]
                ));
                return Ok(());
            }
            let share = lumen::reference::path::Shard {
                index: spec.index,
                count: spec.count,
            }
            .range(total_rows);
            configs = configs
                .into_iter()
                .skip(share.start as usize)
                .take(share.len())
                .collect();
            Some((spec, part, share, settings, scene_hash))
        }
        None => None,
    };
    let start = std::time::Instant::now();
    let progress = crate::progress::bar(configs.len() as u64, "tradeoff", "configurations");
    let mut rows = Vec::new();
    let mut adapter = None;
    for (kind, setting, scene) in &configs {
        progress.set_message(format!("{kind} {setting}"));
        let mut app = App::headless()?;
        build_scene(&mut app, scene)?;
        // TAA runs frame by frame, as in the viewer: its warm-up fills the history, so
        // the row's time is one frame's and its image the converged one, read after
        // whole jitter sequences (a still camera's history is their plain mean).
        app.set_progressive_taa(true);
        let taa = app.world().resource::<lumen::prelude::Quality>().aa.method
            == lumen::quality::AaMethod::Taa;
        let warmup = if taa {
            let period = lumen::render::post::antialias::taa::TAA_JITTER_PERIOD;
            let rest = (period - args.frames % period) % period;
            if rest < 3 { rest + period } else { rest }
        } else {
            3
        };
        let samples = measure(&mut app, args.size, warmup, args.frames, &|_| {})?;
        let img = app.read_hdr_image()?;
        let frame: Vec<f64> = samples.iter().map(|s| s.frame_ms).collect();
        let gpu: Option<Vec<f64>> = samples.iter().map(|s| s.gpu_ms()).collect();
        let (flip_mean, psnr_db, relative_mse) = errors(&img, &reference_image, tonemapper)?;
        adapter = app.adapter().cloned();
        rows.push(Row {
            kind: kind.clone(),
            setting: setting.clone(),
            frame_ms: Summary::of(&frame).map_or(f64::NAN, |s| s.median),
            gpu_ms: gpu.and_then(|g| Summary::of(&g)).map(|s| s.median),
            flip_mean,
            psnr_db,
            relative_mse,
        });
        progress.inc(1);
    }
    progress.finish_and_clear();
    let adapter = match (adapter, &part) {
        (Some(a), _) => a,
        // A shard with no row still names its adapter.
        (None, Some(_)) => {
            let app = App::headless()?;
            app.adapter().cloned().context("no adapter")?
        }
        (None, None) => anyhow::bail!("no adapter"),
    };
    let title = match args.against_accumulated {
        Some(n) => format!(
            "{} {}x{}, judged against {n} jittered renders of high (--aa none --accumulate {n}), on {} ({})",
            args.scene.label(),
            args.size.0,
            args.size.1,
            adapter.name,
            adapter.backend
        ),
        None => format!(
            "{} {}x{}, reference {} spp, {} on {} ({})",
            args.scene.label(),
            args.size.0,
            args.size.1,
            args.spp,
            if cached { "cached" } else { "traced" },
            adapter.name,
            adapter.backend
        ),
    };
    let table = markdown(&title, &rows);
    crate::output::print(&table);
    if let Some((spec, path, share, settings, scene_hash)) = &part {
        let mut doc = rows_document(args, &adapter, cached, &rows);
        doc["title"] = json!(title);
        doc["shard"] = json!({"index": spec.index, "count": spec.count, "source": spec.source});
        doc["rows_of"] = json!(total_rows);
        write_json(path, &doc)?;
        crate::shard::write_sidecar(
            path,
            "tradeoff",
            args.scene.label(),
            settings.clone(),
            scene_hash.clone(),
            *spec,
            share.clone(),
            0,
            start.elapsed().as_secs_f64(),
        )?;
        crate::output::print(&format!(
            "tradeoff shard {}/{} (index from {}): rows {}..{} of {total_rows}\nwrote {} and its sidecar\n",
            spec.index,
            spec.count,
            spec.source,
            share.start,
            share.end,
            path.display()
        ));
        return Ok(());
    }
    if let Some(path) = &args.out {
        crate::output::write_text(path, &table)?;
    }
    if let Some(path) = &args.json {
        write_json(path, &rows_document(args, &adapter, cached, &rows))?;
    }
    if let Some(path) = &args.plot {
        plot(path, &title, &rows)?;
    }
    Ok(())
}

/// The rows as JSON (schema lumen-tradeoff/1), with the scene, size, adapter and judge.
fn rows_document(
    args: &TradeoffArgs,
    adapter: &lumen::render::device::AdapterSummary,
    cached: bool,
    rows: &[Row],
) -> serde_json::Value {
    json!({
        "schema": "lumen-tradeoff/1",
        "scene": args.scene.label(),
        "size": format!("{}x{}", args.size.0, args.size.1),
        "adapter": {"name": adapter.name, "backend": adapter.backend, "driver": adapter.driver},
        "frames": args.frames,
        "reference": match args.against_accumulated {
            Some(n) => json!({"accumulated_renders": n, "quality": "high", "aa": "none"}),
            None => json!({"spp": args.spp, "max_bounces": REFERENCE_BOUNCES, "cached": cached,
                           "visibility": "smith-correlated", "energy_compensation": true}),
        },
        "rows": rows.iter().map(|r| json!({
            "kind": r.kind, "setting": r.setting, "frame_ms": r.frame_ms, "gpu_ms": r.gpu_ms,
            "flip_mean": r.flip_mean, "psnr_db": r.psnr_db, "relative_mse": r.relative_mse,
        })).collect::<Vec<_>>(),
    })
}

/// The rows of a tradeoff document (schema lumen-tradeoff/1), as [`markdown`] takes
/// them; an error naming what is missing.
pub fn rows_of(doc: &serde_json::Value) -> Result<Vec<Row>> {
    let rows = doc["rows"].as_array().context("no \"rows\" array")?;
    rows.iter()
        .map(|r| {
            let text = |k: &str| {
                r[k].as_str()
                    .map(str::to_string)
                    .with_context(|| format!("a row without \"{k}\""))
            };
            let number = |k: &str| {
                r[k].as_f64()
                    .with_context(|| format!("a row without \"{k}\""))
            };
            Ok(Row {
                kind: text("kind")?,
                setting: text("setting")?,
                frame_ms: number("frame_ms")?,
                gpu_ms: r["gpu_ms"].as_f64(),
                flip_mean: number("flip_mean")?,
                psnr_db: number("psnr_db")?,
                relative_mse: number("relative_mse")?,
            })
        })
        .collect()
}

/// One part of the decomposed error: what was compared with what, and the errors.
struct Part {
    name: &'static str,
    compared: &'static str,
    flip_mean: f64,
    psnr_db: f64,
    relative_mse: f64,
}

/// `--decompose`: splits the frame's error against the full reference into what its
/// shading gets wrong (its direct light against the direct-light reference with the
/// frame's light visibility), what its unshadowed lights cost, what indirect light is
/// worth in the scene, and the total, which holds what the frame does not transport;
/// then the two measures of the judge: its own noise, and what a uniform error of 1 % and
/// 3 % costs on the scene.
fn decompose(args: &TradeoffArgs) -> Result<()> {
    let direct = |visibility| ReferenceKind {
        bounces: 1,
        visibility,
        seed: 0,
    };
    let (direct_reference, tonemapper, _) = reference(
        &args.scene,
        args.size,
        args.spp,
        direct(LightVisibility::AsFrame),
    )
    .context("the direct-light reference with the frame's visibility")?;
    let (direct_physical, _, _) = reference(
        &args.scene,
        args.size,
        args.spp,
        direct(LightVisibility::Physical),
    )
    .context("the direct-light reference")?;
    let (full, _, _) =
        reference(&args.scene, args.size, args.spp, FULL_REFERENCE).context("the reference")?;
    let (second, _, _) = reference(
        &args.scene,
        args.size,
        args.spp,
        ReferenceKind {
            seed: 1,
            ..FULL_REFERENCE
        },
    )
    .context("the second reference (another seed)")?;
    // The frame as configured, and its direct-light part: the same frame without the
    // passes that add indirect light (AO, reflections, the irradiance volume and the
    // reflection probes).
    let mut app = App::headless()?;
    build_scene(&mut app, &args.scene)?;
    let samples = measure(&mut app, args.size, 3, args.frames, &|_| {})?;
    let frame_ms = Summary::of(&samples.iter().map(|s| s.frame_ms).collect::<Vec<_>>())
        .map_or(f64::NAN, |s| s.median);
    let frame = app.read_hdr_image()?;
    let mut direct_app = App::headless()?;
    let mut direct_args = args.scene.clone();
    direct_args.knobs.set(&AO, Value::Name("off"));
    direct_args.knobs.set(&SSR, Value::Bool(false));
    direct_args.knobs.set(&GI, Value::Bool(false));
    direct_args
        .knobs
        .set(&REFLECTION_PROBES, Value::Bool(false));
    build_scene(&mut direct_app, &direct_args)?;
    direct_app.render_headless(args.size)?;
    let direct_frame = direct_app.read_hdr_image()?;
    let part = |name, compared, a: &image::Rgba32FImage, b: &image::Rgba32FImage| -> Result<Part> {
        let (flip_mean, psnr_db, relative_mse) = errors(a, b, tonemapper)?;
        Ok(Part {
            name,
            compared,
            flip_mean,
            psnr_db,
            relative_mse,
        })
    };
    let parts = [
        part(
            "implementation",
            "the frame without AO, reflections and probes against direct light with the frame's light visibility",
            &direct_frame,
            &direct_reference,
        )?,
        part(
            "unshadowed lights",
            "direct light with the frame's visibility against physical visibility",
            &direct_reference,
            &direct_physical,
        )?,
        part(
            "indirect light",
            "direct light against all light (8 bounces), both physical: what the scene's indirect light is worth",
            &direct_physical,
            &full,
        )?,
        part(
            "total",
            "the frame against the full reference: what it does not transport, and the rest",
            &frame,
            &full,
        )?,
        part(
            "reference noise",
            "the full reference against a second one traced with another seed: the judge's own noise, below which no frame can be measured",
            &second,
            &full,
        )?,
        part(
            "1 % brighter",
            "the full reference 1 % brighter against itself: what a uniform error of 1 % costs on this scene (FLIP's scale)",
            &brighter(&full, 1.01),
            &full,
        )?,
        part(
            "3 % brighter",
            "the full reference 3 % brighter against itself: what a uniform error of 3 % costs on this scene",
            &brighter(&full, 1.03),
            &full,
        )?,
    ];
    let adapter = app.adapter().cloned().context("no adapter")?;
    let quality = crate::setup::preset_name(app.world().resource::<lumen::prelude::Quality>());
    let title = format!(
        "{} {}x{}, {quality}, {:.2} ms/frame, references {} spp, on {} ({})",
        args.scene.label(),
        args.size.0,
        args.size.1,
        frame_ms,
        args.spp,
        adapter.name,
        adapter.backend
    );
    let mut table = format!(
        "{title}\n\n| part | compared | FLIP mean | PSNR (dB) | relative MSE |\n| --- | --- | --- | --- | --- |\n"
    );
    for p in &parts {
        table += &format!(
            "| {} | {} | {:.4} | {:.2} | {:.2e} |\n",
            p.name, p.compared, p.flip_mean, p.psnr_db, p.relative_mse
        );
    }
    table += "\nFLIP is not additive: the parts show where the error comes from, not a sum.\n";
    crate::output::print(&table);
    if let Some(path) = &args.out {
        crate::output::write_text(path, &table)?;
    }
    if let Some(path) = &args.json {
        let doc = json!({
            "schema": "lumen-tradeoff-decompose/1",
            "scene": args.scene.label(),
            "size": format!("{}x{}", args.size.0, args.size.1),
            "quality": quality,
            "frame_ms": frame_ms,
            "adapter": {"name": adapter.name, "backend": adapter.backend, "driver": adapter.driver},
            "reference": {"spp": args.spp, "max_bounces": REFERENCE_BOUNCES},
            "parts": parts.iter().map(|p| json!({
                "part": p.name, "compared": p.compared, "flip_mean": p.flip_mean,
                "psnr_db": p.psnr_db, "relative_mse": p.relative_mse,
            })).collect::<Vec<_>>(),
        });
        write_json(path, &doc)?;
    }
    Ok(())
}

/// `img` with its colour multiplied by `k` and its alpha kept.
fn brighter(img: &image::Rgba32FImage, k: f32) -> image::Rgba32FImage {
    let mut out = img.clone();
    for p in out.pixels_mut() {
        for c in &mut p.0[..3] {
            *c *= k;
        }
    }
    out
}

/// Writes `doc` as pretty JSON to `path`, or to standard output for "-".
fn write_json(path: &Path, doc: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(doc)?;
    if path.as_os_str() == "-" {
        crate::output::print(&format!("{text}\n"));
        Ok(())
    } else {
        crate::output::write_text(path, &text)
    }
}

/// The table: one row per configuration.
pub fn markdown(title: &str, rows: &[Row]) -> String {
    let mut s = format!(
        "{title}\n\n| setting | ms/frame | GPU ms | FLIP mean | PSNR (dB) | relative MSE |\n| --- | --- | --- | --- | --- | --- |\n"
    );
    for r in rows {
        s += &format!(
            "| {} | {:.2} | {} | {:.4} | {:.2} | {:.2e} |\n",
            r.label(),
            r.frame_ms,
            r.gpu_ms.map_or("—".into(), |g| format!("{g:.2}")),
            r.flip_mean,
            r.psnr_db,
            r.relative_mse
        );
    }
    s
}

/// Indices of the rows no other row beats in both time and FLIP error, fastest first.
pub fn pareto_front(rows: &[Row]) -> Vec<usize> {
    let mut front: Vec<usize> = (0..rows.len())
        .filter(|&i| {
            !rows.iter().any(|o| {
                o.frame_ms <= rows[i].frame_ms
                    && o.flip_mean <= rows[i].flip_mean
                    && (o.frame_ms < rows[i].frame_ms || o.flip_mean < rows[i].flip_mean)
            })
        })
        .collect();
    front.sort_by(|&a, &b| rows[a].frame_ms.total_cmp(&rows[b].frame_ms));
    front
}

fn plot(path: &Path, title: &str, rows: &[Row]) -> Result<()> {
    plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        crate::commands::bench::plot::FONT,
    )
    .map_err(|_| anyhow!("the bundled chart font does not load"))?;
    let draw = |e: &dyn std::fmt::Display| anyhow!("drawing {}: {e}", path.display());
    let x_max = rows.iter().map(|r| r.frame_ms).fold(0.0, f64::max) * 1.15;
    let y_max = rows.iter().map(|r| r.flip_mean).fold(0.0, f64::max) * 1.15;
    crate::commands::bench::plot::draw_png(path, |root| {
        root.fill(&WHITE).map_err(|e| draw(&e))?;
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..x_max.max(1e-3), 0.0..y_max.max(1e-4))
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc("ms per frame")
            .y_desc("FLIP mean against the reference")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| draw(&e))?;
        let front = pareto_front(rows);
        chart
            .draw_series(LineSeries::new(
                front.iter().map(|&i| (rows[i].frame_ms, rows[i].flip_mean)),
                RGBColor(214, 39, 40).stroke_width(2),
            ))
            .map_err(|e| draw(&e))?;
        for (i, r) in rows.iter().enumerate() {
            let color = if front.contains(&i) {
                RGBColor(214, 39, 40)
            } else {
                RGBColor(31, 119, 180)
            };
            chart
                .draw_series(std::iter::once(Circle::new(
                    (r.frame_ms, r.flip_mean),
                    5,
                    color.filled(),
                )))
                .map_err(|e| draw(&e))?;
            chart
                .draw_series(std::iter::once(Text::new(
                    r.label(),
                    (r.frame_ms, r.flip_mean),
                    ("sans-serif", 12),
                )))
                .map_err(|e| draw(&e))?;
        }
        Ok(())
    })
}

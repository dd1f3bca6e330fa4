//! `lumen bench`: frame times of a scene, per pass on the GPU (timestamp queries) and per
//! stage on the CPU, summarised (mean, median, p95, p99, min, max, standard deviation),
//! written as JSON, CSV and a chart, and compared between runs.

pub mod compare;
pub mod plot;
pub mod rays;
pub mod report;

use super::view::{WindowOptions, WindowScene, run_window};
use crate::cli::{BenchArgs, ViewArgs};
use crate::measure::{FrameSample, WindowFrames, measure};
use crate::output::write_text;
use crate::setup::{build_scene, check_scene_args, preset_name};
use anyhow::{Context, Result, anyhow};
use lumen::App;
use lumen::prelude::Quality;
use report::RunInfo;
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

/// Runs the benchmark (or the comparison) the arguments ask for.
pub fn run(args: &BenchArgs) -> Result<()> {
    if let Some([a, b]) = args.compare.as_deref() {
        let rows = compare::compare(a, b)?;
        crate::output::print(&compare::to_text(a, b, &rows));
        return Ok(());
    }
    check_scene_args(&args.scene)?;
    if let Some(n) = args.rays {
        return rays::run(args, n);
    }
    for (path, ext) in [(&args.csv, "csv"), (&args.plot, "png")] {
        if let Some(p) = path
            && !p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
        {
            return Err(anyhow!("{}: expected a .{ext} file", p.display()));
        }
    }
    let total = args.warmup + args.frames;
    let bar = crate::progress::bar(u64::from(total), "bench", "frames");
    let started_unix_s = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (samples, app, mode) = if args.window {
        let (samples, app) = window(args, &bar)?;
        (samples, app, "window")
    } else {
        let (samples, app) = headless(args, &bar)?;
        (samples, app, "headless")
    };
    bar.finish_and_clear();

    let adapter = app.adapter().cloned().context("no adapter")?;
    let quality = app.world().resource::<Quality>().clone();
    let last = samples
        .last()
        .ok_or_else(|| anyhow!("no frame was measured"))?;
    let info = RunInfo {
        mode,
        scene: args.scene.label(),
        size: args.size,
        preset: preset_name(&quality),
        quality: app
            .world()
            .resource::<lumen::quality::Knobs>()
            .json(&quality),
        adapter: [
            adapter.name.clone(),
            adapter.backend.to_string(),
            adapter.device_type.to_string(),
            adapter.driver.clone(),
        ],
        timestamps: last.gpu_ms().is_some(),
        warmup: args.warmup,
        scene_stats: scene_stats(&app),
        memory: app
            .world()
            .resource::<lumen::render::graph::FramePlan>()
            .memory(),
        started_unix_s,
    };
    let json = report::to_json(&info, &samples);
    match args.json.as_deref() {
        Some(p) if p == Path::new("-") => crate::output::print(&format!("{json}\n")),
        Some(p) => write_text(p, &format!("{json:#}\n"))?,
        None => {}
    }
    if let Some(p) = &args.csv {
        write_text(p, &report::to_csv(&samples))?;
    }
    if let Some(p) = &args.plot {
        let title = format!(
            "{} {}x{}, {}, {} ({})",
            info.scene, info.size.0, info.size.1, info.preset, adapter.name, adapter.backend
        );
        plot::plot(p, &title, &samples)?;
    }
    let text = report::summary_text(&info, &samples);
    if args.json.as_deref() == Some(Path::new("-")) {
        eprint!("{text}");
    } else {
        crate::output::print(&text);
    }
    Ok(())
}

/// Offscreen frames: ECS update, then the frame up to the GPU finishing.
fn headless(args: &BenchArgs, bar: &indicatif::ProgressBar) -> Result<(Vec<FrameSample>, App)> {
    let mut app = App::headless()?;
    crate::progress::show_ibl_progress(&mut app);
    build_scene(&mut app, &args.scene)?;
    // TAA frame by frame, as in the viewer.
    app.set_progressive_taa(true);
    let samples = measure(&mut app, args.size, args.warmup, args.frames, &|done| {
        bar.set_position(u64::from(done))
    })?;
    Ok((samples, app))
}

/// Frames in a window without vsync or panel (see [`WindowFrames`] for what a frame's
/// time is).
fn window(args: &BenchArgs, bar: &indicatif::ProgressBar) -> Result<(Vec<FrameSample>, App)> {
    let view = ViewArgs::new(args.scene.clone(), args.size);
    let options = WindowOptions {
        size: args.size,
        panel: false,
        shader_dir: None,
        ..WindowOptions::default()
    };
    let b = bar.clone();
    let frames = WindowFrames::new(
        args.warmup,
        args.frames,
        Box::new(move |done| b.set_position(u64::from(done))),
    );
    let (samples, app) = run_window(WindowScene::Args(Box::new(view)), options, Some(frames))?;
    let app = app.ok_or_else(|| anyhow!("the window never opened"))?;
    if samples.len() < args.frames as usize {
        return Err(anyhow!(
            "the window closed after {} of {} measured frames",
            samples.len(),
            args.frames
        ));
    }
    Ok((samples, app))
}

fn scene_stats(app: &App) -> [usize; 4] {
    app.world()
        .get_resource::<lumen::render::extract::ExtractedFrame>()
        .map_or([0; 4], |f| {
            [
                f.instances.len(),
                f.draws(),
                usize::try_from(f.triangles).unwrap_or(usize::MAX),
                f.light_counts.total() as usize,
            ]
        })
}

//! `lumen render`: one frame to a PNG or EXR file, with a timing report.

use crate::cli::RenderArgs;
use crate::sequence;
use crate::setup::{build_scene, check_scene_args, hold_animations};
use anyhow::{Context, Result, anyhow};
use lumen::App;
use lumen::assets::image_io::{OutputFormat, save_exr, save_png};
use lumen::choice::Choice;
use lumen::prelude::Quality;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Renders, writes the image (or, with `--frames`, each frame of the sequence) and prints
/// the report. Returns the path written last.
pub fn run(args: &RenderArgs) -> Result<PathBuf> {
    let Some((first, last)) = args.frames else {
        return render_frame(args);
    };
    let pattern = args
        .out
        .clone()
        .filter(|p| p.file_name().is_some_and(|n| n.to_string_lossy().contains('#')))
        .ok_or_else(|| {
            anyhow!(
                "--frames needs --out with #s in the file name for the frame number, e.g. --out seq/frame-####.png"
            )
        })?;
    check_scene_args(&args.scene)?;
    let shard = crate::shard::resolve(args.shard, args.shards, &crate::shard::process_env)?;
    let Some(spec) = shard else {
        let mut written = pattern.clone();
        for k in first..=last {
            written = render_sequence_frame(args, &pattern, k)?;
        }
        return Ok(written);
    };
    let start = std::time::Instant::now();
    let share = lumen::reference::path::Shard {
        index: spec.index,
        count: spec.count,
    }
    .range(last - first + 1);
    let frames = first + share.start..first + share.end;
    let settings = format!(
        "{:?}; {}x{}; frames {first}..{last} at {} fps; {}",
        args.scene,
        args.size.0,
        args.size.1,
        args.fps,
        pattern.file_name().unwrap_or_default().to_string_lossy()
    );
    let scene_hash = crate::shard::scene_hash(&settings, args.scene.file.as_deref())?;
    let manifest_path = sequence::manifest_path(&pattern, spec.index, spec.count);
    let label = |frames: &std::ops::Range<u32>| {
        if frames.is_empty() {
            "no frames".to_string()
        } else {
            format!("frames {}..{}", frames.start, frames.end - 1)
        }
    };
    // Frames on disk are kept only when they can be from these settings: the manifest is
    // this render's, or there is none yet (a shard stopped before writing it).
    let state = crate::shard::part_state(&manifest_path, &settings, &scene_hash, spec.count);
    let manifest = match state {
        crate::shard::PartState::Done(_) => match sequence::read(&manifest_path) {
            Ok(m) => Some(m),
            Err(e) => {
                log::warn!("{e:#}");
                None
            }
        },
        _ => None,
    };
    if let Some(m) = &manifest {
        match sequence::check_frames(&manifest_path, m) {
            Ok(()) => {
                crate::output::print(&format!(
                    "shard {}/{} ({}): {} are already done ({}): skipped\n",
                    spec.index,
                    spec.count,
                    spec.source,
                    label(&frames),
                    manifest_path.display()
                ));
                return Ok(manifest_path);
            }
            Err(e) => log::warn!("{e:#}"),
        }
    }
    let keep_frames = !matches!(state, crate::shard::PartState::OtherSettings);
    // A frame the manifest lists is kept only with the checksum it recorded (a damaged
    // file may still decode); without a manifest, a frame that decodes is kept (frames
    // are written whole, by a rename).
    let recorded: std::collections::HashMap<u32, String> = manifest
        .into_iter()
        .flat_map(|m| m.frames)
        .map(|e| (e.frame, e.hash))
        .collect();
    let whole = |path: &std::path::Path, k: u32| match recorded.get(&k) {
        Some(hash) => sequence::FrameEntry::of(path, k).is_ok_and(|e| e.hash == *hash),
        None => image::open(path).is_ok(),
    };
    crate::output::print(&format!(
        "shard {}/{} (index from {}): {}\n",
        spec.index,
        spec.count,
        spec.source,
        label(&frames)
    ));
    let mut entries = Vec::new();
    for k in frames.clone() {
        let path = frame_path(&pattern, k);
        // A shard re-run after a failure redoes only the frames that are not whole.
        if keep_frames && whole(&path, k) {
            crate::output::print(&format!("frame {k}: {} exists: skipped\n", path.display()));
        } else {
            render_sequence_frame(args, &pattern, k)?;
        }
        entries.push(sequence::FrameEntry::of(&path, k)?);
    }
    let manifest = sequence::Manifest {
        schema: sequence::MANIFEST_SCHEMA.into(),
        pattern: pattern
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned(),
        frames_of: [first, last],
        fps: args.fps,
        frames: entries,
    };
    lumen::files::write_atomic(
        &manifest_path,
        serde_json::to_string_pretty(&manifest)?.as_bytes(),
    )?;
    crate::shard::write_sidecar(
        &manifest_path,
        "sequence",
        args.scene.label(),
        settings,
        scene_hash,
        spec,
        frames,
        0,
        start.elapsed().as_secs_f64(),
    )?;
    crate::output::print(&format!(
        "wrote {} (this shard's frames) and its sidecar\n",
        manifest_path.display()
    ));
    Ok(manifest_path)
}

/// Frame `k` of the sequence `pattern`, posed at k / fps seconds.
fn render_sequence_frame(args: &RenderArgs, pattern: &Path, k: u32) -> Result<PathBuf> {
    let mut frame = args.clone();
    frame.frames = None;
    frame.scene.time = Some(k as f32 / args.fps);
    frame.out = Some(frame_path(pattern, k));
    render_frame(&frame).with_context(|| format!("frame {k}"))
}

/// `pattern` with its last run of `#`s replaced by `frame`, zero-padded to the run's
/// length (`frame-####.png`, 7 → `frame-0007.png`; a longer number is written whole).
pub fn frame_path(pattern: &Path, frame: u32) -> PathBuf {
    let text = pattern.to_string_lossy();
    let Some(end) = text.rfind('#') else {
        return pattern.to_path_buf();
    };
    let start = text[..end].trim_end_matches('#').len();
    let width = end + 1 - start;
    PathBuf::from(format!(
        "{}{frame:0width$}{}",
        &text[..start],
        &text[end + 1..]
    ))
}

/// One frame: renders, writes the image and prints the report. An animated file is held
/// at `--time`, or at 0 s.
fn render_frame(args: &RenderArgs) -> Result<PathBuf> {
    check_scene_args(&args.scene)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/{}.png", args.scene.label())));
    let format = OutputFormat::from_path(&out)?;

    let mut app = App::headless()?;
    crate::progress::show_ibl_progress(&mut app);
    build_scene(&mut app, &args.scene)?;
    if args.scene.time.is_none() {
        hold_animations(&mut app, 0.0);
    }
    let pixels = u64::from(args.size.0) * u64::from(args.size.1);
    let stages = crate::progress::stages(
        pixels >= crate::progress::LONG_FRAME_PIXELS,
        &format!("rendering {}x{}", args.size.0, args.size.1),
    );
    stages.set_message("first frame (compiling pipelines)");
    // The first frame compiles the pipelines the scene needs; the second is measured.
    // Automatic exposure first adapts: frames at a fixed 1/30 s until the meter settles.
    let first = app.render_headless(args.size)?;
    let mut adaptation_frames = 0;
    if first.plan.runs(lumen::render::graph::PassId::Exposure) {
        app.set_fixed_delta(Some(1.0 / 30.0));
        for _ in 0..240 {
            let r = app.render_headless(args.size)?;
            adaptation_frames += 1;
            match (r.metered.ev100, r.metered.target_ev100) {
                (Some(ev), Some(target)) if (ev - target).abs() < 0.01 => break,
                _ => {}
            }
        }
    }
    stages.set_message("measured frame");
    let report = app.render_headless(args.size)?;
    for note in &report.notes {
        log::warn!("camera: {note}");
    }
    if args.explain {
        eprint!("{}", report.plan.explain());
    }
    stages.set_message(format!("reading back and writing {}", out.display()));
    save_frame(&app, &out, format)?;
    stages.finish_and_clear();

    let adapter = app.adapter().cloned().context("no adapter")?;
    let gpu_total: Option<f64> = report.passes.iter().map(|p| p.gpu_ms).sum();
    let quality = app.world().resource::<Quality>().clone();
    let tonemapper = report_tonemapper(&app);
    if args.json {
        let value = json!({
            "scene": args.scene.label(),
            "adapter": adapter.name,
            "backend": adapter.backend,
            "device_type": adapter.device_type,
            "driver": adapter.driver,
            "size": format!("{}x{}", args.size.0, args.size.1),
            "width": args.size.0,
            "height": args.size.1,
            "out": out.display().to_string(),
            "format": match format { OutputFormat::Png => "png", OutputFormat::Exr => "exr" },
            "exposure": report.exposure,
            "ev100": report.ev100,
            "tonemapper": tonemapper,
            "visibility": quality.visibility.name(),
            "quality": app.world().resource::<lumen::quality::Knobs>().json(&quality),
            "frame_ms": report.frame_ms,
            "first_frame_ms": first.frame_ms,
            "gpu_ms": gpu_total,
            "passes": report.passes.iter().map(|p| json!({
                "name": p.name, "gpu_ms": p.gpu_ms, "cpu_ms": p.cpu_ms,
            })).collect::<Vec<_>>(),
            "stages": report.stages.iter().map(|(name, ms)| json!({
                "name": name, "cpu_ms": ms,
            })).collect::<Vec<_>>(),
            "plan": {
                "passes": report.plan.passes.iter().map(|(_, d)| json!({
                    "name": d.name, "runs": d.enabled, "reason": d.reason,
                })).collect::<Vec<_>>(),
                "features": report.plan.features.iter().map(|d| json!({
                    "name": d.name, "enabled": d.enabled, "reason": d.reason,
                })).collect::<Vec<_>>(),
                "memory": report.plan.memory(),
            },
            "accumulated": report.accumulated,
            "temporal_frames": report.temporal_frames,
            "camera_notes": report.notes,
            "auto_exposure": report.metered.ev100.map(|ev| json!({
                "ev100": ev,
                "target_ev100": report.metered.target_ev100,
                "average_log2_luminance": report.metered.average_log2_luminance,
                "adaptation_frames": adaptation_frames,
            })),
            "preprocessing": first.preprocessing.iter().map(|(step, ms)| json!({
                "step": step, "ms": ms,
            })).collect::<Vec<_>>(),
            "probes": {
                "volume_probes": first.probes.volume.counts.to_array(),
                "volume_passes": first.probes.volume.passes.0,
                "faces_captured": first.probes.volume.faces_captured,
                "reflection_probes": first.probes.reflections.probes,
                "reflection_probes_captured": first.probes.reflections.captured,
                "capture_ms": first.probes.capture_ms,
            },
            "stats": {
                "instances": report.stats.instances,
                "draws": report.stats.draws,
                "triangles": report.stats.triangles,
                "lights": report.stats.lights,
            },
        });
        crate::output::print(&format!("{value}\n"));
    } else {
        let mut text = String::new();
        use std::fmt::Write as _;
        let _ = writeln!(
            text,
            "rendered {} at {}x{} on {} ({}, {})",
            args.scene.label(),
            args.size.0,
            args.size.1,
            adapter.name,
            adapter.backend,
            adapter.device_type
        );
        for p in &report.passes {
            let _ = match p.gpu_ms {
                Some(g) => writeln!(
                    text,
                    "  {:<10} gpu {g:8.3} ms   cpu {:7.3} ms",
                    p.name, p.cpu_ms
                ),
                None => writeln!(
                    text,
                    "  {:<10} gpu      n/a      cpu {:7.3} ms",
                    p.name, p.cpu_ms
                ),
            };
        }
        let _ = writeln!(
            text,
            "frame {:.2} ms (first frame, compiling pipelines: {:.1} ms); exposure {:.3e} (EV100 {:.2}), tone mapper {tonemapper}",
            report.frame_ms, first.frame_ms, report.exposure, report.ev100
        );
        if report.accumulated > 1 {
            let _ = writeln!(
                text,
                "accumulated {} jittered renders (box pixel filter); the times above are their sums",
                report.accumulated
            );
        }
        if report.temporal_frames > 1 {
            let _ = writeln!(
                text,
                "temporal anti-aliasing: {} jittered frames from a fresh history (a still camera's image converges in that many); the times above are their sums",
                report.temporal_frames
            );
        }
        if !first.preprocessing.is_empty() {
            let steps: Vec<String> = first
                .preprocessing
                .iter()
                .map(|(step, ms)| format!("{step} {ms:.1} ms"))
                .collect();
            let _ = writeln!(text, "one-off preprocessing: {}", steps.join(", "));
        }
        let probes = &first.probes;
        if probes.volume.faces_captured > 0 || probes.reflections.captured > 0 {
            let c = probes.volume.counts;
            let _ = writeln!(
                text,
                "probe captures: {}×{}×{} irradiance probes ({} passes, {} faces), {} reflection probe(s): {:.1} ms",
                c.x,
                c.y,
                c.z,
                probes.volume.passes.0,
                probes.volume.faces_captured,
                probes.reflections.captured,
                probes.capture_ms
            );
        }
        let _ = writeln!(text, "wrote {}", out.display());
        crate::output::print(&text);
    }
    Ok(out)
}

fn report_tonemapper(app: &App) -> &'static str {
    app.world()
        .get_resource::<lumen::render::extract::ExtractedFrame>()
        .and_then(|f| f.camera.as_ref())
        .map(|c| c.tonemapper.name())
        .unwrap_or("none")
}

/// Saves the last headless frame of `app` as `out`: the display image for PNG, exposed
/// linear HDR for EXR (parent folders are created).
pub fn save_frame(app: &App, out: &Path, format: OutputFormat) -> Result<()> {
    match format {
        OutputFormat::Png => save_png(out, &app.read_display_image()?),
        OutputFormat::Exr => save_exr(out, &app.read_hdr_image()?),
    }
    .with_context(|| format!("writing {}", out.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_numbers_fill_the_last_run_of_hashes() {
        let p = |s: &str, k| frame_path(Path::new(s), k).display().to_string();
        assert_eq!(p("seq/frame-####.png", 7), "seq/frame-0007.png");
        assert_eq!(p("a#/f-##.exr", 123), "a#/f-123.exr");
        assert_eq!(p("#", 0), "0");
    }
}

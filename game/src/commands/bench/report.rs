//! What a benchmark recorded: per-frame samples, their summaries as the JSON report
//! (schema `lumen-bench/1`, README "Benchmarking"), the CSV and the terminal summary.

use crate::measure::FrameSample;
use crate::measure::stats::Summary;
use serde_json::{Value, json};
use std::fmt::Write as _;

/// The schema name written into every report.
pub const SCHEMA: &str = "lumen-bench/1";

/// Everything about the run that is not a timing.
#[derive(Clone, Debug)]
pub struct RunInfo {
    /// `headless` or `window`.
    pub mode: &'static str,
    /// Built-in scene name or file stem.
    pub scene: String,
    /// Image size (px).
    pub size: (u32, u32),
    /// The preset whose knobs the run used, or `custom`.
    pub preset: String,
    /// Every quality knob, as JSON.
    pub quality: Value,
    /// Adapter name, backend, device type, driver.
    pub adapter: [String; 4],
    /// Whether the adapter timed passes on the GPU.
    pub timestamps: bool,
    /// Frames rendered and thrown away before measuring.
    pub warmup: u32,
    /// Instances, draws, triangles, lights of the last frame.
    pub scene_stats: [usize; 4],
    /// Seconds since the Unix epoch when measuring began.
    pub started_unix_s: u64,
    /// The bytes the last frame's graph resources took.
    pub memory: lumen::render::graph::Memory,
}

/// Names in first-seen order across `samples`.
fn names<'a>(
    samples: &'a [FrameSample],
    of: impl Fn(&'a FrameSample) -> Vec<&'a str>,
) -> Vec<&'a str> {
    let mut out: Vec<&str> = Vec::new();
    for s in samples {
        for n in of(s) {
            if !out.contains(&n) {
                out.push(n);
            }
        }
    }
    out
}

fn pass_names(samples: &[FrameSample]) -> Vec<&str> {
    names(samples, |s| s.passes.iter().map(|p| p.name).collect())
}

fn stage_names(samples: &[FrameSample]) -> Vec<&str> {
    names(samples, |s| s.stages.iter().map(|(n, _)| *n).collect())
}

fn summary_json(values: &[f64]) -> Value {
    Summary::of(values).map_or(Value::Null, |s| s.to_json())
}

fn pass_values(samples: &[FrameSample], name: &str, gpu: bool) -> Option<Vec<f64>> {
    samples
        .iter()
        .filter_map(|s| s.passes.iter().find(|p| p.name == name))
        .map(|p| if gpu { p.gpu_ms } else { Some(p.cpu_ms) })
        .collect()
}

fn stage_values(samples: &[FrameSample], name: &str) -> Vec<f64> {
    samples
        .iter()
        .filter_map(|s| s.stages.iter().find(|(n, _)| *n == name).map(|(_, v)| *v))
        .collect()
}

/// The JSON report (schema [`SCHEMA`]).
pub fn to_json(info: &RunInfo, samples: &[FrameSample]) -> Value {
    let frame: Vec<f64> = samples.iter().map(|s| s.frame_ms).collect();
    let gpu: Option<Vec<f64>> = samples.iter().map(FrameSample::gpu_ms).collect();
    let [name, backend, device_type, driver] = info.adapter.clone();
    let [instances, draws, triangles, lights] = info.scene_stats;
    json!({
        "schema": SCHEMA,
        "lumen_version": env!("CARGO_PKG_VERSION"),
        "git_revision": env!("LUMEN_GIT_REVISION"),
        "build_profile": if cfg!(debug_assertions) { "debug" } else { "release" },
        "mode": info.mode,
        "scene": info.scene,
        "size": format!("{}x{}", info.size.0, info.size.1),
        "width": info.size.0,
        "height": info.size.1,
        "preset": info.preset,
        "quality": info.quality,
        "adapter": {"name": name, "backend": backend, "device_type": device_type, "driver": driver},
        "timestamps": info.timestamps,
        "warmup_frames": info.warmup,
        "frames": samples.len(),
        "started_unix_s": info.started_unix_s,
        "scene_stats": {"instances": instances, "draws": draws, "triangles": triangles, "lights": lights},
        "memory": info.memory,
        "frame_ms": summary_json(&frame),
        "gpu_ms": gpu.as_deref().map_or(Value::Null, summary_json),
        "cpu_stages": stage_names(samples).iter().map(|n| json!({
            "name": n, "ms": summary_json(&stage_values(samples, n)),
        })).collect::<Vec<_>>(),
        "passes": pass_names(samples).iter().map(|n| json!({
            "name": n,
            "gpu_ms": pass_values(samples, n, true).as_deref().map_or(Value::Null, summary_json),
            "cpu_ms": pass_values(samples, n, false).as_deref().map_or(Value::Null, summary_json),
        })).collect::<Vec<_>>(),
    })
}

/// One row per frame: `frame,frame_ms,gpu_ms,<stage>_ms…,<pass>_gpu_ms,<pass>_cpu_ms…`;
/// an empty cell where a value is missing.
pub fn to_csv(samples: &[FrameSample]) -> String {
    let passes = pass_names(samples);
    let stages = stage_names(samples);
    let mut out = String::from("frame,frame_ms,gpu_ms");
    for s in &stages {
        let _ = write!(out, ",{s}_ms");
    }
    for p in &passes {
        let col = p.replace(' ', "_");
        let _ = write!(out, ",{col}_gpu_ms,{col}_cpu_ms");
    }
    out.push('\n');
    let cell = |v: Option<f64>| v.map(|v| format!("{v:.6}")).unwrap_or_default();
    for (i, s) in samples.iter().enumerate() {
        let _ = write!(out, "{i},{:.6},{}", s.frame_ms, cell(s.gpu_ms()));
        for name in &stages {
            let v = s.stages.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
            let _ = write!(out, ",{}", cell(v));
        }
        for name in &passes {
            let p = s.passes.iter().find(|p| p.name == *name);
            let _ = write!(
                out,
                ",{},{}",
                cell(p.and_then(|p| p.gpu_ms)),
                cell(p.map(|p| p.cpu_ms))
            );
        }
        out.push('\n');
    }
    out
}

/// The terminal summary: median, p95 and mean of the frame, the GPU total, each pass
/// and each CPU stage.
pub fn summary_text(info: &RunInfo, samples: &[FrameSample]) -> String {
    let mut out = String::new();
    let [name, backend, device_type, _] = &info.adapter;
    let _ = writeln!(
        out,
        "bench {} {}x{} ({}, preset {}) on {name} ({backend}, {device_type}): {} frames after {} warm-up",
        info.scene,
        info.size.0,
        info.size.1,
        info.mode,
        info.preset,
        samples.len(),
        info.warmup
    );
    let _ = writeln!(
        out,
        "  {:<22} {:>10} {:>10} {:>10} {:>10}",
        "", "median", "p95", "mean", "std"
    );
    let mut row = |label: &str, values: Option<Vec<f64>>| {
        if let Some(s) = values.as_deref().and_then(Summary::of) {
            let _ = writeln!(
                out,
                "  {label:<22} {:>7.2} ms {:>7.2} ms {:>7.2} ms {:>7.2} ms",
                s.median, s.p95, s.mean, s.std
            );
        }
    };
    row("frame", Some(samples.iter().map(|s| s.frame_ms).collect()));
    row(
        "gpu (all passes)",
        samples.iter().map(FrameSample::gpu_ms).collect(),
    );
    for p in pass_names(samples) {
        row(&format!("  {p} (gpu)"), pass_values(samples, p, true));
    }
    for s in stage_names(samples) {
        row(&format!("cpu {s}"), Some(stage_values(samples, s)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use lumen::render::timing::PassTiming;

    fn sample(frame: f64, gpu: [f64; 2]) -> FrameSample {
        FrameSample {
            frame_ms: frame,
            stages: vec![("update", 0.1), ("wait", frame * 0.5)],
            passes: vec![
                PassTiming {
                    name: "gbuffer",
                    cpu_ms: 0.01,
                    gpu_ms: Some(gpu[0]),
                },
                PassTiming {
                    name: "lighting",
                    cpu_ms: 0.02,
                    gpu_ms: Some(gpu[1]),
                },
            ],
        }
    }

    fn info() -> RunInfo {
        RunInfo {
            mode: "headless",
            scene: "spheres".into(),
            size: (64, 32),
            preset: "high".into(),
            quality: json!({}),
            adapter: ["a".into(), "vulkan".into(), "cpu".into(), "d".into()],
            timestamps: true,
            warmup: 1,
            scene_stats: [1, 1, 2, 1],
            started_unix_s: 0,
            memory: lumen::render::graph::Memory {
                texture_bytes: 300,
                texture_bytes_unaliased: 400,
                buffer_bytes: 16,
            },
        }
    }

    #[test]
    fn report_and_csv() {
        let samples = [sample(10.0, [2.0, 5.0]), sample(12.0, [3.0, 6.0])];
        let v = to_json(&info(), &samples);
        assert_eq!(v["frames"], 2);
        assert_eq!(v["memory"]["texture_bytes_unaliased"], 400);
        assert_eq!(v["frame_ms"]["mean"], 11.0);
        assert_eq!(v["gpu_ms"]["median"], 8.0);
        assert_eq!(v["passes"][1]["name"], "lighting");
        assert_eq!(v["passes"][1]["gpu_ms"]["max"], 6.0);
        assert_eq!(v["cpu_stages"][0]["name"], "update");
        let csv = to_csv(&samples);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "frame,frame_ms,gpu_ms,update_ms,wait_ms,gbuffer_gpu_ms,gbuffer_cpu_ms,lighting_gpu_ms,lighting_cpu_ms"
        );
        assert_eq!(lines.len(), 3);
        assert!(
            lines[2].starts_with("1,12.000000,9.000000,"),
            "{}",
            lines[2]
        );
        assert!(summary_text(&info(), &samples).contains("lighting (gpu)"));
    }
}

//! Frame-time measurement, shared by `lumen bench` (offscreen, or in the viewer's window
//! with `--window`) and `lumen tradeoff`: per-frame samples of the wall time, the CPU
//! stages (the ECS update first) and every pass's CPU and GPU time, after warm-up frames
//! that are thrown away; [`stats`] summarises them.

pub mod stats;

use anyhow::Result;
use lumen::render::timing::PassTiming;
use lumen::{App, FrameReport};
use std::time::Instant;

/// One measured frame.
#[derive(Clone, Debug)]
pub struct FrameSample {
    /// Wall time of the whole frame (ms): headless, from the start of the ECS update to
    /// the GPU finishing; in a window, from one frame's start to the next's.
    pub frame_ms: f64,
    /// CPU time of each stage (ms), `update` first.
    pub stages: Vec<(&'static str, f64)>,
    /// Every pass's CPU recording time and GPU time.
    pub passes: Vec<PassTiming>,
}

impl FrameSample {
    /// The sample of a frame whose ECS update took `update_ms` and which took `frame_ms`
    /// in all (both ms).
    fn new(report: FrameReport, update_ms: f64, frame_ms: f64) -> FrameSample {
        let mut stages = vec![("update", update_ms)];
        stages.extend(report.stages);
        FrameSample {
            frame_ms,
            stages,
            passes: report.passes,
        }
    }

    /// Sum of the passes' GPU times (ms); `None` without timestamp queries.
    pub fn gpu_ms(&self) -> Option<f64> {
        self.passes.iter().map(|p| p.gpu_ms).sum()
    }
}

/// Renders `warmup + frames` offscreen frames of `app` at `size` and returns the measured
/// ones (the machinery of `lumen bench` and `lumen tradeoff`). `progress` gets the number
/// of frames rendered so far.
pub fn measure(
    app: &mut App,
    size: (u32, u32),
    warmup: u32,
    frames: u32,
    progress: &dyn Fn(u32),
) -> Result<Vec<FrameSample>> {
    let mut samples = Vec::with_capacity(frames as usize);
    for i in 0..warmup + frames {
        let start = Instant::now();
        app.update();
        let update_ms = start.elapsed().as_secs_f64() * 1e3;
        let report = app.render_headless(size)?;
        let frame_ms = start.elapsed().as_secs_f64() * 1e3;
        if i >= warmup {
            samples.push(FrameSample::new(report, update_ms, frame_ms));
        }
        progress(i + 1);
    }
    Ok(samples)
}

/// Frames measured as a window draws them (`lumen bench --window`): a frame's time is
/// the wall time from its start to the next frame's start (update, record, submit, GPU,
/// present), so one frame more than measured is drawn.
pub struct WindowFrames {
    warmup: u32,
    frames: u32,
    samples: Vec<FrameSample>,
    seen: u32,
    last_start: Option<Instant>,
    pending: Option<FrameSample>,
    progress: Box<dyn FnMut(u32)>,
}

impl WindowFrames {
    /// Measures `frames` frames after `warmup` ones; `progress(done)` is called after
    /// every frame.
    pub fn new(warmup: u32, frames: u32, progress: Box<dyn FnMut(u32)>) -> WindowFrames {
        WindowFrames {
            warmup,
            frames,
            samples: Vec::new(),
            seen: 0,
            last_start: None,
            pending: None,
            progress,
        }
    }

    /// Records a frame that started at `start` and whose ECS update took `update_ms`;
    /// the previous frame's time ends here. Returns true once every measured frame is in.
    pub fn frame(&mut self, start: Instant, report: FrameReport, update_ms: f64) -> bool {
        if let (Some(last), Some(mut sample)) = (self.last_start, self.pending.take()) {
            sample.frame_ms = start.duration_since(last).as_secs_f64() * 1e3;
            self.samples.push(sample);
        }
        self.seen += 1;
        (self.progress)(self.seen);
        self.last_start = Some(start);
        if self.seen > self.warmup {
            self.pending = Some(FrameSample::new(report, update_ms, 0.0));
        }
        // One frame more than measured closes the last measured frame's interval.
        self.samples.len() >= self.frames as usize
    }

    /// The measured frames so far.
    pub fn into_samples(self) -> Vec<FrameSample> {
        self.samples
    }
}

//! The frame-time chart of `lumen bench --plot`: every measured frame's wall time as a
//! line over the per-pass GPU times stacked as areas (plotters, bitmap backend, DejaVu
//! Sans from `assets/fonts`).

use crate::measure::FrameSample;
use anyhow::{Context, Result, anyhow};
use plotters::prelude::*;
use std::path::Path;

pub(crate) static FONT: &[u8] = include_bytes!("../../../../assets/fonts/DejaVuSans.ttf");

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Size of every chart, in pixels.
pub(crate) const CHART_SIZE: (u32, u32) = (1200, 600);

/// The drawing area of a chart held in memory.
pub(crate) type Canvas<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws a [`CHART_SIZE`] chart with `draw` into memory, then writes it to `path` as a PNG
/// atomically (a failed write is an error and leaves no partial file).
pub(crate) fn draw_png(path: &Path, draw: impl FnOnce(&Canvas) -> Result<()>) -> Result<()> {
    let (w, h) = CHART_SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, CHART_SIZE).into_drawing_area();
        draw(&root)?;
        root.present()
            .map_err(|e| anyhow!("drawing {}: {e}", path.display()))?;
    }
    let image = image::RgbImage::from_raw(w, h, rgb).context("chart buffer size")?;
    lumen::assets::image_io::save(path, &image, image::ImageFormat::Png)
        .with_context(|| format!("writing {}", path.display()))
}

/// Draws the chart of `samples` into the PNG `path` (1200×600 px) titled `title`.
pub fn plot(path: &Path, title: &str, samples: &[FrameSample]) -> Result<()> {
    if samples.is_empty() {
        return Err(anyhow!("no frames to plot"));
    }
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the bundled chart font does not load"))?;
    let mut passes: Vec<&str> = Vec::new();
    for s in samples {
        for p in &s.passes {
            if !passes.contains(&p.name) {
                passes.push(p.name);
            }
        }
    }
    // Cumulative GPU time up to and including pass k, per frame.
    let stacked: Vec<Vec<f64>> = (0..passes.len())
        .map(|k| {
            samples
                .iter()
                .map(|s| {
                    passes[..=k]
                        .iter()
                        .filter_map(|n| s.passes.iter().find(|p| p.name == *n)?.gpu_ms)
                        .sum()
                })
                .collect()
        })
        .collect();
    let y_max = samples
        .iter()
        .map(|s| s.frame_ms)
        .chain(stacked.last().into_iter().flatten().copied())
        .fold(0.0f64, f64::max)
        * 1.1;
    let n = samples.len();
    draw_png(path, |root| {
        let draw = |e: &dyn std::fmt::Display| anyhow!("drawing {}: {e}", path.display());
        root.fill(&WHITE).map_err(|e| draw(&e))?;
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0usize..n.max(2) - 1, 0.0..y_max.max(1e-3))
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc("frame")
            .y_desc("ms")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| draw(&e))?;
        // Largest cumulative first, so each pass shows as the band above the previous one.
        for (k, name) in passes.iter().enumerate().rev() {
            let color = PALETTE[k % PALETTE.len()];
            chart
                .draw_series(AreaSeries::new(
                    stacked[k].iter().copied().enumerate(),
                    0.0,
                    color.mix(0.8).filled(),
                ))
                .map_err(|e| draw(&e))?
                .label(format!("{name} (GPU)"))
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled())
                });
        }
        chart
            .draw_series(LineSeries::new(
                samples.iter().map(|s| s.frame_ms).enumerate(),
                BLACK.stroke_width(2),
            ))
            .map_err(|e| draw(&e))?
            .label("frame (wall)")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 12, y)], BLACK.stroke_width(2)));
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| draw(&e))?;
        Ok(())
    })
}

//! Frame times measured from code with `lumen bench`'s machinery: 30 frames of `spheres`
//! after 5 warm-up frames, summarised per pass.
//! `cargo run --release --example frame_timing [WxH]`.

use lumen::prelude::*;
use lumen_game::measure::{measure, stats::Summary};

fn main() -> anyhow::Result<()> {
    let size = lumen_game::examples::start((1280, 720)).size;
    let mut app = App::headless()?;
    let scene = lumen_game::scenes::find("spheres").map_err(anyhow::Error::msg)?;
    (scene.build)(&mut app)?;
    let samples = measure(&mut app, size, 5, 30, &|_| {})?;
    let frame: Vec<f64> = samples.iter().map(|s| s.frame_ms).collect();
    let summary = Summary::of(&frame).ok_or_else(|| anyhow::anyhow!("no frames"))?;
    println!(
        "frame: median {:.2} ms, p95 {:.2} ms over {} frames",
        summary.median, summary.p95, summary.n
    );
    let names: Vec<&str> = samples[0].passes.iter().map(|p| p.name).collect();
    for name in names {
        let gpu: Option<Vec<f64>> = samples
            .iter()
            .map(|s| {
                s.passes
                    .iter()
                    .find(|p| p.name == name)
                    .and_then(|p| p.gpu_ms)
            })
            .collect();
        match gpu.and_then(|g| Summary::of(&g)) {
            Some(s) => println!("  {name:<12} GPU median {:.3} ms", s.median),
            None => println!("  {name:<12} GPU time not available on this adapter"),
        }
    }
    Ok(())
}

//! Progress bars for long one-off work, on a terminal only.

use lumen::App;
use lumen::render::indirect::environment_maps::Ibl;
use std::io::IsTerminal;

/// Shows environment prefiltering progress on stderr when it is a terminal.
pub fn show_ibl_progress(app: &mut App) {
    if !std::io::stderr().is_terminal() {
        return;
    }
    let mut bar: Option<indicatif::ProgressBar> = None;
    if let Some(mut ibl) = app.world_mut().get_resource_mut::<Ibl>() {
        ibl.set_progress(Box::new(move |step, done, total| {
            let b = bar.get_or_insert_with(|| {
                let b = indicatif::ProgressBar::new(u64::from(total));
                b.set_style(
                    indicatif::ProgressStyle::with_template(
                        "preparing environment {bar:30} {pos}/{len} {msg} ({elapsed})",
                    )
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                );
                b
            });
            b.set_position(u64::from(done));
            b.set_message(step.to_string());
            if done >= total {
                b.finish_and_clear();
            }
        }));
    }
}

/// A bar of `total` steps on stderr labelled `what` (`{pos}/{len} <unit>`, then the bar's
/// message), hidden when stderr is not a terminal.
pub fn bar(total: u64, what: &str, unit: &str) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::new(total);
    let template =
        format!("{what} {{bar:30}} {{pos}}/{{len}} {unit} ({{elapsed}}, ETA {{eta}}) {{msg}}");
    b.set_style(
        indicatif::ProgressStyle::with_template(&template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    b
}

/// Frames of at least this many pixels (2048 × 2048) show a spinner with their stage: on a
/// software rasterizer each one takes seconds.
pub const LONG_FRAME_PIXELS: u64 = 2048 * 2048;

/// A spinner on stderr for one-off work done in stages (`{what}: {stage} ({elapsed})`),
/// ticking by itself while a stage blocks; hidden unless `show` and stderr is a terminal.
pub fn stages(show: bool, what: &str) -> indicatif::ProgressBar {
    if !show || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let b = indicatif::ProgressBar::new_spinner();
    let template = format!("{{spinner}} {what}: {{msg}} ({{elapsed}})");
    b.set_style(
        indicatif::ProgressStyle::with_template(&template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    b.enable_steady_tick(std::time::Duration::from_millis(200));
    b
}

//! `lumen view` ([`run`]), the window `lumen bench --window` measures in, and [`show`]
//! for scripts that want their scene in a window (also at `lumen_game::view`). The
//! window loop is in `window.rs`, its GPU and surface in `surface.rs`, opening files in
//! `open.rs` and screenshots in `screenshot.rs`.
//!
//! The viewer has orbit and fly cameras ([`controls`]), an egui panel ([`panel`]) with
//! the frame time, per-pass timings, debug views, quality knobs, exposure, depth of field
//! and lights, screenshots (PNG and EXR), glTF and HDR files opened by drag and drop or
//! `--open`, and WGSL reloaded from `shaders/` when a file changes ([`watch`]).
//!
//! Resizing (down to a minimised 0×0 window) and lost or outdated surfaces are handled.
//! A frame that fails (a shader that does not compile, a file that does not load) is
//! shown as an error in the panel and the viewer goes on. When the GPU device is lost,
//! the viewer makes a new device, surface and renderer and goes on with the same scene
//! (if no device can be made, it ends with a message). Nothing panics.

mod animation_panel;
pub mod controls;
pub mod gui;
mod knob_panel;
mod open;
pub mod panel;
mod screenshot;
mod surface;
pub mod watch;
mod window;

pub use open::open_file;
pub use screenshot::save_screenshot;
pub use window::{ScreenText, WindowOptions, default_shader_dir, display_available, show};
pub(crate) use window::{WindowScene, run_window};

use crate::cli::ViewArgs;
use crate::setup::check_scene_args;
use anyhow::{Result, anyhow};

/// Opens the viewer on the scene `args` describe and runs until the window closes.
pub fn run(args: ViewArgs) -> Result<()> {
    check_scene_args(&args.scene)?;
    let options = WindowOptions {
        title: "lumen".into(),
        size: args.size,
        panel: !args.no_panel,
        shader_dir: args.shaders.clone().or_else(default_shader_dir),
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        lose_device_after: args.lose_device_after,
        viewer_keys: true,
    };
    if let Some(dir) = &options.shader_dir
        && !dir.is_dir()
    {
        return Err(anyhow!("shader folder {} does not exist", dir.display()));
    }
    run_window(WindowScene::Args(Box::new(args)), options, None).map(|_| ())
}

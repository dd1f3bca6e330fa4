//! Small helpers the examples in `game/examples/` share: their command line, the app they
//! build in, and where images go.

use crate::commands::view::{WindowOptions, show};
use lumen::App;
use std::path::PathBuf;

/// An example's command line: `[WxH] [--window] [--frames N]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExampleArgs {
    /// Image (or window) size in pixels.
    pub size: (u32, u32),
    /// Show the scene in a window (with the viewer's panel) instead of writing an image.
    pub window: bool,
    /// Close the window after this many frames.
    pub frames: Option<u64>,
}

/// Call first in `main`, before any thread exists: turns Mesa's `device_select` layer off
/// as the `lumen` binary does (it only reorders adapters, and prints an `XDG_RUNTIME_DIR`
/// error without a Wayland session), and reads the command line; the size is `default`
/// unless given. Unknown arguments are an error message and exit code 2.
pub fn start(default: (u32, u32)) -> ExampleArgs {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY: documented to run first in main, before any other thread exists.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
    match parse(std::env::args().skip(1), default) {
        Ok(args) => args,
        Err(e) => {
            eprintln!("{e}\nusage: [WxH] [--window] [--frames N]");
            std::process::exit(2);
        }
    }
}

fn parse(args: impl Iterator<Item = String>, default: (u32, u32)) -> Result<ExampleArgs, String> {
    let mut out = ExampleArgs {
        size: default,
        window: false,
        frames: None,
    };
    let mut args = args.peekable();
    while let Some(a) = args.next() {
        match a.as_str() {
            "--window" => out.window = true,
            "--frames" => {
                let n = args.next().ok_or("--frames needs a number")?;
                out.frames = Some(
                    n.parse()
                        .map_err(|_| format!("--frames: '{n}' is not a count"))?,
                );
            }
            _ => out.size = crate::cli::values::size(&a)?,
        }
    }
    Ok(out)
}

impl ExampleArgs {
    /// An empty app to build the scene in: without a GPU when a window will show it (the
    /// window picks an adapter that can present), with a headless one otherwise.
    pub fn app(&self) -> lumen::Result<App> {
        if self.window {
            Ok(App::new())
        } else {
            App::headless()
        }
    }

    /// Windowed: shows `app` until the window closes, running its systems every frame.
    /// Headless: runs `frames` updates and renders, and saves the last image as
    /// `out/examples/<name>`.
    pub fn finish(&self, mut app: App, name: &str, frames: u32) -> anyhow::Result<()> {
        if self.window {
            return show(
                app,
                WindowOptions {
                    title: name.to_string(),
                    size: self.size,
                    frames: self.frames,
                    ..WindowOptions::default()
                },
            );
        }
        for _ in 0..frames.max(1) {
            app.update();
            app.render_headless(self.size)?;
        }
        Ok(save(&app.read_display_image()?, name)?)
    }
}

/// Saves `image` as `out/examples/<name>` (creating the folders) and prints the path.
pub fn save(image: &image::RgbaImage, name: &str) -> lumen::Result<()> {
    let path = PathBuf::from("out/examples").join(name);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| lumen::Error::io(dir, e))?;
    }
    lumen::assets::image_io::save_png(&path, image)?;
    println!("wrote {}", path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(list: &[&str]) -> Result<ExampleArgs, String> {
        parse(list.iter().map(|s| s.to_string()), (640, 360))
    }

    #[test]
    fn parses_size_window_and_frames_in_any_order() {
        assert_eq!(
            args(&[]),
            Ok(ExampleArgs {
                size: (640, 360),
                window: false,
                frames: None
            })
        );
        assert_eq!(
            args(&["--window", "48x27", "--frames", "3"]),
            Ok(ExampleArgs {
                size: (48, 27),
                window: true,
                frames: Some(3)
            })
        );
        assert!(args(&["--frames"]).is_err());
        assert!(args(&["--frames", "x"]).is_err());
        assert!(args(&["big"]).is_err());
    }
}

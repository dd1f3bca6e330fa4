//! `lumen`: render, view and list scenes. See `lumen --help`.

use lumen_game::cli::{Cli, Command, RenderArgs, SceneArgs, ViewArgs};
use lumen_game::{commands, scenes};
use std::process::ExitCode;

fn main() -> ExitCode {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // SAFETY: first statement of main, before any other thread exists. Mesa's
        // device_select layer only reorders adapters (Lumen orders them itself) and prints
        // an XDG_RUNTIME_DIR error on machines without a Wayland session.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or(
        // wgpu logs its own copy of shader-translation and validation errors that Lumen
        // returns as errors; keep the one line Lumen prints.
        "warn,wgpu::backend=off,wgpu_core=error,wgpu_hal=error,naga=error",
    ))
    .format_timestamp(None)
    .init();
    let knobs = lumen::quality::Knobs::default();
    let (args, notes) = lumen_game::cli::legacy::rewrite(std::env::args_os());
    for note in notes {
        eprintln!("lumen: {note}");
    }
    let cli = match lumen_game::cli::parse_from(&knobs, args) {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // One line: clap's first line names the problem.
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("invalid arguments");
            eprintln!(
                "lumen: {} (see lumen --help)",
                first.trim_start_matches("error: ")
            );
            return ExitCode::from(2);
        }
    };
    match run(cli, &knobs) {
        Ok(()) => ExitCode::SUCCESS,
        // Texels that fail a rule get a status of their own, for asset pipelines.
        Err(e) if e.is::<commands::validate::ValidationFailed>() => {
            eprintln!("lumen: {e}");
            ExitCode::from(3)
        }
        Err(e) => {
            eprintln!("lumen: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli, knobs: &lumen::quality::Knobs) -> anyhow::Result<()> {
    match cli.command {
        Some(Command::Render(mut args)) => {
            args.scene.resolve_builtin();
            commands::render::run(&args).map(|_| ())
        }
        Some(Command::View(mut args)) => {
            args.scene.resolve_builtin();
            commands::view::run(args)
        }
        Some(Command::Bench(mut args)) => {
            args.scene.resolve_builtin();
            commands::bench::run(&args)
        }
        Some(Command::Reference(mut args)) => {
            args.scene.resolve_builtin();
            commands::reference::run(&args).map(|_| ())
        }
        Some(Command::Convert(args)) => commands::convert::run(&args),
        Some(Command::Validate(args)) => commands::validate::run(&args),
        Some(Command::Merge(args)) => commands::merge::run(&args),
        Some(Command::Tradeoff(mut args)) => {
            args.scene.resolve_builtin();
            commands::tradeoff::run(&args)
        }
        Some(Command::Quality(args)) => commands::quality::run(&args, knobs),
        Some(Command::Scenes) => {
            let text: String = scenes::SCENES
                .iter()
                .map(|s| format!("{:<10} {}\n", s.name, s.description))
                .collect();
            lumen_game::output::print(&text);
            Ok(())
        }
        None => {
            let scene = SceneArgs {
                scene: Some("showcase".into()),
                ..SceneArgs::default()
            };
            if !cli.headless && commands::view::display_available() {
                match commands::view::run(ViewArgs::new(scene.clone(), (1280, 720))) {
                    Ok(()) => return Ok(()),
                    Err(e) => eprintln!("lumen: no window ({e:#}); rendering headless instead"),
                }
            }
            commands::render::run(&RenderArgs {
                scene,
                size: (1280, 720),
                out: None,
                json: false,
                explain: false,
                frames: None,
                fps: 30.0,
                shard: None,
                shards: None,
            })
            .map(|_| ())
        }
    }
}

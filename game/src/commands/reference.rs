//! `lumen reference`: the CPU path-traced ground truth of a scene, with a progress bar.

use crate::cli::ReferenceArgs;
use crate::setup::{build_scene, check_scene_args};
use anyhow::{Context, Result};
use lumen::App;
use lumen::assets::image_io::{OutputFormat, save_exr, save_exr_rgba, save_png};
use lumen::reference::path::{
    Estimate, ReferenceOptions, Shard, render, render_ambient_occlusion, render_part,
};
use lumen::trace_input::trace_scene;
use std::path::PathBuf;

/// The tone mapper of the camera the last rendered frame used.
pub fn frame_tonemapper(app: &App) -> lumen::shading::color::Tonemapper {
    app.world()
        .get_resource::<lumen::render::extract::ExtractedFrame>()
        .and_then(|f| f.camera.as_ref())
        .map(|c| c.tonemapper)
        .unwrap_or_default()
}

/// Warns when the path tracer dropped NaN or infinite paths (one line, with the count).
pub fn warn_dropped(dropped: u64, options: &ReferenceOptions) {
    if dropped > 0 {
        let total = u64::from(options.size.0)
            * u64::from(options.size.1)
            * u64::from(options.samples_per_pixel.max(1));
        log::warn!(
            "path tracer: dropped {dropped} of {total} paths whose radiance was NaN or infinite"
        );
    }
}

/// What the image depends on besides the scene's file, as words: the sidecar's
/// `settings`, which parts must share to merge.
fn settings(args: &ReferenceArgs) -> String {
    format!(
        "{:?}; {}x{}; {} spp; {} bounce(s); seed {}; {:?} light visibility; light connections {}; occlusion {}; estimator {}",
        args.scene,
        args.size.0,
        args.size.1,
        args.spp,
        args.max_bounces,
        args.seed,
        args.light_visibility,
        !args.no_light_connections,
        args.occlusion,
        lumen::reference::path::ESTIMATOR
    )
}

/// Builds the scene, path-traces it and writes the image (or, sharded, this shard's part
/// and its sidecar). Returns the path written.
/// Writes the traced image: linear EXR, or PNG through the frame's tone mapper (an
/// occlusion image as it is).
fn write_image(
    out: &std::path::Path,
    format: OutputFormat,
    image: &image::Rgba32FImage,
    app: &App,
    occlusion: bool,
) -> Result<()> {
    match format {
        OutputFormat::Exr => save_exr(out, image)?,
        OutputFormat::Png => {
            let tonemapper = frame_tonemapper(app);
            let display = image::RgbaImage::from_fn(image.width(), image.height(), |x, y| {
                let [r, g, b, _] = image.get_pixel(x, y).0;
                let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
                if occlusion {
                    return image::Rgba([byte(r), byte(g), byte(b), 255]);
                }
                let c = tonemapper.apply(glam::Vec3::new(r, g, b));
                let e = |v: f32| byte(lumen::shading::color::srgb_encode(v.clamp(0.0, 1.0)));
                image::Rgba([e(c.x), e(c.y), e(c.z), 255])
            });
            save_png(out, &display)?;
        }
    }
    Ok(())
}

/// Where this run path-traces (`--device`): `None` on the GPU, else on the CPU for the
/// reason given; an error where `gpu` was asked for what only the CPU does.
fn gpu_choice(
    args: &ReferenceArgs,
    app: &App,
    scene: &lumen::reference::path::TraceScene,
    sharded: bool,
) -> Result<Option<String>> {
    use lumen::reference_gpu::{TraceDevice, choose_gpu};
    let gpu = app
        .world()
        .get_resource::<lumen::render::device::Gpu>()
        .context("no GPU")?;
    let reason = if args.occlusion {
        Err("--occlusion is traced on the CPU".to_string())
    } else if sharded {
        Err("shards are traced on the CPU".to_string())
    } else {
        choose_gpu(args.device, &gpu.adapter.get_info(), scene)
    };
    match (args.device, reason) {
        (_, Ok(())) => Ok(None),
        (TraceDevice::Gpu, Err(why)) => Err(anyhow::anyhow!("--device gpu: {why}")),
        (_, Err(why)) => Ok(Some(why)),
    }
}

pub fn run(args: &ReferenceArgs) -> Result<PathBuf> {
    check_scene_args(&args.scene)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/{}-reference.exr", args.scene.label())));
    let format = OutputFormat::from_path(&out)?;
    let shard = crate::shard::resolve(args.shard, args.shards, &crate::shard::process_env)?;
    // A shard: its part, and what its sidecar records (the scene file is read and
    // hashed only here).
    let shard = match shard {
        Some(spec) => {
            if format != OutputFormat::Exr {
                anyhow::bail!(
                    "a shard writes a linear EXR part: give --out with .exr (not {})",
                    out.display()
                );
            }
            let settings = settings(args);
            let scene_hash = crate::shard::scene_hash(&settings, args.scene.file.as_deref())?;
            let part = crate::shard::part_path(&out, spec.index, spec.count);
            if let crate::shard::PartState::Done(s) =
                crate::shard::part_state(&part, &settings, &scene_hash, spec.count)
            {
                crate::output::print(&format!(
                    "shard {}/{} ({}): {} is already done ({} samples per pixel, {:.1} s): skipped\n",
                    spec.index,
                    spec.count,
                    spec.source,
                    part.display(),
                    s.share[1] - s.share[0],
                    s.seconds
                ));
                return Ok(part);
            }
            Some((spec, part, settings, scene_hash))
        }
        None => None,
    };
    let mut app = App::headless()?;
    crate::progress::show_ibl_progress(&mut app);
    build_scene(&mut app, &args.scene)?;
    let mut scene = trace_scene(&mut app, args.size)?;
    scene.light_visibility = args.light_visibility;
    scene.light_connections = !args.no_light_connections;
    let options = ReferenceOptions {
        size: args.size,
        samples_per_pixel: args.spp,
        max_bounces: args.max_bounces,
        seed: args.seed,
    };
    let radius_m = app
        .world()
        .resource::<lumen::prelude::Quality>()
        .ao
        .radius_m;
    let cpu_reason = gpu_choice(args, &app, &scene, shard.is_some())?;
    if cpu_reason.is_none() {
        let gpu = app
            .world()
            .get_resource::<lumen::render::device::Gpu>()
            .context("no GPU")?
            .clone();
        let bar = crate::progress::bar(u64::from(args.spp), "path tracing (GPU)", "samples");
        let start = std::time::Instant::now();
        let traced = lumen::reference_gpu::render_gpu(&gpu, &scene, &options, &|s| {
            bar.set_position(u64::from(s))
        })?;
        bar.finish_and_clear();
        warn_dropped(traced.dropped_samples, &options);
        let seconds = start.elapsed().as_secs_f64();
        write_image(&out, format, &traced.image, &app, false)?;
        crate::output::print(&format!(
            "path-traced {} at {}x{}, {} spp, {} bounce(s), unidirectional, seed {}: {:.1} s (GPU: {})\nwrote {}\n",
            args.scene.label(),
            args.size.0,
            args.size.1,
            args.spp,
            args.max_bounces,
            args.seed,
            seconds,
            gpu.adapter.get_info().name,
            out.display()
        ));
        return Ok(out);
    }
    let bar = crate::progress::bar(u64::from(args.size.1), "path tracing", "rows");
    let start = std::time::Instant::now();
    let progress = |rows| bar.set_position(u64::from(rows));
    if let Some((spec, part, settings, scene_hash)) = shard {
        let estimate = if args.occlusion {
            Estimate::Occlusion(radius_m)
        } else {
            Estimate::Radiance
        };
        let s = Shard {
            index: spec.index,
            count: spec.count,
        };
        let traced = render_part(&scene, &options, s, estimate, &progress);
        bar.finish_and_clear();
        warn_dropped(traced.dropped_samples, &options);
        save_exr_rgba(&part, &traced.image)?;
        let samples = s.range(args.spp);
        let sidecar = crate::shard::write_sidecar(
            &part,
            "reference",
            args.scene.label(),
            settings,
            scene_hash,
            spec,
            samples.clone(),
            args.seed,
            start.elapsed().as_secs_f64(),
        )?;
        crate::output::print(&format!(
            "path-traced shard {}/{} (index from {}) of {} at {}x{}: samples {}..{} of {}, seed {}: {:.1} s\nwrote {} and its sidecar\n",
            spec.index,
            spec.count,
            spec.source,
            args.scene.label(),
            args.size.0,
            args.size.1,
            samples.start,
            samples.end,
            args.spp,
            args.seed,
            sidecar.seconds,
            part.display()
        ));
        return Ok(part);
    }
    let traced = if args.occlusion {
        render_ambient_occlusion(&scene, &options, radius_m, &progress)
    } else {
        render(&scene, &options, &progress)
    };
    bar.finish_and_clear();
    warn_dropped(traced.dropped_samples, &options);
    let image = traced.image;
    let seconds = start.elapsed().as_secs_f64();
    write_image(&out, format, &image, &app, args.occlusion)?;
    let what = if args.occlusion {
        format!("ambient occlusion within {radius_m} m")
    } else if args.no_light_connections {
        format!("{} bounce(s), unidirectional", args.max_bounces)
    } else {
        format!("{} bounce(s)", args.max_bounces)
    };
    crate::output::print(&format!(
        "path-traced {} at {}x{}, {} spp, {}, seed {}: {:.1} s (CPU, {} threads: {})\nwrote {}\n",
        args.scene.label(),
        args.size.0,
        args.size.1,
        args.spp,
        what,
        args.seed,
        seconds,
        rayon::current_num_threads(),
        cpu_reason.unwrap_or_default(),
        out.display()
    ));
    Ok(out)
}

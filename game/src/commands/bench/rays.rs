//! `lumen bench --rays N`: the ray-tracing core on the scene: build times and memory of
//! its acceleration structure, what an unchanged frame pays, and rays per second of the
//! GPU's software traversal and of the CPU's.

use crate::cli::BenchArgs;
use crate::setup::build_scene;
use anyhow::{Context, Result};
use lumen::App;
use lumen::render::device::Gpu;
use lumen::render::extract::ExtractedFrame;
use lumen::render::rays::ray_batch::measure_throughput;
use lumen::render::rays::scene_rays::SceneRays;
use lumen::scene::Meshes;
use std::time::Instant;

/// Runs the measurement and prints it.
pub fn run(args: &BenchArgs, n: u32) -> Result<()> {
    let mut app = App::headless()?;
    crate::progress::show_ibl_progress(&mut app);
    build_scene(&mut app, &args.scene)?;
    app.render_headless(args.size)?;
    let adapter = app.adapter().cloned().context("no adapter")?;
    let world = app.world_mut();
    let gpu = world.resource::<Gpu>().clone();
    let (frame, meshes) = (
        world.resource::<ExtractedFrame>(),
        world.resource::<Meshes>(),
    );
    let mut rays = SceneRays::default();
    let start = Instant::now();
    rays.update(&gpu, frame, meshes)?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    rays.update(&gpu, frame, meshes)?;
    let unchanged_ms = start.elapsed().as_secs_f64() * 1e3;
    let scene = rays.scene();
    let triangles = scene.triangles.len();
    let bar = crate::progress::stages(true, "bench --rays");
    bar.set_message(format!("tracing {n} rays on the GPU and the CPU"));
    let speed = measure_throughput(&gpu, &rays, n as usize)?;
    bar.finish_and_clear();
    let c = rays.counts;
    let text = format!(
        "{scene_label}: ray-tracing core ({adapter}, {backend})\n\
         \x20 structure: {blas} BLAS built, {inst} instances in the TLAS ({skipped} skipped), {triangles} triangles ({dropped} dropped)\n\
         \x20 build: {build_ms:.1} ms (BLAS and TLAS, CPU, upload included); an unchanged frame: {unchanged_ms:.3} ms, {kept} kept\n\
         \x20 memory: {mib:.2} MiB, {per_tri:.1} bytes per triangle ({blas_nodes} BLAS nodes, {tlas_nodes} TLAS nodes)\n\
         \x20 rays: {rays} ({hit:.0} % hit)\n\
         \x20 GPU software traversal: {gpu:.3} Mrays/s\n\
         \x20 CPU traversal ({cores} threads): {cpu:.3} Mrays/s\n",
        scene_label = args.scene.label(),
        adapter = adapter.name,
        backend = adapter.backend,
        blas = c.blas_builds,
        inst = scene.instances.len(),
        skipped = c.skipped_instances,
        dropped = c.dropped_triangles,
        kept = c.kept,
        mib = scene.bytes() as f64 / (1024.0 * 1024.0),
        per_tri = scene.bytes() as f64 / triangles.max(1) as f64,
        blas_nodes = scene.blas_nodes.len(),
        tlas_nodes = scene.tlas_nodes.len(),
        rays = speed.rays,
        hit = 100.0 * speed.hits as f64 / speed.rays.max(1) as f64,
        gpu = speed.gpu_rays_per_s / 1e6,
        cores = rayon::current_num_threads(),
        cpu = speed.cpu_rays_per_s / 1e6,
    );
    crate::output::print(&text);
    Ok(())
}

//! [`App`]: a World with the scene, your systems, and (once a GPU is attached) the
//! renderer. The one type a script needs.

use crate::error::{Error, Result};
use crate::input::{self, InputEvent, Keys, Mouse, MouseButtons, PendingInput};
use crate::quality::Quality;
use crate::render::device::{AdapterSummary, Gpu, GpuRequest};
use crate::render::extract::ExtractedFrame;
use crate::render::frame::{FrameDelta, FrameEncoder, FrameErrors, FrameOutput, MeteredExposure};
use crate::render::graph::registry::Registry;
use crate::render::graph::slots::KeptSlots;
use crate::render::graph::{FramePass, FramePlan, Slot, slots};
use crate::render::indirect::capture::ProbeStatus;
use crate::render::post::antialias::renders::Renders;
use crate::render::readback::{f16_bytes_to_f32, read_texture};
use crate::render::shaders::{self, ShaderOverrides};
use crate::render::targets::{RenderTargets, Target};
use crate::render::timing::PassTiming;
use crate::render::{self, ExtractSchedule, RenderSchedule};
use crate::scene::{MeshData, MeshHandle, Meshes, propagate_transforms};
use crate::time::{Clock, HEADLESS_DELTA_S, Time};
use bevy_ecs::prelude::*;
use bevy_ecs::schedule::{IntoScheduleConfigs, ScheduleLabel};
use bevy_ecs::system::ScheduleSystem;
use std::path::Path;
use std::time::Instant;

/// Your systems: animation, input, spawning. Runs in [`App::update`], after the
/// [`Time`] and input resources are brought up to date.
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Update;

/// Engine bookkeeping after [`Update`], once per rendered frame: animation players, then
/// transform propagation.
#[derive(ScheduleLabel, Clone, Debug, PartialEq, Eq, Hash)]
pub struct PostUpdate;

/// Scene statistics of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneStats {
    /// Mesh instances in the scene (in view or not).
    pub instances: usize,
    /// The G-buffer pass's instanced draw calls (instances outside the view are culled).
    pub draws: usize,
    /// Triangles the G-buffer pass draws (those of the instances in view).
    pub triangles: u64,
    /// Lights of all kinds.
    pub lights: u32,
}

/// What one rendered frame cost and what it did.
#[derive(Clone, Debug)]
pub struct FrameReport {
    /// Per-pass CPU recording time and GPU time.
    pub passes: Vec<PassTiming>,
    /// CPU time of each stage of the frame, in ms: `propagate`, `probes` (probe captures,
    /// waited for), `extract`, `record`
    /// (plan, prepare and record every pass), `submit`, `wait` (for the GPU).
    pub stages: Vec<(&'static str, f64)>,
    /// Wall time of the whole frame in ms, from propagation to the GPU finishing.
    pub frame_ms: f64,
    /// Which passes ran and why.
    pub plan: FramePlan,
    /// Exposure multiplier used (luminance × exposure = tone-mapper input).
    pub exposure: f32,
    /// EV100 equivalent of the exposure.
    pub ev100: f32,
    /// Scene statistics.
    pub stats: SceneStats,
    /// One-off preprocessing this frame ran (environment prefiltering, BRDF table), in ms
    /// per step; empty once everything is cached.
    pub preprocessing: Vec<(String, f64)>,
    /// Camera settings that were out of range and clamped, one line each.
    pub notes: Vec<String>,
    /// What automatic exposure metered (after this frame; empty for other modes).
    pub metered: MeteredExposure,
    /// The irradiance volume and the reflection probes: what is placed, the captures run
    /// before this frame, and their time.
    pub probes: ProbeStatus,
    /// Jittered renders averaged into this image (`--accumulate`; 1 for one render).
    /// The pass and stage times are their sums.
    pub accumulated: u32,
    /// Frames temporal anti-aliasing rendered into this image: [`TAA_JITTER_PERIOD`](crate::render::post::antialias::taa::TAA_JITTER_PERIOD) for a
    /// still render (converged), 1 per frame in the viewer and `bench`, 0 without TAA.
    /// The pass and stage times are their sums.
    pub temporal_frames: u32,
}

/// A render target of the frame that can be read back with [`App::read_target`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameTarget {
    /// Base colour (rgb, decoded to linear with the exact sRGB curve, as the lighting
    /// pass does) and ambient occlusion (a).
    GBuffer0,
    /// Octahedral normal (rg), perceptual roughness (b), metallic (a).
    GBuffer1,
    /// Pre-exposed emissive (rgb), specular level (a).
    GBuffer2,
    /// Reversed-Z depth (r): 1 at the near plane, 0 at the far plane and background.
    Depth,
    /// Exposed HDR luminance (rgb) and coverage (a).
    Hdr,
    /// The shadow map atlas's depth (r; reversed Z, 0 where nothing was drawn), square,
    /// 1×1 when no light casts shadows.
    ShadowAtlas,
    /// Motion vectors (rg): each surface's screen motion in pixels since the previous
    /// frame, without jitter, 0 on the background (only frames with `--aa taa` have them).
    Motion,
}

impl FrameTarget {
    /// The frame graph's slot of the target; `None` for the shadow atlas, which its pass
    /// keeps between frames.
    fn slot(self) -> Option<Slot> {
        match self {
            FrameTarget::GBuffer0 => Some(slots::GBUFFER_BASE_COLOR),
            FrameTarget::GBuffer1 => Some(slots::GBUFFER_NORMAL),
            FrameTarget::GBuffer2 => Some(slots::GBUFFER_EMISSIVE),
            FrameTarget::Depth => Some(slots::DEPTH),
            FrameTarget::Hdr => Some(slots::HDR),
            FrameTarget::Motion => Some(slots::MOTION),
            FrameTarget::ShadowAtlas => None,
        }
    }
}

/// Format of the headless display image: 8-bit RGBA; the tone mapping pass applies the
/// exact sRGB curve itself.
pub const HEADLESS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The scene World, its schedules and, after [`App::attach_gpu`], the renderer.
pub struct App {
    world: World,
    offscreen: Option<Target>,
    /// Where the steps of [`Time`] come from.
    clock: Clock,
    /// [`App::update`] advanced [`Time`] since the last frame rendered: the frame uses
    /// that step instead of taking one of its own.
    ticked: bool,
    /// The shader sources before the last reload, until a frame renders with the new ones.
    shader_fallback: Option<ShaderOverrides>,
    /// The last frame size that passed [`check_size`]: a size is checked once, not every
    /// frame.
    checked_size: Option<(u32, u32)>,
    /// Capture at most `GiSettings::probes_per_frame` probes before each frame (the viewer,
    /// `bench`) instead of converging the irradiance volume before it (still renders).
    progressive_probes: bool,
    /// With TAA, render one frame per call (the viewer, `bench`) instead of converging a
    /// still image from a fresh history in each call.
    progressive_taa: bool,
    /// [`App::camera_cut`] was called: the next frame resets the TAA history.
    pending_cut: bool,
}

impl Default for App {
    fn default() -> Self {
        App::new()
    }
}

impl App {
    /// An empty scene with no GPU: spawn entities, add systems, then attach a GPU.
    pub fn new() -> App {
        let mut world = World::new();
        world.init_resource::<Meshes>();
        world.init_resource::<crate::scene::Textures>();
        world.init_resource::<Quality>();
        world.init_resource::<crate::quality::Knobs>();
        world.init_resource::<Time>();
        world.init_resource::<Keys>();
        world.init_resource::<MouseButtons>();
        world.init_resource::<Mouse>();
        world.init_resource::<PendingInput>();
        world.add_schedule(Schedule::new(Update));
        let mut post = Schedule::new(PostUpdate);
        post.add_systems((crate::scene::animation::animate, propagate_transforms).chain());
        world.add_schedule(post);
        App {
            world,
            offscreen: None,
            clock: Clock::new(None),
            ticked: false,
            shader_fallback: None,
            checked_size: None,
            progressive_probes: false,
            progressive_taa: false,
            pending_cut: false,
        }
    }

    /// An empty scene with a headless GPU (see [`Gpu::new_headless`] for the choice).
    pub fn headless() -> Result<App> {
        App::headless_with(&GpuRequest::from_env()?)
    }

    /// An empty scene with a headless GPU chosen by `request`. Its [`Time`] advances by
    /// a fixed [`HEADLESS_DELTA_S`] per frame (see [`App::set_fixed_delta`]).
    pub fn headless_with(request: &GpuRequest) -> Result<App> {
        let mut app = App::new();
        app.set_fixed_delta(Some(HEADLESS_DELTA_S));
        app.attach_gpu(Gpu::new(request, None, None)?.0)?;
        Ok(app)
    }

    /// Attaches a GPU and installs the renderer. On an app that has one already (say,
    /// a lost device: [`App::gpu_lost`]), it replaces it: every GPU resource is created
    /// again on the new device, and reloaded shaders carry over.
    pub fn attach_gpu(&mut self, gpu: Gpu) -> Result<()> {
        if let Some(old) = self.world.get_resource::<Gpu>() {
            gpu.shaders.set_overrides(old.shaders.overrides());
        }
        self.offscreen = None;
        self.shader_fallback = None;
        render::install(&mut self.world, gpu)
    }

    /// Adds pass `P` to the frame, after the passes registered so far: its name, decision,
    /// reads, writes and systems go into the frame graph, which orders it, runs it when
    /// it decides to and allocates the targets it declares (see [`crate::render::graph`]).
    /// A pass whose reads no earlier pass writes, or whose name is taken, is an error and
    /// the frame stays as it was.
    pub fn add_pass<P: FramePass>(&mut self) -> Result<()> {
        let registry = match self.world.get_resource::<Registry>() {
            Some(r) => r.clone(),
            None => crate::render::passes::builtin()?,
        }
        .with::<P>()
        .ordered()?;
        if let Some(gpu) = self.world.get_resource::<Gpu>().cloned() {
            let pass = P::create(&mut self.world, &gpu)?;
            self.world.insert_resource(pass);
            self.world.insert_resource(registry);
            render::build_render_schedule(&mut self.world);
        } else {
            self.world.insert_resource(registry);
        }
        Ok(())
    }

    /// Adds a knob to the ones the viewer's panel, `--explain` and the reports list (the
    /// front end adds its flag to the command line it builds from
    /// [`crate::quality::Knobs`]). Its value lives in [`Quality::extensions`] unless its
    /// path is a field of [`Quality`]; a name already taken is an error.
    pub fn add_knob(&mut self, knob: &'static crate::quality::Knob) -> Result<()> {
        let knobs = self
            .world
            .resource::<crate::quality::Knobs>()
            .clone()
            .with(knob)
            .map_err(|e| Error::InvalidArgument(e.to_string()))?;
        self.world.insert_resource(knobs);
        Ok(())
    }

    /// Why the GPU device was lost, if it was; attach a new GPU to go on.
    pub fn gpu_lost(&self) -> Option<String> {
        self.world.get_resource::<Gpu>().and_then(Gpu::lost)
    }

    /// The adapter in use, if a GPU is attached.
    pub fn adapter(&self) -> Option<&AdapterSummary> {
        self.world.get_resource::<Gpu>().map(|g| &g.summary)
    }

    /// The World.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The World, mutably: spawn and change entities and resources here.
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// Adds a mesh to the store and returns its handle.
    pub fn add_mesh(&mut self, mesh: MeshData) -> Result<MeshHandle> {
        self.world
            .resource_mut::<Meshes>()
            .add(mesh)
            .map_err(|e| Error::Scene(format!("invalid mesh: {e}")))
    }

    /// Adds a mesh that skinning or morph targets deform, with its per-vertex joints and
    /// weights (both empty, or one set of four per vertex) and its morph targets; see
    /// [`crate::scene::deform`]. Draw it with a [`crate::scene::SkinnedMesh`] and/or
    /// [`crate::scene::MorphWeights`] beside the [`crate::scene::Mesh3d`].
    pub fn add_deformable_mesh(
        &mut self,
        mesh: MeshData,
        joints: Vec<[u32; 4]>,
        weights: Vec<[f32; 4]>,
        targets: Vec<crate::scene::MorphTarget>,
    ) -> Result<MeshHandle> {
        self.world
            .resource_mut::<Meshes>()
            .add_deformable(mesh, joints, weights, targets)
            .map_err(|e| Error::Scene(format!("invalid deformable mesh: {e}")))
    }

    /// Adds a texture to the [`crate::scene::Textures`] store.
    pub fn add_texture(
        &mut self,
        texture: crate::scene::TextureData,
    ) -> Result<crate::scene::TextureHandle> {
        self.world
            .resource_mut::<crate::scene::Textures>()
            .add(texture)
            .map_err(|e| Error::Scene(format!("invalid texture: {e}")))
    }

    /// Adds systems to the [`Update`] schedule.
    pub fn add_systems<M>(
        &mut self,
        systems: impl IntoScheduleConfigs<ScheduleSystem, M>,
    ) -> &mut Self {
        self.world
            .resource_mut::<Schedules>()
            .add_systems(Update, systems);
        self
    }

    /// Makes every frame advance [`Time`] by `delta_s` seconds (your systems and
    /// automatic exposure read it) instead of the real time between frames; `None` goes
    /// back to real time. A headless app starts with [`HEADLESS_DELTA_S`], an app made
    /// with [`App::new`] (the viewer's) with real time. A negative or non-finite step is
    /// ignored (real time).
    pub fn set_fixed_delta(&mut self, delta_s: Option<f32>) {
        self.clock.fixed_delta_s = delta_s.filter(|d| d.is_finite() && *d >= 0.0);
    }

    /// Queues an input event (a key, a mouse button, the cursor, the wheel) for the next
    /// [`App::update`], which applies it to the [`Keys`], [`MouseButtons`] and
    /// [`Mouse`] resources before your systems run. The viewer sends its window's events;
    /// tests and scripts can send their own.
    pub fn send_input(&mut self, event: InputEvent) {
        self.world.resource_mut::<PendingInput>().0.push(event);
    }

    /// Spreads the irradiance volume's captures over frames, at most
    /// [`crate::quality::GiSettings::probes_per_frame`] probes before each (on), or
    /// converges it before the next frame (off, the default: every still frame sees a
    /// converged volume).
    pub fn set_progressive_probes(&mut self, progressive: bool) {
        self.progressive_probes = progressive;
    }

    /// With `--aa taa`: render one frame per call, blending it with the history of the
    /// earlier calls (on: the viewer, `bench`), or converge a still image in each call
    /// from a fresh history ([`TAA_JITTER_PERIOD`](crate::render::post::antialias::taa::TAA_JITTER_PERIOD) jittered frames; off, the default).
    pub fn set_progressive_taa(&mut self, progressive: bool) {
        self.progressive_taa = progressive;
    }

    /// Tells temporal anti-aliasing that the camera jumped: the next frame starts a new
    /// history instead of reprojecting the old one.
    pub fn camera_cut(&mut self) {
        self.pending_cut = true;
    }

    /// Starts a frame: advances [`Time`] by one step, applies the input sent since the
    /// last update, and runs your [`Update`] systems. The next rendered frame uses the
    /// same step (a frame rendered without an update takes a step of its own).
    pub fn update(&mut self) {
        self.tick();
        self.ticked = true;
        input::apply_pending(&mut self.world);
        self.world.run_schedule(Update);
    }

    /// Advances [`Time`] by one step of the clock.
    fn tick(&mut self) {
        let delta = self.clock.tick();
        self.world.resource_mut::<Time>().advance(delta);
    }

    /// Renders one frame into an offscreen image of `size` pixels, waiting for the GPU.
    /// Read it with [`App::read_display_image`] and [`App::read_hdr_image`].
    pub fn render_headless(&mut self, size: (u32, u32)) -> Result<FrameReport> {
        let gpu = self.gpu()?.clone();
        self.check_size(&gpu, size)?;
        if self
            .offscreen
            .as_ref()
            .is_none_or(|o| (o.texture.width(), o.texture.height()) != size)
        {
            self.offscreen = Some(Target::new(&gpu, "display image", size, HEADLESS_FORMAT));
        }
        let view = self.offscreen.as_ref().map(|o| o.view.clone());
        self.render_to_view(view, HEADLESS_FORMAT, size)
    }

    /// Renders one frame into `view` (e.g. a window's surface texture) of `format` and
    /// `size`, waiting for the GPU to finish.
    ///
    /// After [`App::reload_shaders`], a frame that fails puts the previous shaders back
    /// (the next frame renders with them) and returns the error.
    pub fn render_to_view(
        &mut self,
        view: Option<wgpu::TextureView>,
        format: wgpu::TextureFormat,
        size: (u32, u32),
    ) -> Result<FrameReport> {
        if let Some(reason) = self.gpu_lost() {
            return Err(Error::Gpu(format!(
                "the GPU device was lost ({reason}): attach a new GPU (App::attach_gpu)"
            )));
        }
        let result = self.render_frame(view, format, size);
        if let Err(e) = &result
            && let Some(reason) = self.world.get_resource::<Gpu>().and_then(Gpu::poll_lost)
        {
            return Err(Error::Gpu(format!(
                "{e}; the GPU device was lost ({reason})"
            )));
        }
        match (result, self.shader_fallback.take()) {
            (Err(e), Some(previous)) => {
                let gpu = self.gpu()?.clone();
                self.restore_shaders(&gpu, previous)?;
                Err(Error::Gpu(format!(
                    "{e}\n(the reloaded shaders failed: the previous ones are back)"
                )))
            }
            (result, _) => result,
        }
    }

    /// Reads the WGSL modules in `dir` (e.g. the repository's `shaders/`) and rebuilds
    /// every pass from them; a file that is missing keeps the built-in source. Returns
    /// the files whose source changed (empty: nothing to do).
    ///
    /// A module that does not compile is an error naming it, and the previous shaders stay
    /// in use; so does a frame that fails with the new shaders (see
    /// [`App::render_to_view`]). Nothing panics on a broken shader.
    pub fn reload_shaders(&mut self, dir: &Path) -> Result<Vec<&'static str>> {
        let gpu = self.gpu()?.clone();
        let new = shaders::read_overrides(dir)?;
        let old = gpu.shaders.overrides();
        let changed: Vec<&'static str> = shaders::BUILTIN
            .iter()
            .map(|(file, _)| *file)
            .filter(|file| new.get(file) != old.get(file))
            .collect();
        if changed.is_empty() {
            return Ok(changed);
        }
        gpu.shaders.set_overrides(new);
        if let Err(e) = render::insert_passes(&mut self.world, &gpu) {
            self.restore_shaders(&gpu, old)?;
            return Err(Error::Gpu(format!(
                "{e}\n(the reloaded shaders failed: the previous ones are back)"
            )));
        }
        self.shader_fallback = Some(old);
        Ok(changed)
    }

    fn restore_shaders(&mut self, gpu: &Gpu, previous: ShaderOverrides) -> Result<()> {
        gpu.shaders.set_overrides(previous);
        render::insert_passes(&mut self.world, gpu)
    }

    /// [`check_size`], once per new size.
    fn check_size(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<()> {
        if self.checked_size != Some(size) {
            check_size(gpu, size, self.world.get_resource::<Quality>())?;
            self.checked_size = Some(size);
        }
        Ok(())
    }

    fn render_frame(
        &mut self,
        view: Option<wgpu::TextureView>,
        format: wgpu::TextureFormat,
        size: (u32, u32),
    ) -> Result<FrameReport> {
        let gpu = self.gpu()?.clone();
        self.check_size(&gpu, size)?;
        let start = Instant::now();
        let mut stages = Vec::new();
        let mut stage = |name, t: Instant| stages.push((name, t.elapsed().as_secs_f64() * 1e3));

        if !std::mem::take(&mut self.ticked) {
            self.tick();
        }
        let delta = self.world.resource::<Time>().delta_secs();
        self.world.insert_resource(FrameDelta(delta));

        let t = Instant::now();
        self.world.run_schedule(PostUpdate);
        stage("propagate", t);

        // The capture reads the frame's aspect ratio (directional cascades follow it).
        self.world.insert_resource(FrameOutput {
            size,
            view: None,
            format,
        });
        self.world
            .resource_mut::<crate::render::indirect::environment_maps::Ibl>()
            .last_steps
            .clear();
        let t = Instant::now();
        let probes = crate::render::indirect::capture::update_probes_for_frame(
            &mut self.world,
            self.progressive_probes,
        )?;
        stage("probes", t);

        self.world
            .insert_resource(FrameOutput { size, view, format });
        // The image's renders (several for accumulation and a still TAA image); their
        // stage and pass times add up.
        let cut = std::mem::take(&mut self.pending_cut);
        let mut renders = Renders::plan(&mut self.world, size, self.progressive_taa, cut);
        let mut passes: Vec<PassTiming> = Vec::new();
        for index in 0..renders.count() {
            renders.begin(&mut self.world, index);
            let timings = self.render_sub_frame(&gpu, &mut stage)?;
            renders.end(&self.world);
            add_pass_timings(&mut passes, timings);
        }
        let (accumulated, temporal_frames) = (renders.accumulated(), renders.temporal_frames());
        renders.finish(&mut self.world);
        let frame_ms = start.elapsed().as_secs_f64() * 1e3;
        let stages = merged_stages(stages);
        crate::render::post::exposure::feed_back(&mut self.world, &gpu)?;
        let extracted = self.world.resource::<ExtractedFrame>();
        let camera = extracted
            .camera
            .as_ref()
            .ok_or_else(|| Error::Scene("no active camera".into()))?;
        Ok(FrameReport {
            passes,
            stages,
            frame_ms,
            plan: self.world.resource::<FramePlan>().clone(),
            exposure: camera.exposure,
            ev100: camera.ev100,
            stats: SceneStats {
                instances: extracted.instances.len(),
                draws: extracted.draws(),
                triangles: extracted.triangles,
                lights: extracted.light_counts.total(),
            },
            preprocessing: self
                .world
                .resource::<crate::render::indirect::environment_maps::Ibl>()
                .last_steps
                .clone(),
            notes: camera.notes.clone(),
            metered: *self.world.resource::<MeteredExposure>(),
            probes,
            accumulated,
            temporal_frames,
        })
    }

    /// Extracts, records, submits and waits for one render of the frame; returns its
    /// pass timings.
    fn render_sub_frame(
        &mut self,
        gpu: &Gpu,
        stage: &mut impl FnMut(&'static str, Instant),
    ) -> Result<Vec<PassTiming>> {
        self.world.resource_mut::<FrameErrors>().0.clear();
        let t = Instant::now();
        self.world.run_schedule(ExtractSchedule);
        stage("extract", t);
        self.take_errors()?;

        let t = Instant::now();
        self.world.run_schedule(RenderSchedule);
        stage("record", t);
        let taken = self.world.resource_mut::<FrameEncoder>().encoder.take();
        if !self.world.resource::<FrameErrors>().0.is_empty()
            && let Some(mut shadows) = self
                .world
                .get_resource_mut::<crate::render::shadow::pass::ShadowPass>()
        {
            // This frame's commands never reach the GPU: its shadow atlas was not drawn.
            shadows.forget();
        }
        self.take_errors()?;
        let mut encoder =
            taken.ok_or_else(|| Error::Gpu("the frame recorded no commands".into()))?;

        let t = Instant::now();
        self.world
            .resource::<FrameEncoder>()
            .timer
            .resolve(&mut encoder);
        let index = gpu.checked("frame", |_| gpu.queue.submit([encoder.finish()]))?;
        stage("submit", t);

        let t = Instant::now();
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            })
            .map_err(|e| Error::Gpu(format!("waiting for the frame: {e}")))?;
        stage("wait", t);
        Ok(self.world.resource_mut::<FrameEncoder>().timer.collect(gpu))
    }

    /// The EV100 automatic exposure has adapted to, which the next frame uses; `None`
    /// unless automatic exposure has metered a frame (or without a GPU).
    pub fn metered_ev100(&self) -> Option<f32> {
        self.world
            .get_resource::<MeteredExposure>()
            .and_then(|m| m.ev100)
    }

    /// The last headless frame's display image (tone mapped, sRGB-encoded, 8-bit RGBA).
    pub fn read_display_image(&self) -> Result<image::RgbaImage> {
        let gpu = self.gpu()?;
        let offscreen = self
            .offscreen
            .as_ref()
            .ok_or_else(|| Error::InvalidArgument("no headless frame was rendered".into()))?;
        let bytes = read_texture(gpu, &offscreen.texture, 4)?;
        image::RgbaImage::from_raw(offscreen.texture.width(), offscreen.texture.height(), bytes)
            .ok_or_else(|| Error::Gpu("display image readback has the wrong size".into()))
    }

    /// The last frame's HDR target: exposed luminance (rgb, before tone mapping) and
    /// coverage (a = 1 where geometry was drawn).
    pub fn read_hdr_image(&self) -> Result<image::Rgba32FImage> {
        self.read_target(FrameTarget::Hdr)
    }

    /// Keeps `target` after each frame, for [`App::read_target`]. Only HDR is kept unless
    /// asked: the frame graph lends the memory of a target nothing reads after the frame
    /// to later passes ([`crate::render::graph::slots::KeptSlots`]). Call it before rendering
    /// the frames to read.
    pub fn keep_target(&mut self, target: FrameTarget) {
        if let Some(slot) = target.slot() {
            let mut kept = self.world.get_resource_or_insert_with(KeptSlots::default);
            if !kept.0.contains(&slot) {
                kept.0.push(slot);
            }
        }
    }

    /// One of the last frame's targets as float RGBA: G-buffer channels as stored
    /// (base colour decoded from sRGB by the read, normals still octahedral), depth in the
    /// red channel. A target other than HDR and the shadow atlas must have been kept
    /// ([`App::keep_target`]) before the frame rendered.
    pub fn read_target(&self, target: FrameTarget) -> Result<image::Rgba32FImage> {
        let gpu = self.gpu()?;
        if let Some(slot) = target.slot()
            && !self
                .world
                .get_resource::<KeptSlots>()
                .is_some_and(|k| k.0.contains(&slot))
        {
            return Err(Error::InvalidArgument(format!(
                "the {} target is not kept after the frame: call App::keep_target(FrameTarget::{target:?}) before rendering",
                slot.name
            )));
        }
        let depth = |texture: &wgpu::Texture| -> Result<Vec<f32>> {
            if !gpu
                .adapter
                .get_downlevel_capabilities()
                .flags
                .contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES)
            {
                return Err(Error::Gpu(format!(
                    "{} ({}) cannot copy depth textures to memory: depth and shadow-atlas readback need Vulkan",
                    gpu.summary.name, gpu.summary.backend
                )));
            }
            Ok(read_texture(gpu, texture, 4)?
                .chunks_exact(4)
                .flat_map(|b| [f32::from_le_bytes([b[0], b[1], b[2], b[3]]), 0.0, 0.0, 1.0])
                .collect())
        };
        if target == FrameTarget::ShadowAtlas {
            let atlas = &self
                .world
                .resource::<crate::render::shadow::atlas::ShadowAtlas>()
                .atlas
                .texture;
            return image::Rgba32FImage::from_raw(atlas.width(), atlas.height(), depth(atlas)?)
                .ok_or_else(|| Error::Gpu("atlas readback has the wrong size".into()));
        }
        let targets = self.world.resource::<RenderTargets>();
        let t = targets
            .current
            .as_ref()
            .ok_or_else(|| Error::InvalidArgument("no frame was rendered".into()))?;
        let texture = |slot: Slot| {
            t.texture(slot).ok_or_else(|| {
                Error::InvalidArgument(format!("the last frame had no {} target", slot.name))
            })
        };
        let data: Vec<f32> = match target {
            FrameTarget::GBuffer0 => read_texture(gpu, texture(slots::GBUFFER_BASE_COLOR)?, 4)?
                .chunks_exact(4)
                .flat_map(|p| {
                    let c = |v: u8| crate::shading::color::srgb_decode(f32::from(v) / 255.0);
                    [c(p[0]), c(p[1]), c(p[2]), f32::from(p[3]) / 255.0]
                })
                .collect(),
            FrameTarget::GBuffer1 => {
                f16_bytes_to_f32(&read_texture(gpu, texture(slots::GBUFFER_NORMAL)?, 8)?)
            }
            FrameTarget::GBuffer2 => {
                f16_bytes_to_f32(&read_texture(gpu, texture(slots::GBUFFER_EMISSIVE)?, 8)?)
            }
            FrameTarget::Depth | FrameTarget::ShadowAtlas => depth(texture(slots::DEPTH)?)?,
            FrameTarget::Hdr if t.hdr_format == wgpu::TextureFormat::Rgba32Float => {
                read_texture(gpu, texture(slots::HDR)?, 16)?
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect()
            }
            FrameTarget::Hdr => f16_bytes_to_f32(&read_texture(gpu, texture(slots::HDR)?, 8)?),
            FrameTarget::Motion => f16_bytes_to_f32(&read_texture(
                gpu,
                texture(crate::render::graph::slots::MOTION)?,
                4,
            )?)
            .chunks_exact(2)
            .flat_map(|m| [m[0], m[1], 0.0, 1.0])
            .collect(),
        };
        image::Rgba32FImage::from_raw(t.size.0, t.size.1, data)
            .ok_or_else(|| Error::Gpu("target readback has the wrong size".into()))
    }

    fn gpu(&self) -> Result<&Gpu> {
        self.world
            .get_resource::<Gpu>()
            .ok_or_else(|| Error::InvalidArgument("no GPU attached: call App::attach_gpu".into()))
    }

    fn take_errors(&mut self) -> Result<()> {
        let mut errors = std::mem::take(&mut self.world.resource_mut::<FrameErrors>().0);
        match errors.len() {
            0 => Ok(()),
            _ => Err(errors.remove(0)),
        }
    }
}

/// Checks a frame size before anything is allocated: each side within the adapter's 2D
/// texture limit, and the frame's estimated memory ([`frame_bytes`]) within the memory
/// budget ([`crate::limits::memory_budget`]).
fn check_size(gpu: &Gpu, (w, h): (u32, u32), quality: Option<&Quality>) -> Result<()> {
    let max = gpu.max_texture_size();
    if w == 0 || h == 0 || w > max || h > max {
        return Err(Error::InvalidArgument(format!(
            "image size {w}x{h} is out of range: each side must be 1..={max} on this adapter"
        )));
    }
    let hdr = quality.map_or(crate::quality::HdrPrecision::Half, |q| q.hdr_precision);
    let need = frame_bytes((w, h), hdr.format());
    let budget = crate::limits::memory_budget();
    if need > budget.bytes {
        return Err(Error::InvalidArgument(format!(
            "a {w}x{h} frame needs about {} for its targets and read-back, over the memory budget of {budget}",
            crate::limits::bytes_text(need)
        )));
    }
    Ok(())
}

/// Estimated memory of one frame of `size` (bytes): the core targets (G-buffer, depth,
/// the HDR target in `hdr_format`, the display image), the float read-back of the HDR
/// target and its copy as an image on the CPU. Shadow maps and environment cubes do not
/// grow with the frame and are left out.
pub fn frame_bytes(size: (u32, u32), hdr_format: wgpu::TextureFormat) -> u64 {
    let texel = |f: wgpu::TextureFormat| u64::from(f.block_copy_size(None).unwrap_or(4));
    let targets = [
        slots::GBUFFER0_FORMAT,
        slots::GBUFFER1_FORMAT,
        slots::GBUFFER2_FORMAT,
        slots::DEPTH_FORMAT,
        hdr_format,
        HEADLESS_FORMAT,
    ]
    .map(texel)
    .iter()
    .sum::<u64>();
    let float_rgba = 16;
    let per_pixel = targets + 2 * float_rgba;
    u64::from(size.0) * u64::from(size.1) * per_pixel
}

/// Adds one render's pass `timings` to the image's, pass by pass.
fn add_pass_timings(passes: &mut Vec<PassTiming>, timings: Vec<PassTiming>) {
    for p in timings {
        match passes.iter_mut().find(|q| q.name == p.name) {
            Some(q) => {
                q.cpu_ms += p.cpu_ms;
                q.gpu_ms = q.gpu_ms.zip(p.gpu_ms).map(|(a, b)| a + b);
            }
            None => passes.push(p),
        }
    }
}

/// The stage times (ms) summed by stage name, in the order the stages first ran.
fn merged_stages(stages: Vec<(&'static str, f64)>) -> Vec<(&'static str, f64)> {
    let mut merged: Vec<(&'static str, f64)> = Vec::new();
    for (name, ms) in stages {
        match merged.iter_mut().find(|(n, _)| *n == name) {
            Some((_, total)) => *total += ms,
            None => merged.push((name, ms)),
        }
    }
    merged
}

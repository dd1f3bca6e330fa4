//! Depth of field (`shaders/dof.wgsl`): the thin-lens circle of confusion, a ring gather
//! at half resolution with separate far and near fields, composited at full resolution.
//! Runs only when the camera has [`crate::scene::DepthOfField`].

use crate::error::Result;
use crate::render::bindings::CachedGroup;
use crate::render::device::Gpu;
use crate::render::extract::{ExtractedCamera, ExtractedFrame};
use crate::render::frame::FrameEncoder;
use crate::render::graph::slots::{DEPTH, HDR};
use crate::render::graph::{
    Extent, FramePass, FramePlan, PassDecision, PassId, ShaderBuild, Slot, TargetFormat,
    TextureDesc,
};
use crate::render::pass_params::{Prepare, Record};
use crate::render::pipeline_cache::PipelineCache;
use crate::render::pipelines::create_module;
use crate::render::pipelines::{draw_fullscreen, fullscreen_pipeline};
use crate::render::scene_buffers::SceneBuffers;
use crate::scene::DepthOfField;
use bevy_ecs::prelude::*;

#[allow(non_upper_case_globals)]
impl PassId {
    /// Depth of field.
    pub const Dof: PassId = PassId::new("dof");
}

/// The depth-of-field passes compile one set of pipelines (the composite per HDR format,
/// which the targets decide).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DofVariant;

impl FramePass for DofPass {
    const ID: PassId = PassId::Dof;
    const READS: &'static [Slot] = &[HDR, DEPTH];
    const WRITES: &'static [Slot] = &[HDR, DOF_SHARP, DOF_INPUT, DOF_TILES, DOF_FAR, DOF_NEAR];
    type Variant = DofVariant;

    fn create(_: &mut World, gpu: &Gpu) -> Result<Self> {
        DofPass::new(gpu)
    }

    fn decide(world: &World, _: &FramePlan) -> PassDecision<DofVariant> {
        let camera = world.resource::<ExtractedFrame>().camera.as_ref();
        let reason = match camera.and_then(|c| c.depth_of_field.map(|d| (c, d))) {
            Some((c, d)) => format!(
                "f/{:.1}, focus {:.2} m, {:.0} mm, {} rings, CoC ≤ {:.0} px",
                c.lens.aperture_f_stops,
                c.lens.focus_distance_m,
                c.focal_length_m * 1e3,
                d.rings,
                d.max_coc_px
            ),
            None => "depth of field is off".into(),
        };
        PassDecision::new(
            camera.is_some_and(|c| c.depth_of_field.is_some()),
            reason,
            DofVariant,
        )
    }

    crate::pass_systems!(prepare_dof, dof_pass);

    fn shader_builds() -> Vec<ShaderBuild> {
        vec![ShaderBuild::new("dof.wgsl", Vec::new(), &[])]
    }
}

/// Format of the half-resolution depth-of-field targets.
pub const DOF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the near-field tile target (largest near CoC radius, half-res pixels).
const TILE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// Half-resolution pixels per side of a near-field tile (`TILE` in `dof.wgsl`).
const TILE: u32 = 8;

/// The sharp frame, copied from the HDR target before the composite overwrites it.
pub const DOF_SHARP: Slot = Slot::target("dof sharp", TargetFormat::Hdr);
/// The prepared half-resolution colour and CoC.
pub const DOF_INPUT: Slot = half("dof input", DOF_FORMAT);
/// The largest near CoC per tile of `TILE`² half-resolution pixels.
pub const DOF_TILES: Slot = Slot::texture(
    "dof near tiles",
    TextureDesc::full(TargetFormat::Fixed(TILE_FORMAT)).at(Some(Extent::Divided(2 * TILE))),
);
/// The blurred far field.
pub const DOF_FAR: Slot = half("dof far", DOF_FORMAT);
/// The blurred near field.
pub const DOF_NEAR: Slot = half("dof near", DOF_FORMAT);

/// A half-resolution texture of `format`.
const fn half(name: &'static str, format: wgpu::TextureFormat) -> Slot {
    Slot::texture(
        name,
        TextureDesc::full(TargetFormat::Fixed(format)).at(Some(Extent::HALF)),
    )
}

/// The thin lens as the CoC shaders read it (the first five fields of `DofParams` in
/// `dof.wgsl` and of `DebugParams` in `debug_view.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LensUniform {
    /// Focus distance (m); infinity as the largest float (the shaders test `> 3e38`).
    pub focus_m: f32,
    /// Focal length (m).
    pub focal_length_m: f32,
    /// Aperture diameter f/N (m).
    pub aperture_diameter_m: f32,
    /// Full-resolution pixels per metre on the sensor, for a target `height` pixels high.
    pub pixels_per_m: f32,
    /// Largest CoC radius (full-resolution pixels).
    pub max_radius_px: f32,
}

impl LensUniform {
    /// The lens of `camera` with `dof`'s largest CoC, for a target `height` pixels high.
    pub fn new(camera: &ExtractedCamera, dof: DepthOfField, height: u32) -> LensUniform {
        let lens = camera.lens;
        LensUniform {
            focus_m: lens.focus_distance_m.min(f32::MAX),
            focal_length_m: camera.focal_length_m,
            aperture_diameter_m: camera.focal_length_m / lens.aperture_f_stops,
            pixels_per_m: height as f32 / (lens.sensor_height_mm * 1e-3),
            max_radius_px: dof.max_coc_px * 0.5,
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    lens: LensUniform,
    rings: u32,
    pad: [f32; 2],
}

/// The depth-of-field passes.
#[derive(Resource)]
pub struct DofPass {
    prepare: wgpu::RenderPipeline,
    tiles: wgpu::RenderPipeline,
    blur: wgpu::RenderPipeline,
    /// The composite and its bind group layout, per HDR format.
    composite: PipelineCache<wgpu::TextureFormat, (wgpu::RenderPipeline, wgpu::BindGroupLayout)>,
    /// The prepare, tiles and blur steps' bind group layouts (derived from the shader).
    layouts: [wgpu::BindGroupLayout; 3],
    module: wgpu::ShaderModule,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    /// The prepare, tiles, blur and composite steps' groups.
    bind_groups: [CachedGroup; 4],
}

impl DofPass {
    /// Compiles the three pipelines.
    pub fn new(gpu: &Gpu) -> Result<Self> {
        let source = gpu.shaders.compose("dof.wgsl", &[])?;
        let module = create_module(gpu, "dof", &source)?;
        let pipeline = |entry, formats: &[wgpu::TextureFormat]| {
            fullscreen_pipeline(
                gpu,
                entry,
                None,
                &module,
                ("vs_fullscreen", entry),
                formats,
                None,
            )
        };
        let prepare = pipeline("fs_dof_prepare", &[DOF_FORMAT])?;
        let tiles = pipeline("fs_dof_tiles", &[TILE_FORMAT])?;
        let blur = pipeline("fs_dof_blur", &[DOF_FORMAT, DOF_FORMAT])?;
        Ok(DofPass {
            layouts: [&prepare, &tiles, &blur].map(|p| p.get_bind_group_layout(0)),
            prepare,
            tiles,
            blur,
            composite: PipelineCache::default(),
            params: gpu.uniform_buffer("dof params", std::mem::size_of::<Params>() as u64),
            sampler: gpu.sampler("dof linear", wgpu::FilterMode::Linear),
            bind_groups: Default::default(),
            module,
        })
    }

    /// The composite pipeline writing an HDR target of `format`, compiled on first use.
    fn composite_pipeline(&mut self, gpu: &Gpu, format: wgpu::TextureFormat) -> Result<()> {
        let DofPass {
            composite, module, ..
        } = self;
        composite.ensure_with(&format, || {
            let pipeline = fullscreen_pipeline(
                gpu,
                "fs_dof_composite",
                None,
                module,
                ("vs_fullscreen", "fs_dof_composite"),
                &[format],
                None,
            )?;
            let layout = pipeline.get_bind_group_layout(0);
            Ok((pipeline, layout))
        })?;
        Ok(())
    }
}

/// Writes the lens parameters and builds the bind groups.
pub fn prepare_dof(
    mut p: Prepare<DofPass>,
    frame: Res<ExtractedFrame>,
    buffers: Res<SceneBuffers>,
) -> Result<()> {
    let (Some(camera), Some(t)) = (frame.camera.as_ref(), p.targets.current.as_ref()) else {
        return Ok(());
    };
    let (Some(dof), Some([depth, sharp, input, tiles, far, near])) = (
        camera.depth_of_field,
        t.views([DEPTH, DOF_SHARP, DOF_INPUT, DOF_TILES, DOF_FAR, DOF_NEAR]),
    ) else {
        return Ok(());
    };
    p.pass.composite_pipeline(&p.gpu, t.hdr_format)?;
    let params = Params {
        lens: LensUniform::new(camera, dof, t.size.1),
        rings: dof.rings,
        pad: [0.0; 2],
    };
    if !(params.lens.pixels_per_m.is_finite() && params.lens.aperture_diameter_m.is_finite()) {
        return Err(crate::Error::Scene(
            "depth of field: the lens gives no finite aperture".into(),
        ));
    }
    p.gpu
        .queue
        .write_buffer(&p.pass.params, 0, bytemuck::bytes_of(&params));
    let DofPass {
        composite,
        layouts,
        params,
        sampler,
        bind_groups: [prepare, tile_group, blur, composite_group],
        ..
    } = &mut *p.pass;
    let Some((_, composite_layout)) = composite.get(&t.hdr_format) else {
        return Ok(());
    };
    let entry = |binding, resource| wgpu::BindGroupEntry { binding, resource };
    let view = wgpu::BindingResource::TextureView;
    prepare.entries(
        &p.gpu,
        "dof prepare",
        &layouts[0],
        vec![
            entry(0, buffers.view.as_entire_binding()),
            entry(1, params.as_entire_binding()),
            entry(2, view(sharp)),
            entry(3, view(depth)),
        ],
    );
    tile_group.entries(
        &p.gpu,
        "dof tiles",
        &layouts[1],
        vec![entry(1, params.as_entire_binding()), entry(4, view(input))],
    );
    blur.entries(
        &p.gpu,
        "dof blur",
        &layouts[2],
        vec![
            entry(1, params.as_entire_binding()),
            entry(4, view(input)),
            entry(8, view(tiles)),
        ],
    );
    composite_group.entries(
        &p.gpu,
        "dof composite",
        composite_layout,
        vec![
            entry(0, buffers.view.as_entire_binding()),
            entry(1, params.as_entire_binding()),
            entry(2, view(sharp)),
            entry(3, view(depth)),
            entry(5, view(far)),
            entry(6, view(near)),
            entry(7, wgpu::BindingResource::Sampler(sampler)),
        ],
    );
    Ok(())
}

/// Records the depth-of-field passes: copy, prepare, near tiles, blur, composite into the
/// HDR target.
pub fn dof_pass(mut r: Record<DofPass>) {
    let FrameEncoder { encoder, timer } = &mut *r.encoder;
    let [prepare, tiles, blur, composite] = &r.pass.bind_groups;
    let (Some(encoder), Some(t), Some(prepare), Some(tiles), Some(blur), Some(composite)) = (
        encoder.as_mut(),
        r.targets.current.as_ref(),
        prepare.group(),
        tiles.group(),
        blur.group(),
        composite.group(),
    ) else {
        return;
    };
    let (Some((composite_pipeline, _)), Some([hdr, input, tile_view, far, near])) = (
        r.pass.composite.get(&t.hdr_format),
        t.views([HDR, DOF_INPUT, DOF_TILES, DOF_FAR, DOF_NEAR]),
    ) else {
        return;
    };
    t.copy(encoder, HDR, DOF_SHARP);
    draw_fullscreen(
        encoder,
        timer,
        "dof prepare",
        &[input],
        &r.pass.prepare,
        prepare,
    );
    draw_fullscreen(
        encoder,
        timer,
        "dof tiles",
        &[tile_view],
        &r.pass.tiles,
        tiles,
    );
    draw_fullscreen(encoder, timer, "dof blur", &[far, near], &r.pass.blur, blur);
    draw_fullscreen(
        encoder,
        timer,
        "dof composite",
        &[hdr],
        composite_pipeline,
        composite,
    );
}

/// Asserts that each field of [`LensUniform`], placed `lens_offset` bytes into WGSL struct
/// `wgsl` of `entry` (composed with `defs`), lies at the member of the same name: the lens
/// has no WGSL struct of its own, it is the head of `DofParams` and of `DebugParams`.
#[cfg(test)]
pub(crate) fn assert_lens_heads(
    entry: &str,
    defs: &[crate::render::shaders::ShaderDef],
    wgsl: &str,
    lens_offset: usize,
) {
    use std::mem::offset_of;
    let layout =
        crate::render::shaders::struct_layout(entry, defs, wgsl).unwrap_or_else(|e| panic!("{e}"));
    let fields = [
        ("focus_m", offset_of!(LensUniform, focus_m)),
        ("focal_length_m", offset_of!(LensUniform, focal_length_m)),
        (
            "aperture_diameter_m",
            offset_of!(LensUniform, aperture_diameter_m),
        ),
        ("pixels_per_m", offset_of!(LensUniform, pixels_per_m)),
        ("max_radius_px", offset_of!(LensUniform, max_radius_px)),
    ];
    for (name, offset) in fields {
        let member = layout.members.iter().find(|(m, _)| m == name);
        assert_eq!(
            member.map(|(_, o)| *o),
            Some((lens_offset + offset) as u32),
            "LensUniform::{name} in {wgsl} (WGSL layout {:?})",
            layout.members
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_params_lay_out_as_the_shader_does() {
        crate::assert_wgsl_twin!(Params, "dof.wgsl", &[], "DofParams", [
            lens => "focus_m", rings, pad => "pad0",
        ]);
    }

    #[test]
    fn the_lens_lies_where_the_shader_reads_it() {
        assert_lens_heads(
            "dof.wgsl",
            &[],
            "DofParams",
            std::mem::offset_of!(Params, lens),
        );
    }
}

//! Textured materials on the GPU: every [`TextureData`] a frame's [`crate::scene::MaterialMaps`] use is
//! uploaded once with a full mip chain (built on the CPU with a 2 × 2 box filter, in
//! linear light for sRGB textures), samplers are shared, and each distinct
//! `MaterialMaps` gets one bind group (group 1 of the G-buffer's textured variant).
//! Nothing here is built for a scene without `MaterialMaps`.

use crate::render::bindings::{BindGroupSpec, declared};
use crate::render::device::Gpu;
use crate::render::extract::{ExtractedFrame, FrameMaps};
use crate::render::frame::FrameErrors;
use crate::render::shaders::ShaderDef;
use crate::scene::extension_maps::{EXTENSION_PROPERTIES, EXTENSION_UNITS, NO_UNIT};
use crate::scene::{
    ColorSpace, Filter, Sampler, TextureData, TextureHandle, TextureSlot, Textures, Wrap,
};
use crate::shading::color::{srgb_decode, srgb_encode};
use bevy_ecs::prelude::*;
use bytemuck::{Pod, Zeroable};
use std::collections::HashMap;

/// `Maps` in `material_maps.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct GpuMaps {
    transforms: [[f32; 4]; 10],
    uv_sets: [u32; 4],
    extra: [u32; 4],
    params: [f32; 4],
    transmission: [f32; 4],
    attenuation: [f32; 4],
    clearcoat: [f32; 4],
    sheen: [f32; 4],
    anisotropy: [f32; 4],
    specular_tint: [f32; 4],
    film: [f32; 4],
    translucency: [f32; 4],
    extension_transforms: [[f32; 4]; 8],
    extension_uv_sets: [u32; 4],
    extension_units: [u32; 16],
    extension_params: [f32; 4],
}

/// The rows of the 2 × 3 part of `slot`'s coordinate transform acting on (u, v, 1)
/// (the identity without a slot or with a non-finite transform).
fn transform_rows(slot: Option<&TextureSlot>) -> [[f32; 4]; 2] {
    let m = slot.map_or(glam::Mat3::IDENTITY, |s| s.transform.matrix());
    let m = if m.is_finite() {
        m
    } else {
        glam::Mat3::IDENTITY
    };
    [
        [m.x_axis.x, m.y_axis.x, m.z_axis.x, 0.0],
        [m.x_axis.y, m.y_axis.y, m.z_axis.y, 0.0],
    ]
}

impl GpuMaps {
    /// The uniform of `entry`. A unit is bound only where the layout has units (`bound`)
    /// and its texture was uploaded (`uploaded`); a property whose unit is not bound
    /// keeps its factor, as in the path tracer (white is not a neutral direction or
    /// normal).
    fn new(entry: &FrameMaps, bound: bool, uploaded: impl Fn(TextureHandle) -> bool) -> Self {
        let maps = &entry.maps;
        let mut out = GpuMaps::default();
        for (k, slot) in maps.slots().iter().enumerate() {
            [out.transforms[2 * k], out.transforms[2 * k + 1]] = transform_rows(slot.as_ref());
        }
        let mut units = maps.extensions.units();
        for (k, slot) in units.units.iter().enumerate() {
            if !bound || !slot.is_some_and(|s| uploaded(s.texture)) {
                for of in units.of.iter_mut().filter(|u| **u == k as u32) {
                    *of = NO_UNIT;
                }
            }
            [
                out.extension_transforms[2 * k],
                out.extension_transforms[2 * k + 1],
            ] = transform_rows(slot.as_ref());
            out.extension_uv_sets[k] = slot.map_or(0, |s| s.uv_set.min(1));
        }
        out.extension_units = [NO_UNIT; 16];
        out.extension_units[..EXTENSION_PROPERTIES].copy_from_slice(&units.of);
        out.extension_params = [
            maps.extensions.thickness_min_nm(),
            units.units.iter().filter(|u| u.is_some()).count() as f32,
            maps.extensions.coat_normal_scale(),
            0.0,
        ];
        let set = |k: usize| maps.slots()[k].map_or(0, |s| s.uv_set.min(1));
        out.uv_sets = [set(0), set(1), set(2), set(3)];
        out.extra = [set(4), u32::from(maps.normal.is_some()), 0, 0];
        let finite = |x: f32, d: f32| if x.is_finite() { x } else { d };
        out.params = [
            finite(maps.normal_scale, 1.0),
            finite(maps.occlusion_strength, 1.0).clamp(0.0, 1.0),
            maps.alpha_cutoff.map_or(-1.0, |c| finite(c, 0.5)),
            if entry.blend { 1.0 } else { 0.0 },
        ];
        // Extraction has clamped the transmission; the attenuation distance stays ∞
        // where nothing is absorbed (`INFINITE_DISTANCE_M` in the shader).
        if let Some(t) = entry.transmission {
            out.transmission = [t.factor, t.ior, t.thickness_m, t.attenuation_distance_m];
            out.attenuation = t.attenuation_color.extend(t.dispersion).into();
        }
        if let Some(c) = entry.clearcoat {
            out.clearcoat = [c.factor, c.perceptual_roughness, 0.0, 0.0];
        }
        if let Some(sh) = entry.sheen {
            out.sheen = sh.color.extend(sh.perceptual_roughness).into();
        }
        if let Some(a) = entry.anisotropy {
            let (sin, cos) = a.rotation_rad.sin_cos();
            out.anisotropy = [a.strength, cos, sin, 0.0];
        }
        out.specular_tint = entry
            .specular_tint
            .unwrap_or(glam::Vec3::ONE)
            .extend(0.0)
            .into();
        if let Some(f) = entry.iridescence {
            out.film = [f.factor, f.ior, f.thickness_nm, 0.0];
        }
        if let Some(d) = entry.diffuse_transmission {
            out.translucency = d.color.extend(d.factor).into();
        }
        out
    }
}

/// The levels of a texture's mip chain, level 0 first, each RGBA8 (`width × height × 4`
/// bytes). Each level averages 2 × 2 texels of the one above (edge texels repeat for odd
/// sizes); sRGB colour channels are averaged in linear light, alpha and linear textures
/// as stored.
pub fn mip_chain(texture: &TextureData) -> Vec<(u32, u32, Vec<u8>)> {
    let srgb = texture.color_space == ColorSpace::Srgb;
    let decode: Vec<f32> = (0..256u32)
        .map(|c| {
            let x = c as f32 / 255.0;
            if srgb { srgb_decode(x) } else { x }
        })
        .collect();
    let encode = |v: f32, channel: usize| {
        let v = if srgb && channel < 3 {
            srgb_encode(v)
        } else {
            v
        };
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    };
    let mut levels = vec![(texture.width, texture.height, texture.rgba8.clone())];
    while let Some((w, h, above)) = levels.last() {
        let (w, h) = (*w, *h);
        if w <= 1 && h <= 1 {
            break;
        }
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut next = Vec::with_capacity((nw * nh * 4) as usize);
        for y in 0..nh {
            for x in 0..nw {
                for c in 0..4 {
                    let mut sum = 0.0;
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let sx = (2 * x + dx).min(w - 1);
                        let sy = (2 * y + dy).min(h - 1);
                        let byte = above[((sy * w + sx) * 4) as usize + c];
                        sum += if c < 3 {
                            decode[byte as usize]
                        } else {
                            f32::from(byte) / 255.0
                        };
                    }
                    next.push(encode(sum * 0.25, c));
                }
            }
        }
        levels.push((nw, nh, next));
    }
    levels
}

fn address(w: Wrap) -> wgpu::AddressMode {
    match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    }
}

fn filter(f: Filter) -> wgpu::FilterMode {
    match f {
        Filter::Nearest => wgpu::FilterMode::Nearest,
        Filter::Linear => wgpu::FilterMode::Linear,
    }
}

fn mipmap_filter(f: Filter) -> wgpu::MipmapFilterMode {
    match f {
        Filter::Nearest => wgpu::MipmapFilterMode::Nearest,
        Filter::Linear => wgpu::MipmapFilterMode::Linear,
    }
}

/// The material maps' bind group (the G-buffer pass's group 1): the factors, then the five
/// textures, then their samplers, in the order of [`crate::scene::MaterialMaps::slots`], then the
/// [`EXTENSION_UNITS`] extension textures and their samplers
/// ([`crate::scene::ExtensionMaps::units`]).
pub const BINDINGS: BindGroupSpec =
    BindGroupSpec::fragment("material maps", declared::TRANSPARENT_MAPS_GROUP);
/// [`BINDINGS`] without the extension units, for adapters that cannot bind them beside
/// the lighting pass's textures (OpenGL's 16 textures per stage, for one): extension
/// textures are then not sampled, and their factors apply.
pub const CORE_BINDINGS: BindGroupSpec = BindGroupSpec {
    label: "material maps (no extension textures)",
    visibility: BINDINGS.visibility,
    bindings: BINDINGS.bindings.split_at(11).0,
};

/// The header constant that places the maps' bind group (`MAPS_GROUP` in
/// `material_maps.wgsl`) at `group`: 1 in the G-buffer and shadow passes, 4 in the
/// transparent and layers passes, whose groups 1 to 3 are the lighting pass's.
pub const fn group_def(group: u32) -> ShaderDef {
    ShaderDef::U32("MAPS_GROUP", group)
}

/// The shader defs of a pass that reads the extension textures (it imports
/// `extension_units.wgsl`) at maps group `group`: where the layout has no units
/// ([`CORE_BINDINGS`]), the module that reads white for every unit takes its place.
pub fn unit_defs(group: u32, units: bool) -> Vec<ShaderDef> {
    let mut defs = vec![group_def(group)];
    if !units {
        defs.push(ShaderDef::Import(
            "extension_units",
            "extension_units_unbound",
        ));
    }
    defs
}

/// What a pass that reads the extension textures adds to its reason to run: a note that
/// they are not sampled where the layout has no units and `frame` has some.
pub fn unsampled_note(frame: &ExtractedFrame, units: bool) -> &'static str {
    if !units && frame.material_maps.iter().any(|m| m.maps.extensions.any()) {
        "; extension textures not sampled (the adapter binds too few textures per stage), their factors apply"
    } else {
        ""
    }
}

/// The GPU side of textured materials.
#[derive(Resource)]
pub struct GpuMaterialMaps {
    /// Layout of group 1 of the textured G-buffer variant.
    pub layout: wgpu::BindGroupLayout,
    /// Whether the layout binds the extension units ([`BINDINGS`]) or not
    /// ([`CORE_BINDINGS`]).
    pub units: bool,
    textures: HashMap<TextureHandle, (wgpu::Texture, wgpu::TextureView)>,
    samplers: HashMap<Sampler, wgpu::Sampler>,
    /// 1 × 1 white, for slots without a texture (sRGB and linear).
    white: Option<[(wgpu::Texture, wgpu::TextureView); 2]>,
    groups: Vec<(FrameMaps, wgpu::BindGroup)>,
    /// For each entry of [`ExtractedFrame::material_maps`], its index in `groups`.
    frame_groups: Vec<usize>,
    anisotropy: u16,
}

impl GpuMaterialMaps {
    /// The bind group layout, with the extension units where `units`; nothing is
    /// uploaded until a frame uses textures.
    pub fn new(gpu: &Gpu, units: bool) -> Self {
        let layout = if units { &BINDINGS } else { &CORE_BINDINGS }.layout(gpu);
        let anisotropic = gpu
            .adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::ANISOTROPIC_FILTERING);
        GpuMaterialMaps {
            layout,
            units,
            textures: HashMap::new(),
            samplers: HashMap::new(),
            white: None,
            groups: Vec::new(),
            frame_groups: Vec::new(),
            anisotropy: if anisotropic { 16 } else { 1 },
        }
    }

    /// The bind group of entry `index` of this frame's material maps.
    pub fn group(&self, index: u32) -> Option<&wgpu::BindGroup> {
        let g = *self.frame_groups.get(index as usize)?;
        self.groups.get(g).map(|(_, group)| group)
    }
}

fn upload(gpu: &Gpu, data: &TextureData) -> (wgpu::Texture, wgpu::TextureView) {
    let levels = mip_chain(data);
    let format = match data.color_space {
        ColorSpace::Srgb => wgpu::TextureFormat::Rgba8UnormSrgb,
        ColorSpace::Linear => wgpu::TextureFormat::Rgba8Unorm,
    };
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("material texture"),
        size: wgpu::Extent3d {
            width: data.width,
            height: data.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (level, (w, h, bytes)) in levels.iter().enumerate() {
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * w),
                rows_per_image: Some(*h),
            },
            wgpu::Extent3d {
                width: *w,
                height: *h,
                depth_or_array_layers: 1,
            },
        );
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    (texture, view)
}

/// Uploads the textures and builds the bind groups this frame's material maps need.
pub fn prepare_material_maps(
    gpu: Res<Gpu>,
    frame: Res<ExtractedFrame>,
    store: Res<Textures>,
    mut maps: ResMut<GpuMaterialMaps>,
    mut errors: ResMut<FrameErrors>,
) {
    let maps = &mut *maps;
    maps.frame_groups.clear();
    if frame.material_maps.is_empty() {
        return;
    }
    if maps.white.is_none() {
        maps.white = Some(
            [ColorSpace::Srgb, ColorSpace::Linear]
                .map(|cs| upload(&gpu, &TextureData::solid([255; 4], cs))),
        );
    }
    // Animated maps would add a group per frame: start over past a generous bound.
    if maps.groups.len() > 4096 {
        maps.groups.clear();
    }
    for entry in &frame.material_maps {
        if let Some(i) = maps.groups.iter().position(|(k, _)| k == entry) {
            maps.frame_groups.push(i);
            continue;
        }
        let m = &entry.maps;
        for slot in m.all_slots() {
            if !maps.textures.contains_key(&slot.texture)
                && let Some(data) = store.get(slot.texture)
            {
                let uploaded = upload(&gpu, data);
                maps.textures.insert(slot.texture, uploaded);
            }
            let anisotropy = maps.anisotropy;
            maps.samplers.entry(slot.sampler).or_insert_with(|| {
                let s = slot.sampler;
                let all_linear = s.mag == Filter::Linear
                    && s.min == Filter::Linear
                    && s.mipmap == Filter::Linear;
                gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("material sampler"),
                    address_mode_u: address(s.wrap_u),
                    address_mode_v: address(s.wrap_v),
                    mag_filter: filter(s.mag),
                    min_filter: filter(s.min),
                    mipmap_filter: mipmap_filter(s.mipmap),
                    anisotropy_clamp: if all_linear { anisotropy } else { 1 },
                    ..Default::default()
                })
            });
        }
        let default_sampler = maps
            .samplers
            .entry(Sampler::default())
            .or_insert_with(|| gpu.sampler("material sampler", wgpu::FilterMode::Nearest))
            .clone();
        let Some(white) = maps.white.as_ref() else {
            return;
        };
        // Colour slots (base colour, emissive) default to sRGB white, data slots and
        // unbound extension units to linear white; every default multiplies its factor
        // by 1.
        let srgb_slot = [true, false, false, false, true];
        let units = m.extensions.units().units;
        let defaults = srgb_slot.into_iter().chain([false; EXTENSION_UNITS]);
        let slots: Vec<Option<TextureSlot>> = m.slots().into_iter().chain(units).collect();
        let views: Vec<&wgpu::TextureView> = slots
            .iter()
            .zip(defaults)
            .map(|(slot, srgb)| {
                slot.and_then(|s| maps.textures.get(&s.texture))
                    .map_or(&white[usize::from(!srgb)].1, |(_, v)| v)
            })
            .collect();
        let samplers: Vec<&wgpu::Sampler> = slots
            .iter()
            .map(|slot| {
                slot.and_then(|s| maps.samplers.get(&s.sampler))
                    .unwrap_or(&default_sampler)
            })
            .collect();
        use wgpu::util::DeviceExt;
        let uniform = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("material maps"),
                contents: bytemuck::bytes_of(&GpuMaps::new(entry, maps.units, |h| {
                    maps.textures.contains_key(&h)
                })),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        // The binding order: the factors, the five slots' textures, their samplers, then
        // the extension units' textures and their samplers.
        let (core_views, unit_views) = views.split_at(5);
        let (core_samplers, unit_samplers) = samplers.split_at(5);
        let units = if maps.units { unit_views.len() } else { 0 };
        let resources = std::iter::once(uniform.as_entire_binding())
            .chain(
                core_views
                    .iter()
                    .copied()
                    .map(wgpu::BindingResource::TextureView),
            )
            .chain(
                core_samplers
                    .iter()
                    .copied()
                    .map(wgpu::BindingResource::Sampler),
            )
            .chain(
                unit_views[..units]
                    .iter()
                    .copied()
                    .map(wgpu::BindingResource::TextureView),
            )
            .chain(
                unit_samplers[..units]
                    .iter()
                    .copied()
                    .map(wgpu::BindingResource::Sampler),
            )
            .collect();
        let spec = if maps.units {
            &BINDINGS
        } else {
            &CORE_BINDINGS
        };
        let group = match spec.group(&gpu, &maps.layout, resources) {
            Ok(group) => group,
            Err(e) => {
                errors.0.push(e);
                return;
            }
        };
        maps.groups.push((entry.clone(), group));
        maps.frame_groups.push(maps.groups.len() - 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_maps_lay_out_as_the_shader_does() {
        #[rustfmt::skip]
        crate::assert_wgsl_twin!(GpuMaps, "material_maps.wgsl", &[group_def(1)], "Maps", [
            transforms, uv_sets, extra, params, transmission, attenuation, clearcoat, sheen,
            anisotropy, specular_tint, film, translucency, extension_transforms,
            extension_uv_sets, extension_units, extension_params,
        ]);
    }

    #[test]
    fn mips_average_in_linear_light() {
        // A black and a white texel: their linear mean 0.5 is sRGB code 188, not 128.
        let t = TextureData {
            width: 2,
            height: 1,
            rgba8: vec![0, 0, 0, 0, 255, 255, 255, 255],
            color_space: ColorSpace::Srgb,
        };
        let chain = mip_chain(&t);
        assert_eq!(chain.len(), 2);
        assert_eq!((chain[1].0, chain[1].1), (1, 1));
        assert_eq!(chain[1].2, vec![188, 188, 188, 128]);
        let linear = TextureData {
            color_space: ColorSpace::Linear,
            ..t
        };
        assert_eq!(mip_chain(&linear)[1].2, vec![128, 128, 128, 128]);
    }

    #[test]
    fn odd_sizes_reach_one_texel() {
        let t = TextureData {
            width: 5,
            height: 3,
            rgba8: vec![200; 5 * 3 * 4],
            color_space: ColorSpace::Linear,
        };
        let sizes: Vec<(u32, u32)> = mip_chain(&t).iter().map(|(w, h, _)| (*w, *h)).collect();
        assert_eq!(sizes, vec![(5, 3), (2, 1), (1, 1)]);
        assert!(
            mip_chain(&t)
                .iter()
                .all(|(w, h, d)| d.len() == (w * h * 4) as usize)
        );
    }
}

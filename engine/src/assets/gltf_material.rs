//! glTF materials and their textures → [`Material`] + [`MaterialMaps`].
//!
//! - Colour slots (base colour, emissive, spec/gloss diffuse and specular) are sRGB, data
//!   slots (metallic-roughness, normal, occlusion) linear.
//! - Images are decoded with `image` (PNG, JPEG, and WebP through `EXT_texture_webp`),
//!   and Basis Universal KTX2 images (`KHR_texture_basisu`) are transcoded
//!   ([`texture_io`]), from a buffer view, a data URI or a file next to the glTF. An
//!   extension's image that cannot be read falls back to the texture's core image with a
//!   warning ([`texture_image`]); one that cannot be read at all becomes a magenta
//!   checker with a warning.
//! - A texture larger than the budget (the smaller of [`Quality::max_texture_size`] and
//!   the device's limit) is downscaled with a warning.
//! - `KHR_materials_pbrSpecularGlossiness` textures are converted texel by texel to a
//!   base-colour and a metallic-roughness texture ([`crate::workflow`]).

use super::texture_io;
use crate::scene::extension_maps::{EXTENSION_TEXTURES, EXTENSION_UNITS};
use crate::scene::{
    Anisotropy, Clearcoat, ColorSpace, DiffuseTransmission, ExtensionMaps, Filter, Iridescence,
    Material, MaterialMaps, Sampler, Sheen, TextureData, TextureHandle, TextureSlot, Textures,
    Transmission, UvTransform, Wrap,
};
use crate::shading::brdf::f0_from_ior;
use crate::workflow;
use glam::{Vec2, Vec3, Vec4};
use std::collections::HashMap;
use std::path::Path;

/// Reads a file's images once per colour space and hands out texture handles.
pub(super) struct TextureLoader<'a> {
    pub base: &'a Path,
    pub buffers: &'a [gltf::buffer::Data],
    pub views: &'a [gltf::buffer::View<'a>],
    /// The file's images, for sources that extensions name.
    pub images: &'a [gltf::Image<'a>],
    /// The file's textures, for the texture infos that material extensions name.
    pub textures: &'a [gltf::Texture<'a>],
    pub max_size: u32,
    pub cache: HashMap<(usize, ColorSpace), TextureHandle>,
    pub warnings: Vec<String>,
}

impl TextureLoader<'_> {
    /// The decoded image of `texture` (RGBA8, within the budget), or the missing-texture
    /// checker with a warning.
    fn decode(&mut self, texture: &gltf::Texture, color_space: ColorSpace) -> TextureData {
        let (image, fallback) = match texture_image(texture, self.images) {
            Ok(images) => images,
            Err(e) => {
                self.warnings.push(format!(
                    "texture {}: {e}; drawn as a magenta checker",
                    texture.index()
                ));
                return TextureData::missing(color_space);
            }
        };
        match (self.decode_image(&image, color_space), fallback) {
            (Ok(data), _) => data,
            (Err(e), Some(fallback)) => {
                self.warnings.push(format!(
                    "texture {}: {e}; its fallback image {} is used",
                    texture.index(),
                    fallback.index()
                ));
                self.decode_image(&fallback, color_space)
                    .unwrap_or_else(|e| self.missing(e, color_space))
            }
            (Err(e), None) => self.missing(e, color_space),
        }
    }

    /// The missing-texture checker, with the warning `e`.
    fn missing(&mut self, e: String, color_space: ColorSpace) -> TextureData {
        self.warnings
            .push(format!("{e}; drawn as a magenta checker"));
        TextureData::missing(color_space)
    }

    /// The decoded `image` (RGBA8, within the budget), or an error naming it.
    fn decode_image(
        &mut self,
        image: &gltf::Image,
        color_space: ColorSpace,
    ) -> Result<TextureData, String> {
        let what = format!("image {}", image.index());
        let bytes: Result<Vec<u8>, String> = match image.source() {
            gltf::image::Source::View { view, .. } => self
                .views
                .get(view.index())
                .and_then(|v| super::gltf_buffers::view_bytes(v, self.buffers))
                .map(<[u8]>::to_vec)
                .ok_or(format!(
                    "{what}: buffer view {} is out of range",
                    view.index()
                )),
            gltf::image::Source::Uri { uri, .. } => {
                super::gltf_buffers::read_uri(self.base, uri, crate::limits::FileKind::Texture)
            }
        };
        bytes
            .and_then(|b| {
                texture_io::decode(&b, color_space, self.max_size, &mut self.warnings, &what)
            })
            .map_err(|e| format!("{what}: {e}"))
    }

    /// The handle of `texture` in `color_space`, decoding it on first use.
    fn handle(
        &mut self,
        store: &mut Textures,
        texture: &gltf::Texture,
        color_space: ColorSpace,
    ) -> Option<TextureHandle> {
        // Keyed by the texture: which of its images is read depends on its extensions.
        let key = (texture.index(), color_space);
        if let Some(h) = self.cache.get(&key) {
            return Some(*h);
        }
        let data = self.decode(texture, color_space);
        match store.add(data) {
            Ok(h) => {
                self.cache.insert(key, h);
                Some(h)
            }
            Err(e) => {
                self.warnings.push(format!("image {}: {e}", key.0));
                None
            }
        }
    }

    /// A slot for `texture` read with `tex_coord` and an optional transform.
    fn slot(
        &mut self,
        store: &mut Textures,
        texture: &gltf::Texture,
        tex_coord: u32,
        transform: Option<(UvTransform, Option<u32>)>,
        color_space: ColorSpace,
    ) -> Option<TextureSlot> {
        let handle = self.handle(store, texture, color_space)?;
        let (transform, set) = transform.unwrap_or((UvTransform::default(), None));
        let uv_set = set.unwrap_or(tex_coord);
        if uv_set > 1 {
            self.warnings.push(format!(
                "texture {}: coordinate set {uv_set} is not supported; set 0 is used",
                texture.index()
            ));
        }
        Some(TextureSlot {
            texture: handle,
            sampler: sampler(&texture.sampler()),
            uv_set: if uv_set <= 1 { uv_set } else { 0 },
            transform,
        })
    }

    /// The slot of a material extension's texture info `info` (its JSON: `index`,
    /// `texCoord` and `KHR_texture_transform`), or `None` with a warning when it names no
    /// texture of the file.
    fn extension_slot(
        &mut self,
        store: &mut Textures,
        info: &gltf::json::Value,
        color_space: ColorSpace,
        what: &str,
    ) -> Option<TextureSlot> {
        let index = info.get("index").and_then(gltf::json::Value::as_u64);
        let Some(texture) = index
            .and_then(|i| usize::try_from(i).ok())
            .and_then(|i| self.textures.get(i))
        else {
            self.warnings.push(format!(
                "{what}: its texture index ({}) names no texture of the file; the factor alone applies",
                info.get("index").map_or("missing".into(), ToString::to_string)
            ));
            return None;
        };
        let tex_coord = info
            .get("texCoord")
            .and_then(gltf::json::Value::as_u64)
            .map_or(0, |t| u32::try_from(t).unwrap_or(u32::MAX));
        let transform = json_transform(
            info.get("extensions")
                .and_then(|e| e.get("KHR_texture_transform")),
        );
        self.slot(store, &texture.clone(), tex_coord, transform, color_space)
    }
}

/// `KHR_texture_transform` from its JSON object: the transform and the coordinate set it
/// overrides, if any.
fn uv_transform(value: &gltf::json::Value) -> (UvTransform, Option<u32>) {
    let pair = |key: &str, default: Vec2| {
        value
            .get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| {
                Some(Vec2::new(
                    a.first()?.as_f64()? as f32,
                    a.get(1)?.as_f64()? as f32,
                ))
            })
            .filter(|v| v.is_finite())
            .unwrap_or(default)
    };
    let rotation = value
        .get("rotation")
        .and_then(|v| v.as_f64())
        .map(|r| r as f32)
        .filter(|r| r.is_finite())
        .unwrap_or(0.0);
    let set = value
        .get("texCoord")
        .and_then(|v| v.as_u64())
        .map(|v| v.min(u64::from(u32::MAX)) as u32);
    (
        UvTransform {
            offset: pair("offset", Vec2::ZERO),
            rotation_rad: rotation,
            scale: pair("scale", Vec2::ONE),
        },
        set,
    )
}

fn sampler(s: &gltf::texture::Sampler) -> Sampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |w| match w {
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::Repeat => Wrap::Repeat,
    };
    let (min, mipmap) = match s.min_filter() {
        Some(MinFilter::Nearest) | Some(MinFilter::NearestMipmapNearest) => {
            (Filter::Nearest, Filter::Nearest)
        }
        Some(MinFilter::Linear) | Some(MinFilter::LinearMipmapNearest) => {
            (Filter::Linear, Filter::Nearest)
        }
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Filter::Linear),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, Filter::Linear),
    };
    Sampler {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        mag: match s.mag_filter() {
            Some(MagFilter::Nearest) => Filter::Nearest,
            _ => Filter::Linear,
        },
        min,
        mipmap,
    }
}

/// An `Info`'s `KHR_texture_transform` (parsed by the gltf crate) and the coordinate set
/// it overrides.
fn info_transform(info: &gltf::texture::Info) -> Option<(UvTransform, Option<u32>)> {
    info.texture_transform().map(|t| {
        let finite2 = |v: [f32; 2], d: Vec2| {
            let v = Vec2::from(v);
            if v.is_finite() { v } else { d }
        };
        let rotation = t.rotation();
        (
            UvTransform {
                offset: finite2(t.offset(), Vec2::ZERO),
                rotation_rad: if rotation.is_finite() { rotation } else { 0.0 },
                scale: finite2(t.scale(), Vec2::ONE),
            },
            t.tex_coord(),
        )
    })
}

/// The `KHR_texture_transform` JSON of a normal or occlusion texture, which the gltf
/// crate leaves unparsed.
fn json_transform(value: Option<&gltf::json::Value>) -> Option<(UvTransform, Option<u32>)> {
    value.map(uv_transform)
}

/// The material as the validator and converter read it: factors and the decoded
/// textures of its own workflow (texture transforms and UV sets are not applied).
pub(super) fn material_input(
    m: &gltf::Material,
    loader: &mut TextureLoader,
) -> crate::validate::MaterialInput {
    use crate::validate::{ColorInput, MaterialInput, ScalarInput};
    match m.pbr_specular_glossiness() {
        Some(sg) => {
            let diffuse = sg
                .diffuse_texture()
                .map(|i| loader.decode(&i.texture(), ColorSpace::Srgb));
            // Specular rgb is sRGB, glossiness (alpha) linear: one decode serves both.
            let spec = sg
                .specular_glossiness_texture()
                .map(|i| loader.decode(&i.texture(), ColorSpace::Srgb));
            MaterialInput::SpecGloss {
                diffuse: ColorInput {
                    texture: diffuse,
                    factor: Vec4::from(sg.diffuse_factor()).truncate(),
                },
                specular: ColorInput {
                    texture: spec.clone(),
                    factor: Vec3::from(sg.specular_factor()),
                },
                glossiness: ScalarInput {
                    texture: spec,
                    channel: 3,
                    factor: sg.glossiness_factor(),
                },
            }
        }
        None => {
            let pbr = m.pbr_metallic_roughness();
            let base = pbr
                .base_color_texture()
                .map(|i| loader.decode(&i.texture(), ColorSpace::Srgb));
            let mr = pbr
                .metallic_roughness_texture()
                .map(|i| loader.decode(&i.texture(), ColorSpace::Linear));
            MaterialInput::MetalRough {
                base_color: ColorInput {
                    texture: base,
                    factor: Vec4::from(pbr.base_color_factor()).truncate(),
                },
                metallic: ScalarInput {
                    texture: mr.clone(),
                    channel: 2,
                    factor: pbr.metallic_factor(),
                },
                roughness: ScalarInput {
                    texture: mr,
                    channel: 1,
                    factor: pbr.roughness_factor(),
                },
            }
        }
    }
}

/// The material of a primitive and its maps (`None` when it has no texture and the
/// mesh no vertex colour), or `None` when the primitive is not drawn (alpha mode `MASK`
/// with a constant alpha below the cutoff). Alpha mode `BLEND` sets [`Material::blend`].
pub(super) fn material(
    m: &gltf::Material,
    what: &str,
    has_vertex_colors: bool,
    loader: &mut TextureLoader,
    store: &mut Textures,
) -> Option<(Material, Option<MaterialMaps>)> {
    let pbr = m.pbr_metallic_roughness();
    let mut maps = MaterialMaps::default();
    let (base, metallic, roughness) = match m.pbr_specular_glossiness() {
        Some(sg) => {
            let diffuse = Vec4::from(sg.diffuse_factor());
            let converted = workflow::to_metal_rough(workflow::SpecGloss {
                diffuse: diffuse.truncate(),
                specular: Vec3::from(sg.specular_factor()),
                glossiness: sg.glossiness_factor(),
            });
            if sg.diffuse_texture().is_some() || sg.specular_glossiness_texture().is_some() {
                spec_gloss_textures(&sg, loader, store, &mut maps);
                // The converted textures carry the colour; the factors are folded in.
                (Vec4::new(1.0, 1.0, 1.0, diffuse.w), 1.0, 1.0)
            } else {
                (
                    converted.base_color.extend(diffuse.w),
                    converted.metallic,
                    converted.roughness,
                )
            }
        }
        None => {
            maps.base_color = pbr.base_color_texture().and_then(|i| {
                loader.slot(
                    store,
                    &i.texture(),
                    i.tex_coord(),
                    info_transform(&i),
                    ColorSpace::Srgb,
                )
            });
            maps.metallic_roughness = pbr.metallic_roughness_texture().and_then(|i| {
                loader.slot(
                    store,
                    &i.texture(),
                    i.tex_coord(),
                    info_transform(&i),
                    ColorSpace::Linear,
                )
            });
            (
                Vec4::from(pbr.base_color_factor()),
                pbr.metallic_factor(),
                pbr.roughness_factor(),
            )
        }
    };
    if let Some(n) = m.normal_texture() {
        maps.normal = loader.slot(
            store,
            &n.texture(),
            n.tex_coord(),
            json_transform(n.extension_value("KHR_texture_transform")),
            ColorSpace::Linear,
        );
        maps.normal_scale = if n.scale().is_finite() {
            n.scale()
        } else {
            1.0
        };
    }
    if let Some(o) = m.occlusion_texture() {
        maps.occlusion = loader.slot(
            store,
            &o.texture(),
            o.tex_coord(),
            json_transform(o.extension_value("KHR_texture_transform")),
            ColorSpace::Linear,
        );
        maps.occlusion_strength = if o.strength().is_finite() {
            o.strength().clamp(0.0, 1.0)
        } else {
            1.0
        };
    }
    maps.emissive = m.emissive_texture().and_then(|i| {
        loader.slot(
            store,
            &i.texture(),
            i.tex_coord(),
            info_transform(&i),
            ColorSpace::Srgb,
        )
    });

    let alpha = if base.w.is_nan() { 1.0 } else { base.w };
    let alpha_textured = maps.base_color.is_some() || has_vertex_colors;
    let mut blend = false;
    match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => {}
        gltf::material::AlphaMode::Mask => {
            let cutoff = m.alpha_cutoff().unwrap_or(0.5);
            if alpha_textured {
                maps.alpha_cutoff = Some(if cutoff.is_finite() { cutoff } else { 0.5 });
            } else if alpha < cutoff {
                loader.warnings.push(format!(
                    "{what}: alpha {alpha} is below the mask cutoff: not drawn"
                ));
                return None;
            }
        }
        // Constant full coverage is opaque: it keeps its depth and casts its shadow.
        gltf::material::AlphaMode::Blend => blend = alpha < 1.0 || alpha_textured,
    }
    let strength = m.emissive_strength().unwrap_or(1.0);
    let (specular_level, specular_tint) = specular_level(m);
    let material = Material {
        base_color: base,
        metallic,
        perceptual_roughness: roughness,
        specular_level,
        // glTF emissive is a colour factor × strength in nits (cd/m²) per
        // KHR_materials_emissive_strength's reference of 1 = 1 nit.
        emissive: Vec3::from(m.emissive_factor()) * strength,
        occlusion: 1.0,
        double_sided: m.double_sided(),
        blend,
        transmission: transmission(m),
        unlit: m.unlit(),
        clearcoat: clearcoat(m, what, &mut loader.warnings),
        sheen: sheen(m, what, &mut loader.warnings),
        anisotropy: anisotropy(m, what, &mut loader.warnings),
        specular_tint,
        iridescence: iridescence(m, what, &mut loader.warnings),
        diffuse_transmission: diffuse_transmission(m, what, &mut loader.warnings),
    };
    maps.extensions = extension_maps(m, &material, what, loader, store);
    if specular_tint != Vec3::ONE && material.tint().is_none() && material.metallic < 1.0 {
        loader.warnings.push(format!(
            "{what}: the tinted KHR_materials_specular colour of an unlit material is drawn untinted"
        ));
    }
    let textured =
        maps.slots().iter().any(Option::is_some) || maps.extensions.any() || has_vertex_colors;
    Some((material, textured.then_some(maps)))
}

/// Converts spec/gloss textures (and their factors) texel by texel into a base-colour and
/// a metallic-roughness texture, at the diffuse texture's size (or the specular one's).
fn spec_gloss_textures(
    sg: &gltf::material::PbrSpecularGlossiness,
    loader: &mut TextureLoader,
    store: &mut Textures,
    maps: &mut MaterialMaps,
) {
    let diffuse = sg
        .diffuse_texture()
        .map(|i| (loader.decode(&i.texture(), ColorSpace::Srgb), i));
    let specular = sg
        .specular_glossiness_texture()
        .map(|i| (loader.decode(&i.texture(), ColorSpace::Srgb), i));
    let Some((w, h)) = diffuse
        .as_ref()
        .or(specular.as_ref())
        .map(|(t, _)| (t.width, t.height))
    else {
        return;
    };
    let diffuse_factor = Vec4::from(sg.diffuse_factor());
    let specular_factor = Vec3::from(sg.specular_factor());
    let gloss_factor = sg.glossiness_factor();
    // Texel (x, y) of `t` at the converted texture's (x, y), nearest.
    let texel = |t: &TextureData, x: u32, y: u32| {
        let tx = (u64::from(x) * u64::from(t.width) / u64::from(w)) as usize;
        let ty = (u64::from(y) * u64::from(t.height) / u64::from(h)) as usize;
        let i = (ty * t.width as usize + tx) * 4;
        t.rgba8
            .get(i..i + 4)
            .map_or([255; 4], |p| [p[0], p[1], p[2], p[3]])
    };
    let srgb = |c: u8| crate::shading::color::srgb_decode(f32::from(c) / 255.0);
    let mut base = Vec::with_capacity((w * h * 4) as usize);
    let mut mr = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let d = diffuse.as_ref().map_or([255; 4], |(t, _)| texel(t, x, y));
            let s = specular.as_ref().map_or([255; 4], |(t, _)| texel(t, x, y));
            let converted = workflow::to_metal_rough(workflow::SpecGloss {
                diffuse: Vec3::new(srgb(d[0]), srgb(d[1]), srgb(d[2])) * diffuse_factor.truncate(),
                specular: Vec3::new(srgb(s[0]), srgb(s[1]), srgb(s[2])) * specular_factor,
                glossiness: f32::from(s[3]) / 255.0 * gloss_factor,
            });
            let enc = |v: f32| (crate::shading::color::srgb_encode(v) * 255.0).round() as u8;
            let c = converted.base_color;
            base.extend([enc(c.x), enc(c.y), enc(c.z), d[3]]);
            let unorm = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
            mr.extend([
                0,
                unorm(converted.roughness),
                unorm(converted.metallic),
                255,
            ]);
        }
    }
    let set = diffuse
        .as_ref()
        .or(specular.as_ref())
        .map_or(0, |(_, i)| i.tex_coord().min(1));
    let transform = diffuse
        .as_ref()
        .or(specular.as_ref())
        .and_then(|(_, i)| info_transform(i).map(|(t, _)| t))
        .unwrap_or_default();
    let sampler = diffuse
        .as_ref()
        .or(specular.as_ref())
        .map_or(Sampler::default(), |(_, i)| sampler(&i.texture().sampler()));
    let add = |store: &mut Textures, rgba8, color_space| {
        store
            .add(TextureData {
                width: w,
                height: h,
                rgba8,
                color_space,
            })
            .ok()
            .map(|texture| TextureSlot {
                texture,
                sampler,
                uv_set: set,
                transform,
            })
    };
    maps.base_color = add(store, base, ColorSpace::Srgb);
    maps.metallic_roughness = add(store, mr, ColorSpace::Linear);
}

/// The image a texture is read from, and the one to fall back on if it cannot be
/// decoded: the `EXT_texture_webp` or `KHR_texture_basisu` (KTX2) source where the
/// texture has one (Lumen decodes WebP and transcodes Basis Universal), with the core
/// `source`, if any, as the fallback; else the core `source`.
fn texture_image<'a>(
    texture: &gltf::Texture<'a>,
    images: &[gltf::Image<'a>],
) -> Result<(gltf::Image<'a>, Option<gltf::Image<'a>>), String> {
    let document_image = |name: &str| {
        texture
            .extension_value(name)
            .and_then(|e| e.get("source"))
            .and_then(|s| s.as_u64())
    };
    for name in ["EXT_texture_webp", "KHR_texture_basisu"] {
        if let Some(index) = document_image(name) {
            let image = usize::try_from(index)
                .ok()
                .and_then(|i| images.get(i))
                .cloned()
                .ok_or(format!("{name} source {index} does not exist"))?;
            return Ok((image, texture.source()));
        }
    }
    texture
        .source()
        .map(|image| (image, None))
        .ok_or("it has no image".into())
}

/// The textures of the material's extension layers ([`ExtensionMaps`]), read only for
/// the layers `material` has (a texture scales a factor, so a layer without its factor
/// needs none; the specular textures are read wherever `KHR_materials_specular` is).
/// Colour textures (sheen, diffuse transmission, specular colour) and those read from
/// alpha are sRGB (alpha stays linear), the rest linear; the coat normal map's `scale`
/// comes with it. Specular textures are read where the surface is opaque and lit
/// ([`Material::relit_tint`]); elsewhere a warning says they are not drawn.
/// Past [`EXTENSION_UNITS`] distinct textures the rest are dropped with a warning, and
/// their factors apply.
fn extension_maps(
    m: &gltf::Material,
    material: &Material,
    what: &str,
    loader: &mut TextureLoader,
    store: &mut Textures,
) -> ExtensionMaps {
    let mut out = ExtensionMaps::default();
    let mut read = |extension: &str, key: &str, color_space: ColorSpace| {
        let info = m.extension_value(extension)?.get(key)?;
        loader.extension_slot(
            store,
            info,
            color_space,
            &format!("{what}: {extension}'s {key}"),
        )
    };
    let (linear, srgb) = (ColorSpace::Linear, ColorSpace::Srgb);
    if material.transmission.is_some() {
        out.transmission = read("KHR_materials_transmission", "transmissionTexture", linear);
        out.thickness = read("KHR_materials_volume", "thicknessTexture", linear);
    }
    if material.clearcoat.is_some() {
        out.clearcoat = read("KHR_materials_clearcoat", "clearcoatTexture", linear);
        out.clearcoat_roughness = read(
            "KHR_materials_clearcoat",
            "clearcoatRoughnessTexture",
            linear,
        );
        out.clearcoat_normal = read("KHR_materials_clearcoat", "clearcoatNormalTexture", linear);
    }
    // Alpha is linear in every texture, so the properties read from alpha load as sRGB:
    // an image that packs a colour in rgb and its companion in alpha (as glTF's sheen,
    // diffuse transmission and specular textures often do) is then one unit, not two.
    if material.sheen.is_some() {
        out.sheen_color = read("KHR_materials_sheen", "sheenColorTexture", srgb);
        out.sheen_roughness = read("KHR_materials_sheen", "sheenRoughnessTexture", srgb);
    }
    if material.anisotropy.is_some() {
        out.anisotropy = read("KHR_materials_anisotropy", "anisotropyTexture", linear);
    }
    if material.iridescence.is_some() {
        out.iridescence = read("KHR_materials_iridescence", "iridescenceTexture", linear);
        out.iridescence_thickness = read(
            "KHR_materials_iridescence",
            "iridescenceThicknessTexture",
            linear,
        );
    }
    if material.diffuse_transmission.is_some() {
        let name = "KHR_materials_diffuse_transmission";
        out.diffuse_transmission = read(name, "diffuseTransmissionTexture", srgb);
        out.diffuse_transmission_color = read(name, "diffuseTransmissionColorTexture", srgb);
    }
    if material.relit_tint(true).is_some() {
        out.specular = read("KHR_materials_specular", "specularTexture", srgb);
        out.specular_color = read("KHR_materials_specular", "specularColorTexture", srgb);
    } else if let Some(ext) = m.extension_value("KHR_materials_specular")
        && (ext.get("specularTexture").is_some() || ext.get("specularColorTexture").is_some())
    {
        loader.warnings.push(format!(
            "{what}: KHR_materials_specular's textures are not drawn on an unlit material"
        ));
    }
    if out.clearcoat_normal.is_some()
        && let Some(scale) = m
            .extension_value("KHR_materials_clearcoat")
            .and_then(|e| e.get("clearcoatNormalTexture"))
            .and_then(|info| info.get("scale"))
            .and_then(gltf::json::Value::as_f64)
    {
        out.clearcoat_normal_scale = scale as f32;
    }
    if out.iridescence_thickness.is_some() {
        let ext = m.extension_value("KHR_materials_iridescence");
        match ext.map(|e| {
            extension_number(
                e,
                (
                    "KHR_materials_iridescence",
                    "iridescenceThicknessMinimum",
                    100.0,
                ),
                what,
                "the default 100 nm applies",
            )
        }) {
            Some(Ok(min_nm)) => out.iridescence_thickness_min_nm = min_nm,
            Some(Err(e)) => loader.warnings.push(e),
            None => {}
        }
    }
    let dropped = out.units().dropped;
    if !dropped.is_empty() {
        let names: Vec<&str> = dropped.iter().map(|&k| EXTENSION_TEXTURES[k].1).collect();
        loader.warnings.push(format!(
            "{what}: more than {EXTENSION_UNITS} distinct extension textures; {} not sampled, the factors apply",
            names.join(", ")
        ));
    }
    out.packable()
}

/// `KHR_materials_transmission` with `KHR_materials_volume`, `KHR_materials_ior` and
/// `KHR_materials_dispersion`:
/// the factors (their textures are read by [`extension_maps`]). No transmission
/// extension, or a factor of 0: opaque.
fn transmission(m: &gltf::Material) -> Option<Transmission> {
    let t = m.transmission()?;
    let volume = m.volume();
    let factor = t.transmission_factor();
    (factor > 0.0).then(|| Transmission {
        factor,
        ior: m.ior().unwrap_or(1.5),
        thickness_m: volume.as_ref().map_or(0.0, |v| v.thickness_factor()),
        attenuation_color: volume
            .as_ref()
            .map_or(Vec3::ONE, |v| Vec3::from(v.attenuation_color())),
        attenuation_distance_m: volume
            .as_ref()
            .map_or(f32::INFINITY, |v| v.attenuation_distance()),
        dispersion: m
            .extension_value("KHR_materials_dispersion")
            .and_then(|d| d.get("dispersion"))
            .and_then(|d| d.as_f64())
            .map_or(0.0, |d| d as f32),
    })
}

/// `KHR_materials_clearcoat`'s factors: `clearcoatFactor` (default 0: no coat) and
/// `clearcoatRoughnessFactor` (default 0); its textures are read by [`extension_maps`].
/// A factor that is not a number is refused with a warning (no coat).
fn clearcoat(m: &gltf::Material, what: &str, warnings: &mut Vec<String>) -> Option<Clearcoat> {
    let name = "KHR_materials_clearcoat";
    let ext = m.extension_value(name)?;
    let number = |key| extension_number(ext, (name, key, 0.0), what, "no coat");
    match (
        number("clearcoatFactor"),
        number("clearcoatRoughnessFactor"),
    ) {
        (Ok(factor), Ok(perceptual_roughness)) => (factor > 0.0).then_some(Clearcoat {
            factor,
            perceptual_roughness,
        }),
        (Err(e), _) | (_, Err(e)) => {
            warnings.push(e);
            None
        }
    }
}

/// `KHR_materials_sheen`'s factors: `sheenColorFactor` (default black: no sheen) and
/// `sheenRoughnessFactor` (default 0); its textures are read by [`extension_maps`]. A
/// factor of the wrong shape is refused with a warning (no sheen).
fn sheen(m: &gltf::Material, what: &str, warnings: &mut Vec<String>) -> Option<Sheen> {
    let ext = m.extension_value("KHR_materials_sheen")?;
    let color = match ext.get("sheenColorFactor") {
        None => Some(Vec3::ZERO),
        Some(v) => three_numbers(v),
    };
    let roughness = match ext.get("sheenRoughnessFactor") {
        None => Some(0.0),
        Some(v) => v.as_f64().map(|x| x as f32),
    };
    match (color, roughness) {
        (Some(color), Some(perceptual_roughness)) => (color.max_element() > 0.0).then_some(Sheen {
            color,
            perceptual_roughness,
        }),
        _ => {
            warnings.push(format!(
                "{what}: KHR_materials_sheen's factors are not a colour of three numbers and a number ({ext}); no sheen"
            ));
            None
        }
    }
}

/// `KHR_materials_anisotropy`'s factors: `anisotropyStrength` (default 0: isotropic) and
/// `anisotropyRotation` (radians from the tangent towards the bitangent, default 0); its
/// `anisotropyTexture` (direction and strength per texel) is read by [`extension_maps`].
/// A factor that is not a number is refused with a warning (isotropic).
fn anisotropy(m: &gltf::Material, what: &str, warnings: &mut Vec<String>) -> Option<Anisotropy> {
    let name = "KHR_materials_anisotropy";
    let ext = m.extension_value(name)?;
    let number = |key| extension_number(ext, (name, key, 0.0), what, "isotropic");
    match (number("anisotropyStrength"), number("anisotropyRotation")) {
        (Ok(strength), Ok(rotation_rad)) => (strength != 0.0).then_some(Anisotropy {
            strength,
            rotation_rad,
        }),
        (Err(e), _) | (_, Err(e)) => {
            warnings.push(e);
            None
        }
    }
}

/// `KHR_materials_iridescence`'s factors: `iridescenceFactor` (default 0: no film),
/// `iridescenceIor` (default 1.3) and `iridescenceThicknessMaximum` (nm, default 400),
/// the film's thickness where there is no thickness texture; its textures and
/// `iridescenceThicknessMinimum` are read by [`extension_maps`]. A factor that is not a
/// number is refused with a warning (no film).
fn iridescence(m: &gltf::Material, what: &str, warnings: &mut Vec<String>) -> Option<Iridescence> {
    let name = "KHR_materials_iridescence";
    let ext = m.extension_value(name)?;
    let number = |key, default| extension_number(ext, (name, key, default), what, "no film");
    match (
        number("iridescenceFactor", 0.0),
        number("iridescenceIor", 1.3),
        number("iridescenceThicknessMaximum", 400.0),
    ) {
        (Ok(factor), Ok(ior), Ok(thickness_nm)) => (factor > 0.0).then_some(Iridescence {
            factor,
            ior,
            thickness_nm,
        }),
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => {
            warnings.push(e);
            None
        }
    }
}

/// `KHR_materials_diffuse_transmission`'s factors: `diffuseTransmissionFactor` (default
/// 0: none) and `diffuseTransmissionColorFactor` (default white); its textures are read
/// by [`extension_maps`]. A factor of the wrong shape is refused with a warning (none). With `KHR_materials_transmission` the two share
/// the diffuse lobe, as the extension specifies ([`Material::translucent`]).
fn diffuse_transmission(
    m: &gltf::Material,
    what: &str,
    warnings: &mut Vec<String>,
) -> Option<DiffuseTransmission> {
    let name = "KHR_materials_diffuse_transmission";
    let ext = m.extension_value(name)?;
    let factor = extension_number(ext, (name, "diffuseTransmissionFactor", 0.0), what, "none");
    let color = match ext.get("diffuseTransmissionColorFactor") {
        None => Ok(Vec3::ONE),
        Some(v) => three_numbers(v).ok_or_else(|| {
            format!(
                "{what}: {name}'s diffuseTransmissionColorFactor is not three numbers ({v}); none"
            )
        }),
    };
    match (factor, color) {
        (Ok(factor), Ok(color)) => (factor > 0.0).then_some(DiffuseTransmission { factor, color }),
        (Err(e), _) | (_, Err(e)) => {
            warnings.push(e);
            None
        }
    }
}

/// A JSON array of exactly three numbers, as a colour.
fn three_numbers(v: &gltf::json::Value) -> Option<Vec3> {
    let a = v.as_array().filter(|a| a.len() == 3)?;
    let c: Vec<f32> = a
        .iter()
        .filter_map(|x| x.as_f64())
        .map(|x| x as f32)
        .collect();
    (c.len() == 3).then(|| Vec3::new(c[0], c[1], c[2]))
}

/// The number `key` of the extension object `ext` (`(extension name, key, default)`),
/// the default where it is absent; otherwise an error naming the material `what`, the
/// key and the `consequence`.
fn extension_number(
    ext: &gltf::json::Value,
    (name, key, default): (&str, &str, f32),
    what: &str,
    consequence: &str,
) -> Result<f32, String> {
    match ext.get(key) {
        None => Ok(default),
        Some(v) => v
            .as_f64()
            .map(|x| x as f32)
            .ok_or_else(|| format!("{what}: {name}'s {key} is not a number ({v}); {consequence}")),
    }
}

/// Dielectric F0 as Lumen's specular level and tint, `(level, tint)`, so that
/// F0 = 0.08 × level × tint ([`crate::shading::brdf::tinted_f0`]): `KHR_materials_ior` gives
/// F0 = ((ior − 1)/(ior + 1))², `KHR_materials_specular` scales it by its factor and its
/// colour. The level takes the colour's largest channel (clamped to 0..1), the tint the
/// colour divided by it (white where the colour is grey or black).
fn specular_level(m: &gltf::Material) -> (f32, Vec3) {
    let mut f0 = f0_from_ior(m.ior().unwrap_or(1.5));
    let mut tint = Vec3::ONE;
    if let Some(spec) = m.specular() {
        let colour = Vec3::from(spec.specular_color_factor());
        let largest = colour.max_element();
        if largest > 0.0 && largest.is_finite() && colour.min_element() < largest - 1e-3 {
            tint = (colour / largest).max(Vec3::ZERO);
        }
        f0 *= spec.specular_factor() * largest;
    }
    let level = f0 / 0.08;
    let level = if level.is_nan() {
        0.5
    } else {
        level.clamp(0.0, 1.0)
    };
    (level, tint)
}

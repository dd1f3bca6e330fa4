//! Material maps for the path tracer: the same `MaterialMaps` the G-buffer's textured
//! variant samples, read on the CPU with bilinear filtering (no mip maps: the reference
//! supersamples every pixel), the samplers' wrap modes and `KHR_texture_transform`.

use crate::scene::extension_maps::EXTENSION_PROPERTIES;
use crate::scene::texture::normal_from_map;
use crate::scene::{ColorSpace, Filter, MaterialMaps, TextureData, TextureSlot, Textures, Wrap};
use crate::shading::color::srgb_decode;
use glam::{Vec2, Vec3, Vec4};
use std::sync::Arc;

/// One slot ready to sample.
#[derive(Clone, Debug)]
pub struct TraceSlot {
    texture: Arc<TextureData>,
    slot: TextureSlot,
    rows: [Vec3; 2],
}

/// A `MaterialMaps` with its textures.
#[derive(Clone, Debug)]
pub struct TraceMaps {
    /// Base colour, metallic-roughness, normal, occlusion, emissive.
    pub slots: [Option<TraceSlot>; 5],
    /// Normal map scale.
    pub normal_scale: f32,
    /// Alpha cutoff of a masked material.
    pub alpha_cutoff: Option<f32>,
    /// The extensions' textures, in [`crate::scene::ExtensionMaps::slots`] order.
    pub extensions: [Option<TraceSlot>; EXTENSION_PROPERTIES],
    /// The film's thickness (nm) where its thickness texture reads 0.
    pub thickness_min_nm: f32,
    /// The scale of the coat normal map's x and y.
    pub coat_normal_scale: f32,
}

fn wrap(t: f32, mode: Wrap) -> f32 {
    match mode {
        Wrap::Repeat => t - t.floor(),
        Wrap::ClampToEdge => t.clamp(0.0, 1.0),
        Wrap::MirroredRepeat => {
            let m = t.rem_euclid(2.0);
            if m > 1.0 { 2.0 - m } else { m }
        }
    }
}

impl TraceSlot {
    fn new(slot: TextureSlot, textures: &Textures) -> Option<TraceSlot> {
        let texture = textures.get(slot.texture)?.clone();
        let m = slot.transform.matrix();
        let m = if m.is_finite() {
            m
        } else {
            glam::Mat3::IDENTITY
        };
        Some(TraceSlot {
            texture,
            slot,
            rows: [
                Vec3::new(m.x_axis.x, m.y_axis.x, m.z_axis.x),
                Vec3::new(m.x_axis.y, m.y_axis.y, m.z_axis.y),
            ],
        })
    }

    /// The texture.
    pub fn texture(&self) -> &TextureData {
        &self.texture
    }

    /// The slot: sampler, texture coordinate set and transform.
    pub fn slot(&self) -> &TextureSlot {
        &self.slot
    }

    /// The first two rows of the texture-coordinate transform (`KHR_texture_transform`,
    /// made the identity where it is not finite): `u' = rows[0]·(u, v, 1)`, likewise v.
    pub fn rows(&self) -> [Vec3; 2] {
        self.rows
    }

    fn texel(&self, x: i64, y: i64) -> Vec4 {
        let t = &self.texture;
        let (w, h) = (i64::from(t.width), i64::from(t.height));
        let i = ((y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) * 4) as usize;
        let p = t.rgba8.get(i..i + 4).unwrap_or(&[255; 4]);
        let decode = |c: u8| {
            let v = f32::from(c) / 255.0;
            if t.color_space == ColorSpace::Srgb {
                srgb_decode(v)
            } else {
                v
            }
        };
        Vec4::new(
            decode(p[0]),
            decode(p[1]),
            decode(p[2]),
            f32::from(p[3]) / 255.0,
        )
    }

    /// The linear value at texture coordinates `uv` (set 0) / `uv1` (set 1).
    pub fn sample(&self, uv0: Vec2, uv1: Vec2) -> Vec4 {
        let uv = if self.slot.uv_set == 1 { uv1 } else { uv0 };
        let p = uv.extend(1.0);
        let (u, v) = (self.rows[0].dot(p), self.rows[1].dot(p));
        let t = &self.texture;
        let (u, v) = (
            wrap(u, self.slot.sampler.wrap_u),
            wrap(v, self.slot.sampler.wrap_v),
        );
        let (x, y) = (u * t.width as f32 - 0.5, v * t.height as f32 - 0.5);
        if self.slot.sampler.mag == Filter::Nearest {
            return self.texel((x + 0.5).floor() as i64, (y + 0.5).floor() as i64);
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let wrap_index = |i: i64, n: u32, mode: Wrap| match mode {
            Wrap::Repeat => i.rem_euclid(i64::from(n)),
            _ => i.clamp(0, i64::from(n) - 1),
        };
        let xs = [x0, x0 + 1].map(|i| wrap_index(i, t.width, self.slot.sampler.wrap_u));
        let ys = [y0, y0 + 1].map(|i| wrap_index(i, t.height, self.slot.sampler.wrap_v));
        let top = self.texel(xs[0], ys[0]).lerp(self.texel(xs[1], ys[0]), fx);
        let bottom = self.texel(xs[0], ys[1]).lerp(self.texel(xs[1], ys[1]), fx);
        top.lerp(bottom, fy)
    }
}

impl TraceMaps {
    /// The maps with their textures from `textures` (a missing texture drops its slot).
    pub fn new(maps: &MaterialMaps, textures: &Textures) -> TraceMaps {
        TraceMaps {
            slots: maps
                .slots()
                .map(|s| s.and_then(|s| TraceSlot::new(s, textures))),
            normal_scale: if maps.normal_scale.is_finite() {
                maps.normal_scale
            } else {
                1.0
            },
            alpha_cutoff: maps.alpha_cutoff,
            // What the GPU binds: the properties past its last unit keep their factors.
            extensions: maps
                .extensions
                .packable()
                .slots()
                .map(|s| s.and_then(|s| TraceSlot::new(s, textures))),
            thickness_min_nm: maps.extensions.thickness_min_nm(),
            coat_normal_scale: maps.extensions.coat_normal_scale(),
        }
    }

    /// The coat's normal at the coordinates: the interpolated normal `normal` bent by
    /// the coat normal map where there is one (`fs_coat` in `layers.wgsl`).
    pub fn coat_normal(&self, normal: Vec3, tangent: Vec4, uv0: Vec2, uv1: Vec2) -> Vec3 {
        self.extension(13, uv0, uv1).map_or(normal, |texel| {
            normal_from_map(normal, tangent, texel.truncate(), self.coat_normal_scale)
        })
    }

    /// Extension property `k`'s texel at the coordinates, if it is textured.
    pub fn extension(&self, k: usize, uv0: Vec2, uv1: Vec2) -> Option<Vec4> {
        self.extensions[k].as_ref().map(|s| s.sample(uv0, uv1))
    }

    /// Slot `k` at the coordinates, or white.
    pub fn sample(&self, k: usize, uv0: Vec2, uv1: Vec2) -> Vec4 {
        self.slots[k]
            .as_ref()
            .map_or(Vec4::ONE, |s| s.sample(uv0, uv1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Sampler, TextureHandle, UvTransform};

    fn slot(sampler: Sampler) -> (Textures, TextureSlot) {
        let mut textures = Textures::default();
        let handle = textures
            .add(TextureData {
                width: 2,
                height: 1,
                rgba8: vec![0, 0, 0, 255, 255, 255, 255, 255],
                color_space: ColorSpace::Linear,
            })
            .unwrap_or(TextureHandle(0));
        (
            textures,
            TextureSlot {
                texture: handle,
                sampler,
                uv_set: 0,
                transform: UvTransform::default(),
            },
        )
    }

    #[test]
    fn bilinear_nearest_and_wrap() {
        let (textures, s) = slot(Sampler::default());
        let t = TraceSlot::new(s, &textures).expect("slot");
        // Texel centres at u = 0.25 (black) and 0.75 (white); halfway is grey.
        assert!((t.sample(Vec2::new(0.5, 0.5), Vec2::ZERO).x - 0.5).abs() < 1e-6);
        assert!(t.sample(Vec2::new(0.25, 0.5), Vec2::ZERO).x.abs() < 1e-6);
        // Repeat: u = 1.25 is u = 0.25.
        assert!(t.sample(Vec2::new(1.25, 0.5), Vec2::ZERO).x.abs() < 1e-6);
        let (textures, s) = slot(Sampler {
            mag: Filter::Nearest,
            wrap_u: Wrap::ClampToEdge,
            ..Sampler::default()
        });
        let t = TraceSlot::new(s, &textures).expect("slot");
        assert_eq!(t.sample(Vec2::new(0.6, 0.5), Vec2::ZERO).x, 1.0);
        assert_eq!(t.sample(Vec2::new(7.0, 0.5), Vec2::ZERO).x, 1.0);
        assert_eq!(t.sample(Vec2::new(-7.0, 0.5), Vec2::ZERO).x, 0.0);
    }
}

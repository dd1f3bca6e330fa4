//! Textures: CPU data shared through handles, like meshes, and how a material samples
//! one ([`TextureSlot`]). The [`crate::scene::MaterialMaps`] component holds a
//! material's slots.

use bevy_ecs::prelude::*;
use glam::{Mat3, Vec2, Vec3};
use std::sync::Arc;

/// How a texture's values are encoded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB transfer function (colour slots: base colour, emissive); decoded to linear
    /// before filtering.
    #[default]
    Srgb,
    /// Linear values (data slots: metallic-roughness, normal, occlusion).
    Linear,
}

/// RGBA8 texels, row-major from the top-left, as decoded from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureData {
    /// Width in texels (≥ 1).
    pub width: u32,
    /// Height in texels (≥ 1).
    pub height: u32,
    /// `width × height × 4` bytes.
    pub rgba8: Vec<u8>,
    /// Encoding of the colour channels (alpha is always linear).
    pub color_space: ColorSpace,
}

impl TextureData {
    /// A texture of one colour.
    pub fn solid(rgba: [u8; 4], color_space: ColorSpace) -> Self {
        TextureData {
            width: 1,
            height: 1,
            rgba8: rgba.to_vec(),
            color_space,
        }
    }

    /// The fallback for a texture that cannot be loaded: an 8 × 8 magenta and black
    /// checker, impossible to mistake for a real material.
    pub fn missing(color_space: ColorSpace) -> Self {
        let rgba8 = (0..64)
            .flat_map(|i| {
                if (i % 8 + i / 8) % 2 == 0 {
                    [255, 0, 255, 255]
                } else {
                    [0, 0, 0, 255]
                }
            })
            .collect();
        TextureData {
            width: 8,
            height: 8,
            rgba8,
            color_space,
        }
    }

    /// Checks the size and the byte count.
    pub fn validate(&self) -> Result<(), String> {
        let expected = u64::from(self.width) * u64::from(self.height) * 4;
        if self.width == 0 || self.height == 0 {
            return Err(format!("empty texture {}×{}", self.width, self.height));
        }
        if self.rgba8.len() as u64 != expected {
            return Err(format!(
                "{}×{} texture holds {} bytes, not {expected}",
                self.width,
                self.height,
                self.rgba8.len()
            ));
        }
        Ok(())
    }
}

/// Identifies a texture in [`Textures`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TextureHandle(pub u32);

/// The texture store.
#[derive(Resource, Default, Debug)]
pub struct Textures {
    textures: Vec<Arc<TextureData>>,
}

impl Textures {
    /// Adds a texture and returns its handle; fails on a texture that breaks
    /// [`TextureData::validate`].
    pub fn add(&mut self, texture: TextureData) -> Result<TextureHandle, String> {
        texture.validate()?;
        let index =
            u32::try_from(self.textures.len()).map_err(|_| "too many textures".to_string())?;
        self.textures.push(Arc::new(texture));
        Ok(TextureHandle(index))
    }

    /// The texture behind a handle.
    pub fn get(&self, handle: TextureHandle) -> Option<&Arc<TextureData>> {
        self.textures.get(handle.0 as usize)
    }
}

/// Texture coordinate wrapping outside [0, 1] (glTF sampler wrap modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Wrap {
    /// Repeat (glTF's default).
    #[default]
    Repeat,
    /// Repeat, mirrored every other time.
    MirroredRepeat,
    /// Clamp to the edge texel.
    ClampToEdge,
}

/// Texel filtering.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    /// The nearest texel (or mip level).
    Nearest,
    /// Linear interpolation.
    #[default]
    Linear,
}

/// How a texture is sampled. With every filter linear, sampling is also anisotropic
/// (16×).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Sampler {
    /// Wrapping along u.
    pub wrap_u: Wrap,
    /// Wrapping along v.
    pub wrap_v: Wrap,
    /// Magnification filter.
    pub mag: Filter,
    /// Minification filter within a mip level.
    pub min: Filter,
    /// Filter between mip levels.
    pub mipmap: Filter,
}

/// `KHR_texture_transform`: uv' = T(offset) · R(rotation) · S(scale) · uv.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Offset in uv units.
    pub offset: Vec2,
    /// Rotation in radians, counter-clockwise in uv space.
    pub rotation_rad: f32,
    /// Scale.
    pub scale: Vec2,
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform {
            offset: Vec2::ZERO,
            rotation_rad: 0.0,
            scale: Vec2::ONE,
        }
    }
}

impl UvTransform {
    /// The transform as a 3 × 3 matrix acting on (u, v, 1), per the extension:
    /// translation × rotation × scale, the rotation's columns being (cos, sin) and
    /// (−sin, cos).
    pub fn matrix(&self) -> Mat3 {
        let (s, c) = self.rotation_rad.sin_cos();
        let translation = Mat3::from_cols(
            Vec3::X,
            Vec3::Y,
            Vec3::new(self.offset.x, self.offset.y, 1.0),
        );
        let rotation = Mat3::from_cols(Vec3::new(c, s, 0.0), Vec3::new(-s, c, 0.0), Vec3::Z);
        let scale = Mat3::from_diagonal(Vec3::new(self.scale.x, self.scale.y, 1.0));
        translation * rotation * scale
    }
}

/// One texture of a material: which texture, how it is sampled, and with which
/// coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// The texture.
    pub texture: TextureHandle,
    /// Its sampler.
    pub sampler: Sampler,
    /// Texture coordinate set, 0 or 1.
    pub uv_set: u32,
    /// `KHR_texture_transform`.
    pub transform: UvTransform,
}

impl TextureSlot {
    /// A texture sampled with the default sampler from coordinate set 0.
    pub fn new(texture: TextureHandle) -> Self {
        TextureSlot {
            texture,
            sampler: Sampler::default(),
            uv_set: 0,
            transform: UvTransform::default(),
        }
    }
}

/// The shading normal a tangent-space normal map gives (glTF 2.0, `normalTexture`): the
/// texel's rgb × 2 − 1, its x and y × `scale`, in the frame of the unit normal `n`, the
/// tangent `tangent.xyz` made perpendicular to it and the bitangent `n × t` × the sign of
/// `tangent.w`; unit length (`n` where the result vanishes).
pub fn normal_from_map(n: Vec3, tangent: glam::Vec4, texel: Vec3, scale: f32) -> Vec3 {
    let t = (tangent.truncate() - n * n.dot(tangent.truncate())).normalize_or(Vec3::X);
    let b = n.cross(t) * if tangent.w >= 0.0 { 1.0 } else { -1.0 };
    let tn = (texel * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
    (t * tn.x + b * tn.y + n * tn.z).normalize_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_transform_follows_the_extension() {
        let t = UvTransform {
            offset: Vec2::new(0.5, 0.25),
            rotation_rad: std::f32::consts::FRAC_PI_2,
            scale: Vec2::new(2.0, 3.0),
        };
        // (1, 0) scaled to (2, 0), rotated a quarter turn to (0, 2), then offset.
        let p = t.matrix() * Vec3::new(1.0, 0.0, 1.0);
        assert!((p - Vec3::new(0.5, 2.25, 1.0)).length() < 1e-6, "{p}");
        assert_eq!(UvTransform::default().matrix(), Mat3::IDENTITY);
    }

    #[test]
    fn textures_are_validated() {
        let mut store = Textures::default();
        assert!(
            store
                .add(TextureData::solid([1, 2, 3, 4], ColorSpace::Linear))
                .is_ok()
        );
        assert!(store.add(TextureData::missing(ColorSpace::Srgb)).is_ok());
        let bad = TextureData {
            width: 2,
            height: 2,
            rgba8: vec![0; 15],
            color_space: ColorSpace::Srgb,
        };
        assert!(store.add(bad).is_err());
        let empty = TextureData {
            width: 0,
            height: 4,
            rgba8: vec![],
            color_space: ColorSpace::Srgb,
        };
        assert!(store.add(empty).is_err());
    }
}

//! The textures of the glTF PBR extensions (transmission, volume, clearcoat, sheen,
//! anisotropy, iridescence, diffuse transmission, specular): each multiplies, per texel,
//! the factor of its [`crate::scene::Material`] layer that glTF names it after, and the
//! clearcoat's normal texture bends the coat's normal
//! (docs/src/materials.md#extension-textures).
//!
//! On the GPU a material binds at most [`EXTENSION_UNITS`] distinct textures for them
//! ([`ExtensionMaps::units`]): glTF files commonly pack two properties into the channels of
//! one image (clearcoat in red, its roughness in green), which then take one unit.

use crate::scene::TextureSlot;

/// How many distinct textures (texture, sampler, coordinate set and transform) the
/// extension textures of one material may use on the GPU.
pub const EXTENSION_UNITS: usize = 4;

/// The unit index that stands for "no texture" (the property keeps its factor).
pub const NO_UNIT: u32 = EXTENSION_UNITS as u32;

/// How many textured properties there are ([`ExtensionMaps::slots`]).
pub const EXTENSION_PROPERTIES: usize = 14;

/// Per property, the glTF texture that scales it and the channel it reads, in
/// [`ExtensionMaps::slots`] order (the order of the `PROPERTY_*` constants in
/// `material_maps.wgsl`).
pub const EXTENSION_TEXTURES: [(&str, &str, &str); EXTENSION_PROPERTIES] = [
    ("KHR_materials_transmission", "transmissionTexture", "r"),
    ("KHR_materials_volume", "thicknessTexture", "g"),
    ("KHR_materials_clearcoat", "clearcoatTexture", "r"),
    ("KHR_materials_clearcoat", "clearcoatRoughnessTexture", "g"),
    ("KHR_materials_sheen", "sheenColorTexture", "rgb"),
    ("KHR_materials_sheen", "sheenRoughnessTexture", "a"),
    ("KHR_materials_anisotropy", "anisotropyTexture", "rgb"),
    ("KHR_materials_iridescence", "iridescenceTexture", "r"),
    (
        "KHR_materials_iridescence",
        "iridescenceThicknessTexture",
        "g",
    ),
    (
        "KHR_materials_diffuse_transmission",
        "diffuseTransmissionTexture",
        "a",
    ),
    (
        "KHR_materials_diffuse_transmission",
        "diffuseTransmissionColorTexture",
        "rgb",
    ),
    ("KHR_materials_specular", "specularTexture", "a"),
    ("KHR_materials_specular", "specularColorTexture", "rgb"),
    ("KHR_materials_clearcoat", "clearcoatNormalTexture", "rgb"),
];

/// The extensions' textures of one material; `None` leaves the factor as it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtensionMaps {
    /// Red × the transmission factor.
    pub transmission: Option<TextureSlot>,
    /// Green × the volume's thickness (m).
    pub thickness: Option<TextureSlot>,
    /// Red × the clearcoat factor.
    pub clearcoat: Option<TextureSlot>,
    /// Green × the clearcoat's perceptual roughness.
    pub clearcoat_roughness: Option<TextureSlot>,
    /// RGB (sRGB) × the sheen colour.
    pub sheen_color: Option<TextureSlot>,
    /// Alpha × the sheen's perceptual roughness.
    pub sheen_roughness: Option<TextureSlot>,
    /// Red and green: the direction in tangent space (each × 2 − 1), turned by the
    /// material's rotation; blue × the strength ([`crate::shading::anisotropy::textured_anisotropy`]).
    pub anisotropy: Option<TextureSlot>,
    /// Red × the iridescence factor.
    pub iridescence: Option<TextureSlot>,
    /// Green: the film thickness between [`ExtensionMaps::iridescence_thickness_min_nm`]
    /// (0) and the material's `thickness_nm` (1) ([`crate::shading::iridescence::film_thickness`]).
    pub iridescence_thickness: Option<TextureSlot>,
    /// Alpha × the diffuse transmission factor.
    pub diffuse_transmission: Option<TextureSlot>,
    /// RGB (sRGB) × the diffuse transmission colour.
    pub diffuse_transmission_color: Option<TextureSlot>,
    /// Alpha × the dielectric specular level (`specularTexture`); it makes an opaque,
    /// lit, not wholly metal surface a relit base.
    pub specular: Option<TextureSlot>,
    /// RGB (sRGB) × the dielectric F0's tint (`specularColorTexture`); a relit base too.
    pub specular_color: Option<TextureSlot>,
    /// The coat's tangent-space normal map (`clearcoatNormalTexture`, as the base's
    /// normal map), scaled by [`ExtensionMaps::clearcoat_normal_scale`].
    pub clearcoat_normal: Option<TextureSlot>,
    /// The scale of the coat normal map's x and y (the texture info's `scale`, 1 by
    /// default).
    pub clearcoat_normal_scale: f32,
    /// The film's thickness (nm) where the thickness texture reads 0 (glTF's
    /// `iridescenceThicknessMinimum`, 100 nm by default).
    pub iridescence_thickness_min_nm: f32,
}

impl Default for ExtensionMaps {
    fn default() -> Self {
        ExtensionMaps {
            transmission: None,
            thickness: None,
            clearcoat: None,
            clearcoat_roughness: None,
            sheen_color: None,
            sheen_roughness: None,
            anisotropy: None,
            iridescence: None,
            iridescence_thickness: None,
            diffuse_transmission: None,
            diffuse_transmission_color: None,
            specular: None,
            specular_color: None,
            clearcoat_normal: None,
            clearcoat_normal_scale: 1.0,
            iridescence_thickness_min_nm: 100.0,
        }
    }
}

/// The GPU's packing of a material's extension textures ([`ExtensionMaps::units`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ExtensionUnits {
    /// The distinct textures bound, in first-use order.
    pub units: [Option<TextureSlot>; EXTENSION_UNITS],
    /// Per property ([`ExtensionMaps::slots`] order), its unit, or [`NO_UNIT`].
    pub of: [u32; EXTENSION_PROPERTIES],
    /// The properties left without a unit because every unit was taken.
    pub dropped: Vec<usize>,
}

impl ExtensionMaps {
    /// The slots in property order (the order of [`EXTENSION_TEXTURES`]).
    pub fn slots(&self) -> [Option<TextureSlot>; EXTENSION_PROPERTIES] {
        [
            self.transmission,
            self.thickness,
            self.clearcoat,
            self.clearcoat_roughness,
            self.sheen_color,
            self.sheen_roughness,
            self.anisotropy,
            self.iridescence,
            self.iridescence_thickness,
            self.diffuse_transmission,
            self.diffuse_transmission_color,
            self.specular,
            self.specular_color,
            self.clearcoat_normal,
        ]
    }

    /// Whether a specular texture is set (the surface is then a relit base).
    pub fn specular_textured(&self) -> bool {
        self.specular.is_some() || self.specular_color.is_some()
    }

    /// [`ExtensionMaps::clearcoat_normal_scale`], 1 where it is not finite.
    pub fn coat_normal_scale(&self) -> f32 {
        let s = self.clearcoat_normal_scale;
        if s.is_finite() { s } else { 1.0 }
    }

    /// Whether any property is textured.
    pub fn any(&self) -> bool {
        self.slots().iter().any(Option::is_some)
    }

    /// The slots packed into at most [`EXTENSION_UNITS`] units: equal slots share one.
    /// Properties past the last free unit keep their factors (they are listed in
    /// `dropped`; the glTF loader drops them with a warning before they get here).
    pub fn units(&self) -> ExtensionUnits {
        let mut out = ExtensionUnits {
            units: [None; EXTENSION_UNITS],
            of: [NO_UNIT; EXTENSION_PROPERTIES],
            dropped: Vec::new(),
        };
        for (k, slot) in self.slots().into_iter().enumerate() {
            let Some(slot) = slot else { continue };
            if let Some(u) = out.units.iter().position(|u| *u == Some(slot)) {
                out.of[k] = u as u32;
            } else if let Some(u) = out.units.iter().position(Option::is_none) {
                out.units[u] = Some(slot);
                out.of[k] = u as u32;
            } else {
                out.dropped.push(k);
            }
        }
        out
    }

    /// [`ExtensionMaps::iridescence_thickness_min_nm`] made usable: at least 0, 100 nm
    /// (glTF's default) where it is not a number.
    pub fn thickness_min_nm(&self) -> f32 {
        let m = self.iridescence_thickness_min_nm;
        if m.is_finite() { m.max(0.0) } else { 100.0 }
    }

    /// The same maps without the properties `units().dropped` lists.
    pub fn packable(mut self) -> ExtensionMaps {
        for k in self.units().dropped {
            *self.slot_mut(k) = None;
        }
        self
    }

    fn slot_mut(&mut self, k: usize) -> &mut Option<TextureSlot> {
        match k {
            0 => &mut self.transmission,
            1 => &mut self.thickness,
            2 => &mut self.clearcoat,
            3 => &mut self.clearcoat_roughness,
            4 => &mut self.sheen_color,
            5 => &mut self.sheen_roughness,
            6 => &mut self.anisotropy,
            7 => &mut self.iridescence,
            8 => &mut self.iridescence_thickness,
            9 => &mut self.diffuse_transmission,
            10 => &mut self.diffuse_transmission_color,
            11 => &mut self.specular,
            12 => &mut self.specular_color,
            _ => &mut self.clearcoat_normal,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{TextureHandle, UvTransform};

    fn slot(texture: u32, uv_set: u32) -> TextureSlot {
        TextureSlot {
            uv_set,
            ..TextureSlot::new(TextureHandle(texture))
        }
    }

    #[test]
    fn equal_slots_share_a_unit_and_the_fifth_texture_is_dropped() {
        let maps = ExtensionMaps {
            clearcoat: Some(slot(0, 0)),
            clearcoat_roughness: Some(slot(0, 0)),
            sheen_color: Some(slot(1, 0)),
            // The same texture from another coordinate set is another unit.
            sheen_roughness: Some(slot(1, 1)),
            anisotropy: Some(slot(2, 0)),
            iridescence: Some(slot(3, 0)),
            diffuse_transmission: Some(TextureSlot {
                transform: UvTransform {
                    scale: glam::Vec2::splat(2.0),
                    ..UvTransform::default()
                },
                ..slot(0, 0)
            }),
            ..ExtensionMaps::default()
        };
        let u = maps.units();
        assert_eq!(u.of[2], 0);
        assert_eq!(u.of[3], 0);
        assert_eq!(u.of[4], 1);
        assert_eq!(u.of[5], 2);
        assert_eq!(u.of[6], 3);
        assert_eq!(u.of[7], NO_UNIT);
        assert_eq!(u.of[9], NO_UNIT);
        assert_eq!(u.of[0], NO_UNIT);
        assert_eq!(u.dropped, vec![7, 9]);
        let kept = maps.packable();
        assert_eq!(kept.iridescence, None);
        assert_eq!(kept.diffuse_transmission, None);
        assert_eq!(kept.clearcoat, maps.clearcoat);
        assert!(kept.units().dropped.is_empty());
    }
}

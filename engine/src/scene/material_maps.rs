//! The material maps: a [`MaterialMaps`] component next to a [`crate::scene::Material`]
//! multiplies the material's factors by its textures, as glTF's metal/roughness model
//! does, and its [`ExtensionMaps`] those of the PBR extensions' layers.

use crate::scene::{ExtensionMaps, TextureSlot};
use bevy_ecs::prelude::*;

/// The textures of a material (glTF's metal/roughness maps). Each multiplies the
/// corresponding factor of the entity's [`crate::scene::Material`]; the vertex colours of
/// the mesh, where it has them, multiply the base colour too.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct MaterialMaps {
    /// Base colour (sRGB rgb, linear alpha).
    pub base_color: Option<TextureSlot>,
    /// Roughness in green, metallic in blue (linear).
    pub metallic_roughness: Option<TextureSlot>,
    /// Tangent-space normal (linear, +y up in texture space as glTF defines).
    pub normal: Option<TextureSlot>,
    /// Ambient occlusion in red (linear).
    pub occlusion: Option<TextureSlot>,
    /// Emissive colour (sRGB).
    pub emissive: Option<TextureSlot>,
    /// Scale of the normal map's x and y.
    pub normal_scale: f32,
    /// Strength of the occlusion map: ao = 1 + strength × (texel − 1).
    pub occlusion_strength: f32,
    /// Alpha mask: fragments with alpha below this are discarded (`None`: opaque).
    pub alpha_cutoff: Option<f32>,
    /// The textures of the PBR extensions' layers (transmission, clearcoat, sheen, …).
    pub extensions: ExtensionMaps,
}

impl Default for MaterialMaps {
    fn default() -> Self {
        MaterialMaps {
            base_color: None,
            metallic_roughness: None,
            normal: None,
            occlusion: None,
            emissive: None,
            normal_scale: 1.0,
            occlusion_strength: 1.0,
            alpha_cutoff: None,
            extensions: ExtensionMaps::default(),
        }
    }
}

impl MaterialMaps {
    /// The five slots in binding order: base colour, metallic-roughness, normal,
    /// occlusion, emissive.
    pub fn slots(&self) -> [Option<TextureSlot>; 5] {
        [
            self.base_color,
            self.metallic_roughness,
            self.normal,
            self.occlusion,
            self.emissive,
        ]
    }

    /// Every texture the maps use: the five slots, then the extensions'.
    pub fn all_slots(&self) -> impl Iterator<Item = TextureSlot> {
        self.slots()
            .into_iter()
            .chain(self.extensions.slots())
            .flatten()
    }
}

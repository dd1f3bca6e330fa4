//! The metal/roughness material (docs/src/formulas.md#material-workflows).

use bevy_ecs::prelude::*;
use glam::{Vec3, Vec4};

/// A metal/roughness surface. All colours are linear (not sRGB).
///
/// Every field reaches the G-buffer (see the README's G-buffer layout); texture slots come
/// with glTF import.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Linear RGBA base colour: albedo of a dielectric, F0 of a metal. Alpha is coverage.
    pub base_color: Vec4,
    /// 0 = dielectric, 1 = metal; values between are partly covered metal.
    pub metallic: f32,
    /// Perceptual roughness r (0 = mirror, 1 = rough); the GGX width is α = r².
    pub perceptual_roughness: f32,
    /// Dielectric specular level (Substance's specularLevel): F0 = 0.08 × level,
    /// so the default 0.5 gives F0 = 0.04.
    pub specular_level: f32,
    /// Emitted luminance in cd/m² (nits), linear RGB.
    pub emissive: Vec3,
    /// Ambient occlusion factor, 0 (fully occluded) .. 1 (open). It scales ambient and
    /// image-based light only, never direct light (docs/src/formulas.md#material-workflows).
    pub occlusion: f32,
    /// Draw back faces too, lit with the normal flipped towards the viewer (glTF's
    /// `doubleSided`); off, back faces are culled.
    pub double_sided: bool,
    /// Alpha blending (glTF's `alphaMode: BLEND`): the base colour's alpha (× its texel
    /// and the vertex colour's) is the fraction of each pixel the surface covers. Such
    /// surfaces are drawn after the opaque frame by the transparent pass, nearest last,
    /// each over what is behind it (docs/src/materials.md#blending). Off, alpha is ignored
    /// unless the material's maps mask by it.
    pub blend: bool,
    /// Light transmitted through the surface and, beneath it, a volume
    /// (`KHR_materials_transmission`, `_volume`, `_ior`): glass, water, thin plastic.
    /// `None`: opaque. Such surfaces are drawn by the transparent pass over a copy of the
    /// opaque frame, sampled along the refracted ray (docs/src/materials.md#transmission).
    pub transmission: Option<Transmission>,
    /// Unlit (glTF's `KHR_materials_unlit`): the surface shows its base colour (× its
    /// texel and vertex colour) as it is, untouched by lights, shadows, the environment
    /// and the probes: its pre-exposed value is the base colour, so it looks the same at
    /// every exposure (it emits base colour ÷ the exposure multiplier, in cd/m²). Its
    /// emissive, metallic, roughness, specular level and transmission are ignored
    /// (docs/src/materials.md#unlit).
    pub unlit: bool,
    /// A clear dielectric coat over the surface (glTF's `KHR_materials_clearcoat`): car
    /// paint, varnish, lacquer. `None`: no coat. It is drawn over opaque surfaces (by the
    /// layers pass), blended and transmissive ones (by the transparent pass); an unlit
    /// surface ignores it ([`Material::coat`]). The coat
    /// is a second specular lobe of F0 0.04 on the mesh's own normal (not the base's
    /// normal map), and the base's light is dimmed by what it reflects
    /// (docs/src/materials.md#clearcoat).
    pub clearcoat: Option<Clearcoat>,
    /// A sheen over the surface (glTF's `KHR_materials_sheen`): velvet, satin, cloth,
    /// dust. `None`: no sheen. Like the clearcoat it is drawn over every lit surface
    /// ([`Material::layer_sheen`]), under the coat if both are set
    /// (docs/src/materials.md#sheen).
    pub sheen: Option<Sheen>,
    /// A specular lobe stretched along a direction in the surface (glTF's
    /// `KHR_materials_anisotropy`): brushed metal, satin, hair. `None`: isotropic. Drawn
    /// on lit surfaces ([`Material::anisotropic`]): on an opaque one the layers pass
    /// lights the base again with the anisotropic lobe, in place of the deferred pass's
    /// isotropic one; a blended or transmissive one is lit with it by the transparent
    /// pass (docs/src/materials.md#anisotropy).
    pub anisotropy: Option<Anisotropy>,
    /// The colour of the dielectric specular reflection (glTF's `KHR_materials_specular`
    /// `specularColorFactor`), linear RGB, each channel 0..1 (clamped): the dielectric
    /// F0 is `0.08 · specular_level · tint` ([`crate::shading::brdf::tinted_f0`]). White (the
    /// default) is untinted. A tint is drawn where the anisotropy is
    /// ([`Material::tint`]): by the layers pass on opaque surfaces, by the transparent pass
    /// on blended ones (docs/src/materials.md#specular-colour).
    pub specular_tint: Vec3,
    /// A thin iridescent film over the surface (glTF's `KHR_materials_iridescence`): soap
    /// bubbles, oil slicks, heat-tinted metal. `None`: no film. Drawn where the anisotropy
    /// is ([`Material::iridescent`]) (docs/src/materials.md#iridescence).
    pub iridescence: Option<Iridescence>,
    /// Light passing diffusely through a thin surface (glTF's
    /// `KHR_materials_diffuse_transmission`): leaves, paper, lampshades, thin fabric.
    /// `None`: none. Its factor moves that share of the diffuse lobe from reflection to
    /// transmission, so light from behind shows through in its colour. Drawn where the
    /// anisotropy is, on lit surfaces that do not transmit and are not wholly metal
    /// ([`Material::translucent`]): by the layers pass on opaque surfaces, by the
    /// transparent pass on blended ones (docs/src/materials.md#diffuse-transmission).
    pub diffuse_transmission: Option<DiffuseTransmission>,
}

/// The diffuse transmission of a [`Material`] (glTF's
/// `KHR_materials_diffuse_transmission`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    /// The share of the diffuse lobe that is transmitted, 0..1 (clamped): 0 reflects it
    /// all, 1 transmits it all.
    pub factor: f32,
    /// The colour of the transmitted light, linear RGB 0..1 (clamped; glTF's default
    /// white). It replaces the base colour for light that passes through.
    pub color: Vec3,
}

impl Default for DiffuseTransmission {
    /// Half the diffuse light passes through, untinted.
    fn default() -> Self {
        DiffuseTransmission {
            factor: 0.5,
            color: Vec3::ONE,
        }
    }
}

impl DiffuseTransmission {
    /// The transmission made safe: the factor and each colour channel in 0..1; NaN or
    /// infinite values are 0.
    pub fn clamped(self) -> DiffuseTransmission {
        let unit = |x: f32| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        DiffuseTransmission {
            factor: unit(self.factor),
            color: Vec3::new(unit(self.color.x), unit(self.color.y), unit(self.color.z)),
        }
    }
}

/// The iridescent film of a [`Material`] (glTF's `KHR_materials_iridescence`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iridescence {
    /// How much of the base's Fresnel the film's replaces, 0..1 (clamped).
    pub factor: f32,
    /// The film's index of refraction (≥ 1, clamped; glTF's default 1.3).
    pub ior: f32,
    /// The film's thickness in nanometres (≥ 0; glTF's default maximum 400).
    pub thickness_nm: f32,
}

impl Default for Iridescence {
    /// A whole film of index 1.3, 400 nm thick (glTF's defaults without a thickness
    /// texture).
    fn default() -> Self {
        Iridescence {
            factor: 1.0,
            ior: 1.3,
            thickness_nm: 400.0,
        }
    }
}

impl Iridescence {
    /// The film made safe: the factor in 0..1, the index ≥ 1, the thickness ≥ 0 nm; NaN
    /// or infinite values are 0 (factor and thickness) or 1.3 (index).
    pub fn clamped(self) -> Iridescence {
        let finite = |x: f32, d: f32| if x.is_finite() { x } else { d };
        Iridescence {
            factor: finite(self.factor, 0.0).clamp(0.0, 1.0),
            ior: finite(self.ior, 1.3).max(1.0),
            thickness_nm: finite(self.thickness_nm, 0.0).max(0.0),
        }
    }
}

/// The anisotropy of a [`Material`] (glTF's `KHR_materials_anisotropy`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anisotropy {
    /// How far the lobe stretches, 0 (isotropic) .. 1: the GGX width along the direction
    /// is `mix(α, 1, strength²)` ([`crate::shading::anisotropy::anisotropic_alphas`]). A negative
    /// strength stretches across the direction instead (Filament's convention): it is
    /// the same as |strength| with the direction turned by 90°.
    pub strength: f32,
    /// The direction's angle (radians) from the mesh's tangent towards its bitangent, in
    /// the tangent plane.
    pub rotation_rad: f32,
}

impl Anisotropy {
    /// The anisotropy made safe: the strength in 0..1, a negative one made positive with
    /// the direction turned by 90°; NaN or infinite values are 0.
    pub fn clamped(self) -> Anisotropy {
        let finite = |x: f32| if x.is_finite() { x } else { 0.0 };
        let (strength, rotation) = (finite(self.strength), finite(self.rotation_rad));
        Anisotropy {
            strength: strength.abs().min(1.0),
            rotation_rad: if strength < 0.0 {
                rotation + std::f32::consts::FRAC_PI_2
            } else {
                rotation
            },
        }
    }
}

/// The sheen of a [`Material`] (glTF's `KHR_materials_sheen`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheen {
    /// The sheen's colour: its reflectance, linear RGB 0..1 (clamped; black is no sheen).
    pub color: Vec3,
    /// Its perceptual roughness, 0..1: the Charlie distribution's α = r², clamped to
    /// [`crate::shading::sheen::MIN_SHEEN_ROUGHNESS`]..1.
    pub perceptual_roughness: f32,
}

impl Sheen {
    /// The sheen with its factors made safe: each colour channel in 0..1 (not finite: 0),
    /// the roughness by [`crate::shading::sheen::clamp_sheen_roughness`].
    pub fn clamped(self) -> Sheen {
        let channel = |c: f32| {
            if c.is_finite() {
                c.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        Sheen {
            color: Vec3::new(
                channel(self.color.x),
                channel(self.color.y),
                channel(self.color.z),
            ),
            perceptual_roughness: crate::shading::sheen::clamp_sheen_roughness(
                self.perceptual_roughness,
            ),
        }
    }
}

/// The clearcoat of a [`Material`] (glTF's `KHR_materials_clearcoat`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearcoat {
    /// Strength of the coat, 0 (none) .. 1 (whole); clamped.
    pub factor: f32,
    /// The coat's perceptual roughness (0 = mirror .. 1), its GGX width α = r²; clamped
    /// like the base's.
    pub perceptual_roughness: f32,
}

impl Default for Clearcoat {
    /// A whole, mirror-smooth coat (glTF's default roughness 0).
    fn default() -> Self {
        Clearcoat {
            factor: 1.0,
            perceptual_roughness: 0.0,
        }
    }
}

impl Clearcoat {
    /// The coat with its factors made safe: the factor in 0..1 (NaN: 0), the roughness
    /// clamped by [`crate::shading::brdf::clamp_perceptual_roughness`].
    pub fn clamped(self) -> Clearcoat {
        Clearcoat {
            factor: if self.factor.is_nan() {
                0.0
            } else {
                self.factor.clamp(0.0, 1.0)
            },
            perceptual_roughness: crate::shading::brdf::clamp_perceptual_roughness(
                self.perceptual_roughness,
            ),
        }
    }
}

/// The transmission and volume of a [`Material`] (glTF's `KHR_materials_transmission`,
/// `KHR_materials_volume` and `KHR_materials_ior`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transmission {
    /// Fraction (0..1) of the light the dielectric base does not reflect specularly that
    /// passes through it instead of being reflected diffusely. Metals transmit nothing.
    pub factor: f32,
    /// Index of refraction of the interior relative to the outside (dimensionless,
    /// clamped to 1..10; glTF's default 1.5). It also sets the refraction; the specular
    /// reflectance stays [`Material::specular_level`]'s.
    pub ior: f32,
    /// Thickness of the volume beneath the surface, measured along the normal, in metres
    /// of the mesh's own space (scaled by the instance's transform). 0 is thin-walled:
    /// light passes straight through without bending or absorption.
    pub thickness_m: f32,
    /// The colour (linear RGB, 0..1) white light takes after travelling
    /// `attenuation_distance_m` through the volume (Beer–Lambert).
    pub attenuation_color: Vec3,
    /// The distance in metres at which light takes `attenuation_color`; `f32::INFINITY`:
    /// no absorption.
    pub attenuation_distance_m: f32,
    /// Dispersion (`KHR_materials_dispersion`): 20 / the Abbe number, 0 for none. The
    /// index of refraction then differs by colour ([`crate::shading::transmission::dispersion_iors`]).
    pub dispersion: f32,
}

impl Default for Transmission {
    /// Clear thin-walled glass: everything transmitted, IOR 1.5, no absorption.
    fn default() -> Self {
        Transmission {
            factor: 1.0,
            ior: 1.5,
            thickness_m: 0.0,
            attenuation_color: Vec3::ONE,
            attenuation_distance_m: f32::INFINITY,
            dispersion: 0.0,
        }
    }
}

impl Default for Material {
    fn default() -> Self {
        Material {
            base_color: Vec4::ONE,
            metallic: 0.0,
            perceptual_roughness: 0.5,
            specular_level: 0.5,
            emissive: Vec3::ZERO,
            occlusion: 1.0,
            double_sided: false,
            blend: false,
            transmission: None,
            unlit: false,
            clearcoat: None,
            sheen: None,
            anisotropy: None,
            specular_tint: Vec3::ONE,
            iridescence: None,
            diffuse_transmission: None,
        }
    }
}

impl Material {
    /// An opaque dielectric or metal of a linear RGB colour.
    pub fn new(base_color: Vec3, metallic: f32, perceptual_roughness: f32) -> Self {
        Material {
            base_color: base_color.extend(1.0),
            metallic,
            perceptual_roughness,
            ..Material::default()
        }
    }

    /// The coat that is drawn (clamped): [`Material::clearcoat`] where its factor is above
    /// 0 and the surface is lit (opaque, blended or transmissive).
    pub fn coat(&self) -> Option<Clearcoat> {
        self.clearcoat
            .map(Clearcoat::clamped)
            .filter(|c| c.factor > 0.0)
            .filter(|_| !self.unlit)
    }

    /// The sheen that is drawn (clamped): [`Material::sheen`] where its colour is not
    /// black and the surface is lit, as for [`Material::coat`].
    pub fn layer_sheen(&self) -> Option<Sheen> {
        self.sheen
            .map(Sheen::clamped)
            .filter(|s| s.color.max_element() > 0.0)
            .filter(|_| !self.unlit)
    }

    /// The anisotropy that is drawn (clamped): [`Material::anisotropy`] where its
    /// strength is above 0 and the surface is lit (opaque, blended or transmissive: a
    /// transmissive one's microfacets refract along the stretched lobe too).
    pub fn anisotropic(&self) -> Option<Anisotropy> {
        self.anisotropy
            .map(Anisotropy::clamped)
            .filter(|a| a.strength > 0.0)
            .filter(|_| !self.unlit)
    }

    /// The specular tint that is drawn: [`Material::specular_tint`] with each channel
    /// clamped to 0..1 (NaN: 1), where it is not white and the surface is lit and not
    /// wholly metal (a metal's F0 is its base colour).
    pub fn tint(&self) -> Option<Vec3> {
        self.relit_tint(false)
    }

    /// The specular tint a relit base is drawn with: [`Material::tint`], or, where
    /// `textured` (a specular texture scales the level or the tint per texel,
    /// [`crate::scene::ExtensionMaps::specular_textured`]), the clamped tint even when
    /// it is white, on every lit surface: whatever the metallic factor, since a
    /// metallic-roughness texture may make any texel a dielectric. A transmissive
    /// surface's tint also colours what it lets through (docs/src/materials.md#tinted-and-iridescent-glass).
    pub fn relit_tint(&self, textured: bool) -> Option<Vec3> {
        let tint = crate::shading::brdf::clamp_tint(self.specular_tint);
        ((tint.min_element() < 1.0 && self.metallic < 1.0) || textured)
            .then_some(tint)
            .filter(|_| !self.unlit)
    }

    /// The iridescent film that is drawn (clamped): [`Material::iridescence`] where its
    /// factor is above 0 and the surface is lit (opaque, blended or transmissive: a soap
    /// bubble is a thin transmissive wall under a film).
    pub fn iridescent(&self) -> Option<Iridescence> {
        self.iridescence
            .map(Iridescence::clamped)
            .filter(|f| f.factor > 0.0)
            .filter(|_| !self.unlit)
    }

    /// The diffuse transmission that is drawn (clamped):
    /// [`Material::diffuse_transmission`] where its factor is above 0 and the surface is
    /// lit and not wholly metal (a metal has no diffuse lobe to transmit). On a
    /// transmissive surface it splits the diffuse share the transmission leaves, as glTF
    /// combines the two.
    pub fn translucent(&self) -> Option<DiffuseTransmission> {
        self.diffuse_transmission
            .map(DiffuseTransmission::clamped)
            .filter(|d| d.factor > 0.0 && self.metallic < 1.0)
            .filter(|_| !self.unlit)
    }

    /// An unlit surface of a linear RGB colour (see [`Material::unlit`]).
    pub fn unlit(color: Vec3) -> Self {
        Material {
            base_color: color.extend(1.0),
            unlit: true,
            ..Material::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specular_textures_relight_every_lit_surface() {
        let metal = Material::new(Vec3::ONE, 1.0, 0.5);
        // A metal's constant tint is not drawn; its specular textures are (a
        // metallic-roughness texture may make any texel a dielectric).
        let tinted = Material {
            specular_tint: Vec3::new(1.0, 0.5, 0.5),
            ..metal
        };
        assert_eq!(tinted.tint(), None);
        assert_eq!(metal.relit_tint(true), Some(Vec3::ONE));
        // A blended or transmissive surface's are drawn too (by the transparent pass); an
        // unlit one's are not.
        let blended = Material {
            blend: true,
            ..Material::new(Vec3::ONE, 0.0, 0.5)
        };
        assert_eq!(blended.relit_tint(true), Some(Vec3::ONE));
        let transmissive = Material {
            transmission: Some(Transmission::default()),
            ..Material::new(Vec3::ONE, 0.0, 0.5)
        };
        assert_eq!(transmissive.relit_tint(true), Some(Vec3::ONE));
        assert_eq!(Material::unlit(Vec3::ONE).relit_tint(true), None);
        let dielectric = Material::new(Vec3::ONE, 0.0, 0.5);
        assert_eq!(dielectric.relit_tint(false), None);
        assert_eq!(tinted.relit_tint(true), Some(Vec3::new(1.0, 0.5, 0.5)));
    }
}

//! Lights in photometric units (docs/src/formulas.md#photometric-lights).
//!
//! A light's position and direction come from its entity's
//! [`crate::scene::GlobalTransform`]: directional and spot lights shine along the entity's
//! forward (local −Z) axis.

use crate::shading::color::kelvin_to_linear_rgb;
use bevy_ecs::prelude::*;
use glam::Vec3;

/// The colour of a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightColor {
    /// Linear RGB, multiplied into the intensity as given.
    LinearRgb(Vec3),
    /// A blackbody colour temperature in kelvin (1667–25000 K), normalised to
    /// luminance 1 so the intensity keeps its photometric meaning.
    Kelvin(f32),
}

impl Default for LightColor {
    fn default() -> Self {
        LightColor::LinearRgb(Vec3::ONE)
    }
}

impl LightColor {
    /// Linear RGB; non-finite or negative components become 0.
    pub fn to_linear_rgb(self) -> Vec3 {
        let c = match self {
            LightColor::LinearRgb(c) => c,
            LightColor::Kelvin(k) => kelvin_to_linear_rgb(k),
        };
        Vec3::new(sanitize(c.x), sanitize(c.y), sanitize(c.z))
    }
}

fn sanitize(x: f32) -> f32 {
    if x.is_finite() { x.max(0.0) } else { 0.0 }
}

/// How bright a point or spot light is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LuminousIntensity {
    /// Luminous power Φ in lumens. A point light spreads it over the sphere:
    /// I = Φ / 4π cd. A spot light concentrates it in its outer cone:
    /// I = Φ / (2π (1 − cos θ_outer)) cd (Filament's physically coupled spot).
    Lumens(f32),
    /// Luminous intensity I in candela (lm/sr), as glTF's `KHR_lights_punctual`.
    Candela(f32),
}

/// A light infinitely far away (the sun): parallel rays, no falloff.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::scene::Transform)]
pub struct DirectionalLight {
    /// Illuminance on a surface facing the light, in lux (lm/m²). Sun ≈ 100 000 lx.
    pub illuminance_lux: f32,
    /// Colour.
    pub color: LightColor,
    /// Whether the light casts shadows (see [`crate::scene::ShadowSettings`] and
    /// [`crate::scene::Cascades`]).
    pub cast_shadows: bool,
    /// Angular diameter of the light's disc in radians (the sun: 0.0093 rad = 0.53°): the
    /// size that soft shadows (PCSS) use for their penumbrae.
    pub angular_diameter_rad: f32,
}

impl Default for DirectionalLight {
    fn default() -> Self {
        DirectionalLight {
            illuminance_lux: 10_000.0,
            color: LightColor::default(),
            cast_shadows: false,
            angular_diameter_rad: SUN_ANGULAR_DIAMETER_RAD,
        }
    }
}

/// The sun's mean angular diameter seen from the Earth, 0.533°, in radians.
pub const SUN_ANGULAR_DIAMETER_RAD: f32 = 0.0093;

/// Default radius of point and spot lights: a 2.5 cm bulb.
pub const DEFAULT_LIGHT_RADIUS_M: f32 = 0.025;

/// A light emitting equally in all directions from a point.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::scene::Transform)]
pub struct PointLight {
    /// Brightness, in lumens or candela.
    pub intensity: LuminousIntensity,
    /// Colour.
    pub color: LightColor,
    /// Distance in metres beyond which the light has no effect; the falloff is
    /// windowed smoothly to 0 there (docs/src/formulas.md#photometric-lights). Infinite = no limit.
    pub range_m: f32,
    /// Whether the light casts shadows (see [`crate::scene::ShadowSettings`]).
    pub cast_shadows: bool,
    /// Radius of the emitting sphere in metres: the size that soft shadows (PCSS) use.
    pub radius_m: f32,
}

impl Default for PointLight {
    fn default() -> Self {
        PointLight {
            intensity: LuminousIntensity::Lumens(800.0),
            color: LightColor::default(),
            range_m: 20.0,
            cast_shadows: false,
            radius_m: DEFAULT_LIGHT_RADIUS_M,
        }
    }
}

impl PointLight {
    /// Luminous intensity in candela.
    pub fn candela(&self) -> f32 {
        match self.intensity {
            LuminousIntensity::Lumens(lm) => lm / (4.0 * std::f32::consts::PI),
            LuminousIntensity::Candela(cd) => cd,
        }
    }
}

/// A point light restricted to a cone around its forward axis.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::scene::Transform)]
pub struct SpotLight {
    /// Brightness, in lumens (emitted into the outer cone) or candela.
    pub intensity: LuminousIntensity,
    /// Colour.
    pub color: LightColor,
    /// Range in metres, as for [`PointLight::range_m`].
    pub range_m: f32,
    /// Half-angle from the axis (radians) inside which the light is at full strength.
    pub inner_angle_rad: f32,
    /// Half-angle from the axis (radians) outside which there is no light; at most π/2.
    pub outer_angle_rad: f32,
    /// Whether the light casts shadows (see [`crate::scene::ShadowSettings`]).
    pub cast_shadows: bool,
    /// Radius of the emitting disc in metres: the size that soft shadows (PCSS) use.
    pub radius_m: f32,
}

impl Default for SpotLight {
    fn default() -> Self {
        SpotLight {
            intensity: LuminousIntensity::Lumens(800.0),
            color: LightColor::default(),
            range_m: 20.0,
            inner_angle_rad: 0.0,
            outer_angle_rad: std::f32::consts::FRAC_PI_4,
            cast_shadows: false,
            radius_m: DEFAULT_LIGHT_RADIUS_M,
        }
    }
}

impl SpotLight {
    /// Luminous intensity in candela.
    pub fn candela(&self) -> f32 {
        match self.intensity {
            LuminousIntensity::Lumens(lm) => {
                let outer = self
                    .outer_angle_rad
                    .clamp(1e-3, std::f32::consts::FRAC_PI_2);
                lm / (2.0 * std::f32::consts::PI * (1.0 - outer.cos()))
            }
            LuminousIntensity::Candela(cd) => cd,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lumens_to_candela() {
        let p = PointLight {
            intensity: LuminousIntensity::Lumens(4.0 * std::f32::consts::PI),
            ..PointLight::default()
        };
        assert!((p.candela() - 1.0).abs() < 1e-6);
        // A hemisphere spot (outer = 90°) spreads Φ over 2π sr.
        let s = SpotLight {
            intensity: LuminousIntensity::Lumens(2.0 * std::f32::consts::PI),
            outer_angle_rad: std::f32::consts::FRAC_PI_2,
            ..SpotLight::default()
        };
        assert!((s.candela() - 1.0).abs() < 1e-5);
        // A zero-angle cone stays finite.
        let s = SpotLight {
            outer_angle_rad: 0.0,
            ..SpotLight::default()
        };
        assert!(s.candela().is_finite());
    }

    #[test]
    fn colours_are_sanitised() {
        assert_eq!(
            LightColor::LinearRgb(Vec3::new(f32::NAN, -1.0, 2.0)).to_linear_rgb(),
            Vec3::new(0.0, 0.0, 2.0)
        );
    }
}

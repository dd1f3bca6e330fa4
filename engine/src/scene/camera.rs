//! The camera: projection and exposure (PBR-REFERENCE §3).
//!
//! The physical camera (aperture, shutter, ISO, depth of field) arrives with its own
//! issue; [`Exposure`] is where it plugs in.

use crate::color::Tonemapper;
use bevy_ecs::prelude::*;
use glam::{Mat4, Vec3};

/// A perspective projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Vertical field of view in radians.
    pub fov_y_rad: f32,
    /// Near plane distance in metres (> 0).
    pub near_m: f32,
    /// Far plane distance in metres (> near).
    pub far_m: f32,
}

impl Default for Projection {
    fn default() -> Self {
        Projection {
            fov_y_rad: 45f32.to_radians(),
            near_m: 0.1,
            far_m: 100.0,
        }
    }
}

impl Projection {
    /// The clip-from-view matrix with reversed Z (near → depth 1, far → depth 0), which
    /// spreads 32-bit float depth precision evenly over distance. Degenerate parameters are
    /// clamped: FOV into [0.01°, 179°], near ≥ 1 µm, far > near.
    pub fn matrix(&self, aspect: f32) -> Mat4 {
        let fov = if self.fov_y_rad.is_finite() {
            self.fov_y_rad
                .clamp(0.01f32.to_radians(), 179f32.to_radians())
        } else {
            45f32.to_radians()
        };
        let near = if self.near_m.is_finite() {
            self.near_m.max(1e-6)
        } else {
            0.1
        };
        let far = if self.far_m.is_finite() && self.far_m > near * 1.0001 {
            self.far_m
        } else {
            near * 1e4
        };
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        Mat4::perspective_rh(fov, aspect, far, near)
    }
}

/// How scene luminance (cd/m²) becomes the exposed value that is tone mapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    /// An exposure value at ISO 100: `exposure = 1 / (1.2 · 2^EV100)`
    /// (Lagarde & de Rousiers 2014, "Moving Frostbite to PBR"; PBR-REFERENCE §3).
    Ev100(f32),
    /// A linear multiplier applied to luminance as given (1 = raw radiance).
    Linear(f32),
}

impl Default for Exposure {
    /// EV100 9.7, Blender's and Bevy's default (an indoor scene).
    fn default() -> Self {
        Exposure::Ev100(9.7)
    }
}

/// `exposure = 1 / (1.2 · 2^EV100)`: the factor that maps luminance (cd/m²) to the
/// exposed value at which 1.0 is the sensor's saturation.
pub fn exposure_from_ev100(ev100: f32) -> f32 {
    1.0 / (1.2 * 2f32.powf(ev100))
}

/// Inverse of [`exposure_from_ev100`].
pub fn ev100_from_exposure(exposure: f32) -> f32 {
    (1.0 / (1.2 * exposure)).log2()
}

impl Exposure {
    /// Range of EV100 accepted; outside it the value is clamped (−10 is moonless night
    /// with a fast lens, 30 is far past direct sunlight on snow).
    pub const EV100_RANGE: (f32, f32) = (-10.0, 30.0);

    /// The linear multiplier applied to luminance, finite and positive.
    pub fn multiplier(self) -> f32 {
        match self {
            Exposure::Ev100(ev) => exposure_from_ev100(Self::clamp_ev100(ev)),
            Exposure::Linear(k) if k.is_finite() && k > 0.0 => k.clamp(1e-12, 1e12),
            Exposure::Linear(_) => 1.0,
        }
    }

    /// The EV100 equivalent of [`Exposure::multiplier`].
    pub fn ev100(self) -> f32 {
        match self {
            Exposure::Ev100(ev) => Self::clamp_ev100(ev),
            Exposure::Linear(_) => ev100_from_exposure(self.multiplier()),
        }
    }

    fn clamp_ev100(ev: f32) -> f32 {
        if ev.is_finite() {
            ev.clamp(Self::EV100_RANGE.0, Self::EV100_RANGE.1)
        } else {
            Exposure::default().ev100()
        }
    }
}

/// A camera that looks along its entity's forward (local −Z) axis.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::scene::Transform)]
pub struct Camera {
    /// Projection.
    pub projection: Projection,
    /// Exposure.
    pub exposure: Exposure,
    /// Tone mapping operator.
    pub tonemapper: Tonemapper,
    /// Luminance of the background where no geometry is drawn, cd/m² (linear RGB).
    pub background: Vec3,
    /// Only the first active camera renders.
    pub active: bool,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            projection: Projection::default(),
            exposure: Exposure::default(),
            tonemapper: Tonemapper::default(),
            background: Vec3::ZERO,
            active: true,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exposure_values() {
        // EV100 0 → 1/1.2.
        assert!((exposure_from_ev100(0.0) - 1.0 / 1.2).abs() < 1e-7);
        // One stop halves the exposure.
        assert!((exposure_from_ev100(10.0) / exposure_from_ev100(11.0) - 2.0).abs() < 1e-5);
        // EV100 9.7 (the default).
        let e = Exposure::default().multiplier();
        assert!((e - 1.0 / (1.2 * 2f32.powf(9.7))).abs() < 1e-9);
        assert!((ev100_from_exposure(e) - 9.7).abs() < 1e-4);
        assert_eq!(Exposure::Linear(1.0).multiplier(), 1.0);
        assert!((Exposure::Linear(1.0).ev100() - (1.0f32 / 1.2).log2()).abs() < 1e-6);
        // Bad input never gives a non-finite multiplier.
        for x in [f32::NAN, f32::INFINITY, -3.0, 0.0, 1e30, -1e30] {
            assert!(Exposure::Linear(x).multiplier().is_finite());
            assert!(Exposure::Ev100(x).multiplier().is_finite());
            assert!(Exposure::Ev100(x).multiplier() > 0.0);
        }
    }

    #[test]
    fn reversed_z_projection() {
        let p = Projection::default().matrix(1.0);
        let near = p.project_point3(Vec3::new(0.0, 0.0, -0.1));
        let far = p.project_point3(Vec3::new(0.0, 0.0, -100.0));
        assert!((near.z - 1.0).abs() < 1e-5, "{near}");
        assert!(far.z.abs() < 1e-5, "{far}");
        let bad = Projection {
            fov_y_rad: f32::NAN,
            near_m: 0.0,
            far_m: -1.0,
        };
        assert!(bad.matrix(0.0).is_finite());
    }
}

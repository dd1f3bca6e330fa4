//! Shadow settings: per light (resolution, biases, cascades) and per mesh (casts,
//! receives). A light casts shadows when its `cast_shadows` is true; these components
//! only tune how.

use bevy_ecs::prelude::*;

/// Shadow-map settings of one light. Optional: without it a light uses
/// [`ShadowSettings::directional`], [`ShadowSettings::spot`] or [`ShadowSettings::point`].
///
/// The biases are in shadow-map texels, converted to metres with the world size of a
/// texel at the receiver, so one setting suits any resolution and distance:
/// - `depth_bias` moves the receiver towards the light by that many texels;
/// - `slope_bias` adds `slope_bias · tan θ` texels (θ between normal and light), where
///   a texel's depth error grows with the slope;
/// - `normal_bias` moves the receiver along its normal by `normal_bias · sin θ` texels.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct ShadowSettings {
    /// Side of each shadow map of this light (each cascade, the spot view, each cube face)
    /// in texels; rounded up to a power of two in 64..=8192.
    pub resolution: u32,
    /// Constant bias along the light direction, texels.
    pub depth_bias: f32,
    /// Slope-scaled bias, texels × tan θ (tan θ is clamped to 10).
    pub slope_bias: f32,
    /// Normal-offset bias, texels × sin θ.
    pub normal_bias: f32,
}

impl ShadowSettings {
    /// Default for directional lights: 2048² per cascade.
    pub fn directional() -> Self {
        ShadowSettings {
            resolution: 2048,
            ..Self::BIASES
        }
    }

    /// Default for spot lights: 1024².
    pub fn spot() -> Self {
        ShadowSettings {
            resolution: 1024,
            ..Self::BIASES
        }
    }

    /// Default for point lights: 512² per cube face.
    pub fn point() -> Self {
        ShadowSettings {
            resolution: 512,
            ..Self::BIASES
        }
    }

    /// The default biases (README, "Shadows": why these values).
    const BIASES: ShadowSettings = ShadowSettings {
        resolution: 1024,
        depth_bias: 1.0,
        slope_bias: 1.0,
        normal_bias: 1.0,
    };
}

/// How a directional light's shadow is split into cascades. Optional: without it a
/// directional light uses `Cascades::default()`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Cascades {
    /// Number of cascades, 1..=4.
    pub count: u32,
    /// Camera distance (m) up to which shadows are drawn; beyond it surfaces are lit.
    pub max_distance_m: f32,
    /// Split scheme: 0 = uniform, 1 = logarithmic, between = the practical blend
    /// (Zhang et al. 2006).
    pub split_lambda: f32,
    /// Fraction of each cascade, at its far end, over which it blends into the next one
    /// (0 = hard switch).
    pub blend_fraction: f32,
}

impl Default for Cascades {
    fn default() -> Self {
        Cascades {
            count: 3,
            max_distance_m: 50.0,
            split_lambda: 0.75,
            blend_fraction: 0.1,
        }
    }
}

/// Marks a mesh entity that casts no shadow.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NotShadowCaster;

/// Marks a mesh entity on which no shadow falls.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NotShadowReceiver;

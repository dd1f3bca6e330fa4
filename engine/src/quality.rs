//! Speed/accuracy knobs. Each is a field with a documented cost; presets arrive with the
//! benchmark issue.

use crate::brdf::VisibilityModel;
use bevy_ecs::prelude::Resource;

/// How shadow maps are filtered (README, "Shadows", for the measured cost of each).
/// The numeric values are the shader constant `SHADOW_FILTER`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowFilter {
    /// One comparison tap: the hardware's bilinear 2×2 percentage-closer filter.
    Hardware2x2 = 0,
    /// 16 hardware 2×2 taps on a Poisson disc of radius 1.5 texels, rotated per pixel
    /// (Reeves et al. 1987, percentage-closer filtering).
    #[default]
    Pcf = 1,
    /// Percentage-closer soft shadows (Fernando 2005): a 16-tap blocker search, then a
    /// 16-tap filter whose radius grows with the light's size and the distance between
    /// blocker and receiver (contact hardening).
    Pcss = 2,
}

impl ShadowFilter {
    /// Every filter, cheapest first.
    pub const ALL: [ShadowFilter; 3] = [
        ShadowFilter::Hardware2x2,
        ShadowFilter::Pcf,
        ShadowFilter::Pcss,
    ];

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ShadowFilter::Hardware2x2 => "hardware",
            ShadowFilter::Pcf => "pcf",
            ShadowFilter::Pcss => "pcss",
        }
    }

    /// Parses a command-line name.
    pub fn from_name(name: &str) -> Option<ShadowFilter> {
        ShadowFilter::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(name))
    }
}

/// The renderer's quality settings.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// Visibility (geometric) term of the specular lobe. `schlick-ggx` (the seeds',
    /// default) and `smith-correlated-fast` cost the same; `smith-correlated` adds two
    /// square roots per light and pixel.
    pub visibility: VisibilityModel,
    /// Shadows on or off for the whole frame (`--no-shadows`); off skips the shadow pass.
    pub shadows: bool,
    /// Shadow filtering.
    pub shadow_filter: ShadowFilter,
    /// Multiple-scattering energy compensation of the specular lobe (Kulla & Conty 2017),
    /// for environment and direct light. On: metals and rough surfaces keep their energy
    /// (the white furnace holds); costs one table lookup per pixel.
    pub energy_compensation: bool,
    /// GGX samples per texel when prefiltering an environment (once per image).
    pub ibl_samples: u32,
    /// Side of the split-sum BRDF table in texels (built once).
    pub brdf_lut_size: u32,
    /// Samples per texel of the split-sum BRDF table.
    pub brdf_lut_samples: u32,
}

impl Default for Quality {
    fn default() -> Self {
        Quality {
            visibility: VisibilityModel::default(),
            shadows: true,
            shadow_filter: ShadowFilter::default(),
            energy_compensation: true,
            ibl_samples: 64,
            brdf_lut_size: 64,
            brdf_lut_samples: 512,
        }
    }
}

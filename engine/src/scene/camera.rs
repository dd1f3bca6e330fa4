//! The physical camera (docs/src/formulas.md#exposure): projection, lens (aperture, shutter, ISO,
//! focal length, focus), exposure modes, depth of field, vignetting and tone mapping.

use crate::shading::color::Tonemapper;
use bevy_ecs::prelude::*;
use glam::{Mat4, Vec2, Vec3, Vec4};

/// A perspective projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Vertical field of view in radians.
    pub fov_y_rad: f32,
    /// Near plane distance in metres (> 0).
    pub near_m: f32,
    /// Far plane distance in metres (> near).
    pub far_m: f32,
    /// Off-axis shift of the frustum's centre in tangent units (view-space x/−z, y/−z):
    /// a lens shift. Zero for a centred frustum; the thin-lens reference
    /// ([`crate::reference::thin_lens`]) uses it to keep the focus plane still.
    pub shift: Vec2,
}

impl Default for Projection {
    fn default() -> Self {
        Projection {
            fov_y_rad: 45f32.to_radians(),
            near_m: 0.1,
            far_m: 100.0,
            shift: Vec2::ZERO,
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
        let tan_half = (fov * 0.5).tan();
        let shift = if self.shift.is_finite() {
            self.shift
        } else {
            Vec2::ZERO
        };
        // Clip x' = x − k·w moves NDC x by −k: a tangent offset of shift.x.
        let k = Vec2::new(shift.x / (tan_half * aspect), shift.y / tan_half);
        let shear = Mat4::from_cols(Vec4::X, Vec4::Y, Vec4::Z, Vec4::new(-k.x, -k.y, 0.0, 1.0));
        shear * Mat4::perspective_rh(fov, aspect, far, near)
    }
}

/// How scene luminance (cd/m²) becomes the exposed value that is tone mapped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    /// An exposure value at ISO 100: `exposure = 1 / (1.2 · 2^EV100)`
    /// (Lagarde & de Rousiers 2014, "Moving Frostbite to PBR"; docs/src/formulas.md#exposure).
    Ev100(f32),
    /// A linear multiplier applied to luminance as given (1 = raw radiance).
    Linear(f32),
    /// From the lens settings: `EV100 = log2(N² / t · 100 / S)` with the camera's
    /// [`Lens`] aperture N, shutter time t (s) and ISO S.
    Physical,
    /// Metered from the rendered frame (a luminance histogram on the GPU) and adapted
    /// smoothly over time.
    Auto(AutoExposure),
}

/// Automatic exposure: the frame's luminance histogram sets a target EV100 that the
/// camera approaches exponentially.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoExposure {
    /// Lowest EV100 the camera adapts to (a dark scene stays dark below it).
    pub min_ev100: f32,
    /// Highest EV100 the camera adapts to.
    pub max_ev100: f32,
    /// Adaptation rate (1/s): the remaining difference shrinks by `e^(−rate · dt)`.
    pub rate_per_s: f32,
    /// Ignored darkest and brightest fractions of the pixels (0..0.5 each).
    pub low_percentile: f32,
    /// Upper cut-off fraction.
    pub high_percentile: f32,
    /// EV100 used for the very first frame, before anything was metered.
    pub initial_ev100: f32,
}

impl Default for AutoExposure {
    fn default() -> Self {
        AutoExposure {
            min_ev100: -6.0,
            max_ev100: 20.0,
            rate_per_s: 3.0,
            low_percentile: 0.05,
            high_percentile: 0.95,
            initial_ev100: 9.7,
        }
    }
}

/// The reflected-light meter constant K (cd/m² · s · ISO), ISO 2720: a meter sets
/// `EV100 = log2(L · 100 / K)` for an average luminance L.
pub const METER_CALIBRATION_K: f32 = 12.5;

/// The EV100 a reflected-light meter picks for log-average luminance `luminance` (cd/m²).
pub fn metered_ev100(luminance: f32) -> f32 {
    (luminance.max(1e-9) * 100.0 / METER_CALIBRATION_K).log2()
}

/// `EV100 = log2(N² / t · 100 / S)` (docs/src/formulas.md#exposure), aperture N (f-number), shutter
/// time t (s), sensitivity S (ISO).
pub fn ev100_from_settings(aperture_f_stops: f32, shutter_s: f32, iso: f32) -> f32 {
    (aperture_f_stops * aperture_f_stops / shutter_s * 100.0 / iso).log2()
}

/// A lens and sensor in real units. The vertical field of view stays in
/// [`Projection::fov_y_rad`]; the focal length follows from it and the sensor height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lens {
    /// Aperture as an f-number N (f/N); clamped to 0.5..=64.
    pub aperture_f_stops: f32,
    /// Shutter time in seconds; clamped to 1/25000..=60.
    pub shutter_s: f32,
    /// Sensor sensitivity (ISO); clamped to 10..=204800.
    pub iso: f32,
    /// Sensor height in millimetres (24 mm: full frame).
    pub sensor_height_mm: f32,
    /// Distance in metres at which the lens is focused; `f32::INFINITY` for infinity.
    /// Clamped to ≥ 1.01 × the focal length (closer, the circle of confusion diverges).
    pub focus_distance_m: f32,
}

impl Default for Lens {
    /// f/16, 1/125 s, ISO 100 (the sunny-16 rule, EV100 ≈ 15), full frame, focused at 10 m.
    fn default() -> Self {
        Lens {
            aperture_f_stops: 16.0,
            shutter_s: 1.0 / 125.0,
            iso: 100.0,
            sensor_height_mm: 24.0,
            focus_distance_m: 10.0,
        }
    }
}

/// Ranges of docs/src/formulas.md#numerical-guards for the physical settings.
pub const APERTURE_RANGE: (f32, f32) = (0.5, 64.0);
/// Shutter time range (s).
pub const SHUTTER_RANGE: (f32, f32) = (1.0 / 25000.0, 60.0);
/// ISO range.
pub const ISO_RANGE: (f32, f32) = (10.0, 204_800.0);

fn clamp_noted(
    name: &str,
    v: f32,
    (lo, hi): (f32, f32),
    fallback: f32,
    notes: &mut Vec<String>,
) -> f32 {
    if !v.is_finite() {
        notes.push(format!("{name} {v} is not finite: using {fallback}"));
        fallback
    } else if v < lo || v > hi {
        let c = v.clamp(lo, hi);
        notes.push(format!("{name} {v} is outside {lo}..={hi}: clamped to {c}"));
        c
    } else {
        v
    }
}

impl Lens {
    /// The lens with every setting clamped into its range (docs/src/formulas.md#numerical-guards) for a focal
    /// length of `focal_length_m`, and one note per setting that was changed.
    pub fn clamped(&self, focal_length_m: f32) -> (Lens, Vec<String>) {
        let d = Lens::default();
        let mut notes = Vec::new();
        let aperture = clamp_noted(
            "aperture (f-number)",
            self.aperture_f_stops,
            APERTURE_RANGE,
            d.aperture_f_stops,
            &mut notes,
        );
        let shutter = clamp_noted(
            "shutter (s)",
            self.shutter_s,
            SHUTTER_RANGE,
            d.shutter_s,
            &mut notes,
        );
        let iso = clamp_noted("ISO", self.iso, ISO_RANGE, d.iso, &mut notes);
        let sensor = clamp_noted(
            "sensor height (mm)",
            self.sensor_height_mm,
            (1.0, 1000.0),
            d.sensor_height_mm,
            &mut notes,
        );
        let min_focus = focal_length_m * 1.01;
        let focus = if self.focus_distance_m.is_nan() {
            notes.push("focus distance NaN: focusing at infinity".into());
            f32::INFINITY
        } else if self.focus_distance_m < min_focus {
            notes.push(format!(
                "focus distance {} m is closer than the focal length allows: clamped to {min_focus} m",
                self.focus_distance_m
            ));
            min_focus
        } else {
            self.focus_distance_m
        };
        (
            Lens {
                aperture_f_stops: aperture,
                shutter_s: shutter,
                iso,
                sensor_height_mm: sensor,
                focus_distance_m: focus,
            },
            notes,
        )
    }

    /// Focal length in metres for a vertical field of view: `f = h / (2 tan(fov/2))`.
    pub fn focal_length_m(&self, fov_y_rad: f32) -> f32 {
        self.sensor_height_mm * 1e-3 / (2.0 * (fov_y_rad * 0.5).tan().max(1e-6))
    }

    /// The vertical field of view of a focal length in millimetres on this sensor.
    pub fn fov_for_focal_length(&self, focal_length_mm: f32) -> f32 {
        2.0 * (self.sensor_height_mm / (2.0 * focal_length_mm.max(1e-3))).atan()
    }
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

    /// The linear multiplier applied to luminance, finite and positive, for manual and
    /// linear exposure; physical and automatic exposure need the lens or the meter (see
    /// [`Camera::resolve_exposure`]) and give the default here.
    pub fn multiplier(self) -> f32 {
        match self {
            Exposure::Ev100(ev) => exposure_from_ev100(Self::clamp_ev100(ev)),
            Exposure::Linear(k) if k.is_finite() && k > 0.0 => k.clamp(1e-12, 1e12),
            Exposure::Linear(_) => 1.0,
            Exposure::Physical | Exposure::Auto(_) => Exposure::default().multiplier(),
        }
    }

    /// The EV100 equivalent of [`Exposure::multiplier`].
    pub fn ev100(self) -> f32 {
        match self {
            Exposure::Ev100(ev) => Self::clamp_ev100(ev),
            _ => ev100_from_exposure(self.multiplier()),
        }
    }

    /// EV100 clamped into [`Exposure::EV100_RANGE`]; non-finite → the default 9.7.
    pub fn clamp_ev100(ev: f32) -> f32 {
        if ev.is_finite() {
            ev.clamp(Self::EV100_RANGE.0, Self::EV100_RANGE.1)
        } else {
            Exposure::default().ev100()
        }
    }
}

/// Depth of field from the thin lens (docs/src/formulas.md#exposure).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthOfField {
    /// Sample rings of the gather blur (1..=5): ring k has 8k samples. More rings give
    /// smoother bokeh at more cost (README, "Physical camera").
    pub rings: u32,
    /// Largest circle of confusion in pixels (diameter, full resolution); larger blur is
    /// clamped to it.
    pub max_coc_px: f32,
}

impl Default for DepthOfField {
    fn default() -> Self {
        DepthOfField {
            rings: 3,
            max_coc_px: 32.0,
        }
    }
}

/// Darkening towards the frame's corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vignette {
    /// 0 = none, 1 = the natural cos⁴ falloff of the lens's field of view.
    pub strength: f32,
}

/// A camera that looks along its entity's forward (local −Z) axis.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(crate::scene::Transform)]
pub struct Camera {
    /// Projection.
    pub projection: Projection,
    /// Exposure mode.
    pub exposure: Exposure,
    /// Exposure compensation in stops: +1 doubles the exposure (any mode).
    pub exposure_compensation: f32,
    /// Lens and sensor: physical exposure and depth of field.
    pub lens: Lens,
    /// Depth of field; `None` runs no depth-of-field pass.
    pub depth_of_field: Option<DepthOfField>,
    /// Vignetting; `None` (the default) for none.
    pub vignette: Option<Vignette>,
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
            exposure_compensation: 0.0,
            lens: Lens::default(),
            depth_of_field: None,
            vignette: None,
            tonemapper: Tonemapper::default(),
            background: Vec3::ZERO,
            active: true,
        }
    }
}

/// The exposure a camera ends up with, and what had to be clamped on the way.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedExposure {
    /// EV100 after compensation and clamping.
    pub ev100: f32,
    /// `1 / (1.2 · 2^EV100)` (or the linear multiplier × 2^compensation).
    pub multiplier: f32,
    /// One line per clamped setting.
    pub notes: Vec<String>,
}

impl Camera {
    /// The exposure of this camera; `metered_ev100` is the automatic exposure's current
    /// EV100 (ignored by the other modes).
    pub fn resolve_exposure(&self, metered_ev100: Option<f32>) -> ResolvedExposure {
        let mut notes = Vec::new();
        let comp = if self.exposure_compensation.is_finite() {
            let c = self.exposure_compensation;
            let clamped = c.clamp(-20.0, 20.0);
            if clamped != c {
                notes.push(format!(
                    "exposure compensation {c} stops is outside -20..=20: clamped to {clamped}"
                ));
            }
            clamped
        } else {
            notes.push("exposure compensation is not finite: using 0".into());
            0.0
        };
        let ev = match self.exposure {
            Exposure::Linear(k) => {
                let m = Exposure::Linear(k).multiplier() * comp.exp2();
                return ResolvedExposure {
                    ev100: ev100_from_exposure(m),
                    multiplier: m,
                    notes,
                };
            }
            Exposure::Ev100(ev) => ev,
            Exposure::Physical => {
                let (lens, lens_notes) = self
                    .lens
                    .clamped(self.lens.focal_length_m(self.projection.fov_y_rad));
                notes.extend(lens_notes);
                ev100_from_settings(lens.aperture_f_stops, lens.shutter_s, lens.iso)
            }
            Exposure::Auto(a) => metered_ev100.unwrap_or(a.initial_ev100),
        };
        let target = ev - comp;
        let (lo, hi) = Exposure::EV100_RANGE;
        if target.is_finite() && !(lo..=hi).contains(&target) {
            notes.push(format!("EV100 {target:.2} is outside {lo}..={hi}: clamped"));
        }
        let ev100 = Exposure::clamp_ev100(target);
        ResolvedExposure {
            ev100,
            multiplier: exposure_from_ev100(ev100),
            notes,
        }
    }
}

/// Signed circle of confusion of the thin lens, diameter on the sensor in metres:
/// `c = A · f · |z − S| / (z · (S − f))` with aperture diameter A = f/N, focal length f,
/// focus distance S and depth z (all m; docs/src/formulas.md#exposure). Negative in front of the
/// focus plane. `S = ∞` gives `−A · f / z` (everything lies in front of the focus plane). Depth is clamped to ≥ 1 µm and S to ≥ 1.01 f.
pub fn circle_of_confusion(
    depth_m: f32,
    focus_m: f32,
    focal_length_m: f32,
    aperture_diameter_m: f32,
) -> f32 {
    let z = depth_m.max(1e-6);
    let f = focal_length_m;
    // Infinity, NaN and anything beyond 3e38 m (the largest float) focus at infinity.
    if focus_m.is_nan() || focus_m > 3.0e38 {
        return -aperture_diameter_m * f / z;
    }
    let s = focus_m.max(f * 1.01);
    aperture_diameter_m * f * (z - s) / (z * (s - f))
}

/// Natural vignetting: the cos⁴ law of illumination at angle θ off the optical axis,
/// from `tan²θ` (dimensionless), blended by `strength` (0 none, 1 physical).
pub fn vignetting(tan2_theta: f32, strength: f32) -> f32 {
    let cos2 = 1.0 / (1.0 + tan2_theta.max(0.0));
    1.0 + (cos2 * cos2 - 1.0) * strength.clamp(0.0, 1.0)
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
    fn filament_exposure_values() {
        // f/16, 1/125 s, ISO 100 → EV100 14.966 (Filament's physical camera test).
        let ev = ev100_from_settings(16.0, 1.0 / 125.0, 100.0);
        assert!((ev - 14.966).abs() < 1e-3, "{ev}");
        // ISO 400 or f/8 or 1/30 s → ≈ 13; f/22, 1/250 s or ISO 50 → ≈ 16. Nominal stops
        // are rounded (f/22 is 0.92 of a stop from f/16, 1/30 s is 2.06 from 1/125 s):
        // within 0.15 EV.
        for ev in [
            ev100_from_settings(16.0, 1.0 / 125.0, 400.0),
            ev100_from_settings(8.0, 1.0 / 125.0, 100.0),
            ev100_from_settings(16.0, 1.0 / 30.0, 100.0),
        ] {
            assert!((ev - 13.0).abs() < 0.15, "{ev}");
        }
        for ev in [
            ev100_from_settings(22.0, 1.0 / 125.0, 100.0),
            ev100_from_settings(16.0, 1.0 / 250.0, 100.0),
            ev100_from_settings(16.0, 1.0 / 125.0, 50.0),
        ] {
            assert!((ev - 16.0).abs() < 0.15, "{ev}");
        }
        // The camera resolves the same, and compensation moves it by whole stops.
        let cam = Camera {
            exposure: Exposure::Physical,
            ..Camera::default()
        };
        let r = cam.resolve_exposure(None);
        assert!((r.ev100 - 14.966).abs() < 1e-3 && r.notes.is_empty());
        let brighter = Camera {
            exposure_compensation: 1.0,
            ..cam
        }
        .resolve_exposure(None);
        assert!((brighter.multiplier / r.multiplier - 2.0).abs() < 1e-4);
    }

    #[test]
    fn out_of_range_settings_are_clamped_and_reported() {
        let cam = Camera {
            exposure: Exposure::Physical,
            lens: Lens {
                aperture_f_stops: 0.1,
                shutter_s: 1e-7,
                iso: f32::NAN,
                focus_distance_m: 0.0,
                ..Lens::default()
            },
            ..Camera::default()
        };
        let r = cam.resolve_exposure(None);
        assert!(r.ev100.is_finite() && r.multiplier.is_finite() && r.multiplier > 0.0);
        assert!(
            r.notes.iter().any(|n| n.contains("aperture")),
            "{:?}",
            r.notes
        );
        assert!(
            r.notes.iter().any(|n| n.contains("shutter")),
            "{:?}",
            r.notes
        );
        assert!(r.notes.iter().any(|n| n.contains("ISO")), "{:?}", r.notes);
        let (lens, notes) = cam.lens.clamped(0.05);
        assert_eq!(lens.aperture_f_stops, 0.5);
        assert_eq!(lens.shutter_s, 1.0 / 25000.0);
        assert!((lens.focus_distance_m - 0.0505).abs() < 1e-6);
        assert!(notes.iter().any(|n| n.contains("focus")));
        // Auto exposure starts from its initial EV100, then follows the meter.
        let auto = Camera {
            exposure: Exposure::Auto(AutoExposure::default()),
            ..Camera::default()
        };
        assert!((auto.resolve_exposure(None).ev100 - 9.7).abs() < 1e-6);
        assert!((auto.resolve_exposure(Some(12.0)).ev100 - 12.0).abs() < 1e-6);
        assert!((metered_ev100(12.5) - 6.643_856).abs() < 1e-4);
    }

    #[test]
    fn circle_of_confusion_is_zero_at_focus_and_grows_away() {
        let (f, n) = (0.05f32, 2.0f32);
        let a = f / n;
        assert_eq!(circle_of_confusion(5.0, 5.0, f, a), 0.0);
        let mut last = 0.0f32;
        for i in 1..200 {
            let z = 5.0 + i as f32 * 0.25;
            let c = circle_of_confusion(z, 5.0, f, a);
            assert!(c > last, "behind: {z} → {c}");
            last = c;
        }
        let mut last = 0.0f32;
        for i in 1..49 {
            let z = 5.0 - i as f32 * 0.1;
            let c = circle_of_confusion(z, 5.0, f, a);
            assert!(c < 0.0 && c.abs() > last.abs(), "in front: {z} → {c}");
            last = c;
        }
        // Known value: z = 10, S = 5: A f (z − S) / (z (S − f)) = 0.025·0.05·5/(10·4.95).
        let c = circle_of_confusion(10.0, 5.0, f, a);
        assert!((c - 0.025 * 0.05 * 5.0 / (10.0 * 4.95)).abs() < 1e-9);
        // Focus at infinity, at the focal length, at 0, depth 0: finite.
        for (z, s) in [
            (10.0, f32::INFINITY),
            (10.0, f),
            (10.0, 0.0),
            (0.0, 5.0),
            (1e9, 5.0),
        ] {
            assert!(circle_of_confusion(z, s, f, a).is_finite(), "{z} {s}");
        }
        assert!((circle_of_confusion(10.0, f32::INFINITY, f, a) + a * f / 10.0).abs() < 1e-9);
    }

    #[test]
    fn natural_vignetting() {
        assert_eq!(vignetting(0.0, 1.0), 1.0);
        // 45° off axis: cos⁴ = 0.25.
        assert!((vignetting(1.0, 1.0) - 0.25).abs() < 1e-6);
        assert!((vignetting(1.0, 0.5) - 0.625).abs() < 1e-6);
        assert_eq!(vignetting(1.0, 0.0), 1.0);
        let lens = Lens::default();
        // 50 mm on full frame: 27° vertical field of view.
        assert!((lens.fov_for_focal_length(50.0).to_degrees() - 26.99).abs() < 0.01);
        assert!((lens.focal_length_m(lens.fov_for_focal_length(50.0)) - 0.05).abs() < 1e-6);
    }

    #[test]
    fn projection_shift_moves_the_frustum_in_tangent_units() {
        let shifted = Projection {
            shift: Vec2::new(0.1, -0.05),
            ..Projection::default()
        };
        let (p, q) = (Projection::default().matrix(1.5), shifted.matrix(1.5));
        // A point on the shifted axis (tangents 0.1, −0.05) lands at the centre.
        for z in [-0.5f32, -3.0, -40.0] {
            let c = q.project_point3(Vec3::new(0.1 * -z, -0.05 * -z, z));
            assert!(c.x.abs() < 1e-5 && c.y.abs() < 1e-5, "{c}");
            // Depth is unchanged.
            let d = p.project_point3(Vec3::new(0.0, 0.0, z)).z;
            assert!((c.z - d).abs() < 1e-6);
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
            shift: Vec2::NAN,
        };
        assert!(bad.matrix(0.0).is_finite());
    }
}

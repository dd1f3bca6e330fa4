//! Depth of field by accumulation (Haeberli & Akeley 1990, "The Accumulation Buffer"):
//! the scene rendered without the DoF pass from points spread over the thin lens's
//! aperture disk, each view's frustum shifted so that the focus plane stays where it was,
//! and averaged. Up to the sample count this is exactly the thin-lens model of
//! docs/src/formulas.md#thin-lens-depth-of-field, with correct occlusion at every edge: the ground truth that the
//! gather in `shaders/dof.wgsl` approximates.

use crate::app::App;
use crate::error::{Error, Result};
use crate::scene::{Camera, Exposure, Transform};
use crate::shading::ibl::hammersley;
use bevy_ecs::prelude::*;
use glam::{Vec2, Vec3};

/// Shirley & Chiu's concentric map of the unit square onto the unit disk (1997, "A
/// Low Distortion Map Between Disk and Square"): area-preserving, so a stratified square
/// stays stratified on the aperture.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let p = u * 2.0 - Vec2::ONE;
    if p == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, theta) = if p.x.abs() > p.y.abs() {
        (p.x, quarter * (p.y / p.x))
    } else {
        (p.y, 2.0 * quarter - quarter * (p.x / p.y))
    };
    Vec2::new(theta.cos(), theta.sin()) * r
}

/// Renders the active camera's view of `size` pixels as the average of `samples` views
/// from Hammersley points on its aperture disk (diameter f/N, m) with the DoF pass off,
/// at the exposure of the camera's current settings (automatic exposure is frozen at
/// its present EV100). Returns the exposed linear HDR image; the camera is restored.
/// `progress(done, samples)` is called after every view.
///
/// The lens offset is applied to the camera's local translation along its own axes, so a
/// camera under a scaled parent moves by the parent's scale too.
pub fn render_thin_lens_reference(
    app: &mut App,
    size: (u32, u32),
    samples: u32,
    mut progress: impl FnMut(u32, u32),
) -> Result<image::Rgba32FImage> {
    if samples == 0 {
        return Err(Error::Scene(
            "the thin-lens reference needs at least one sample".into(),
        ));
    }
    let metered = app.metered_ev100();
    let world = app.world_mut();
    let (entity, camera, transform) = world
        .query::<(Entity, &Camera, &Transform)>()
        .iter(world)
        .filter(|(_, c, _)| c.active)
        .min_by_key(|(e, _, _)| *e)
        .map(|(e, c, t)| (e, *c, *t))
        .ok_or_else(|| Error::Scene("no active camera".into()))?;
    let focal_length_m = camera.lens.focal_length_m(camera.projection.fov_y_rad);
    let (lens, _) = camera.lens.clamped(focal_length_m);
    let radius_m = focal_length_m / lens.aperture_f_stops * 0.5;
    let focus_m = lens.focus_distance_m;
    let exposure = camera.resolve_exposure(metered).multiplier;

    let mut sum: Option<image::Rgba32FImage> = None;
    let mut result = Ok(());
    for i in 0..samples {
        let offset = concentric_disk(hammersley(i, samples)) * radius_m;
        let mut view = camera;
        view.exposure = Exposure::Linear(exposure);
        view.exposure_compensation = 0.0;
        view.depth_of_field = None;
        // Moving the eye by u keeps the focus plane still if the frustum shifts by −u/S.
        view.projection.shift = camera.projection.shift
            - if focus_m.is_finite() {
                offset / focus_m
            } else {
                Vec2::ZERO
            };
        let moved = Transform {
            translation: transform.translation + transform.rotation * Vec3::from((offset, 0.0)),
            ..transform
        };
        app.world_mut().entity_mut(entity).insert((view, moved));
        let frame = app.render_headless(size).and_then(|_| app.read_hdr_image());
        match frame {
            Ok(image) => match sum.as_mut() {
                Some(s) => s
                    .pixels_mut()
                    .zip(image.pixels())
                    .for_each(|(a, b)| (0..4).for_each(|c| a.0[c] += b.0[c])),
                None => sum = Some(image),
            },
            Err(e) => {
                result = Err(e);
                break;
            }
        }
        progress(i + 1, samples);
    }
    app.world_mut()
        .entity_mut(entity)
        .insert((camera, transform));
    result?;
    let mut image = sum.ok_or_else(|| Error::Scene("no reference view rendered".into()))?;
    let scale = 1.0 / samples as f32;
    image
        .pixels_mut()
        .for_each(|p| p.0.iter_mut().for_each(|c| *c *= scale));
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concentric_disk_fills_the_unit_disk_evenly() {
        let n = 4096;
        let points: Vec<Vec2> = (0..n).map(|i| concentric_disk(hammersley(i, n))).collect();
        assert!(points.iter().all(|p| p.length() <= 1.0 + 1e-6));
        // Area-preserving: the fraction inside radius 0.5 is 1/4, the mean is the centre.
        let inner = points.iter().filter(|p| p.length() < 0.5).count() as f32 / n as f32;
        assert!((inner - 0.25).abs() < 0.01, "{inner}");
        let mean = points.iter().copied().sum::<Vec2>() / n as f32;
        assert!(mean.length() < 0.01, "{mean}");
        assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
        assert!((concentric_disk(Vec2::new(1.0, 0.5)) - Vec2::X).length() < 1e-6);
    }
}

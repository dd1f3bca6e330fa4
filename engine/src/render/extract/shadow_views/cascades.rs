//! Cascaded shadow maps for directional lights: split distances and stable cascade fits.
//!
//! Each cascade covers a slice [near, far] of the camera frustum with the smallest sphere
//! around the slice. The sphere's radius depends only on the slice distances, the FOV and
//! the aspect ratio, not on where the camera looks, so the shadow map's texel size never
//! changes as the camera rotates. The sphere's centre is snapped to whole texels in a
//! light-space basis that does not depend on the camera, so a world point always falls on
//! the same spot within a texel as the camera moves: no shimmering (Valient 2008, "Stable
//! Rendering of Cascaded Shadow Maps", ShaderX6).

use glam::{Mat4, Vec3};

/// Split distances (m) from `near` to `far` for `count` cascades: `count + 1` values.
/// `lambda` blends the uniform (0) and logarithmic (1) schemes — the "practical split
/// scheme" of Zhang et al. 2006, "Parallel-Split Shadow Maps".
pub fn split_distances(near: f32, far: f32, count: u32, lambda: f32) -> Vec<f32> {
    let count = count.clamp(1, 4);
    let near = near.max(1e-4);
    let far = far.max(near * 1.001);
    let lambda = lambda.clamp(0.0, 1.0);
    (0..=count)
        .map(|i| {
            let t = i as f32 / count as f32;
            let log = near * (far / near).powf(t);
            let uniform = near + (far - near) * t;
            lambda * log + (1.0 - lambda) * uniform
        })
        .collect()
}

/// Centre distance along the view axis and radius (m) of the smallest sphere around the
/// slice [near, far] of a frustum whose corners at unit depth lie `k` from the axis
/// (k = √(tan²(fov_x/2) + tan²(fov_y/2))).
pub fn slice_sphere(near: f32, far: f32, k: f32) -> (f32, f32) {
    let center = ((near + far) * (1.0 + k * k) * 0.5).min(far);
    let radius = ((far - center).powi(2) + (far * k).powi(2)).sqrt();
    (center, radius)
}

/// The rotation from world to light space for a light shining along `direction` (from
/// the light towards the scene). Independent of the camera.
pub fn light_rotation(direction: Vec3) -> Mat4 {
    let forward = direction.try_normalize().unwrap_or(Vec3::NEG_Y);
    let up = if forward.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    };
    Mat4::look_to_rh(Vec3::ZERO, forward, up)
}

/// One fitted cascade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CascadeFit {
    /// Clip (orthographic, depth 0 at the side towards the light) from world.
    pub clip_from_world: Mat4,
    /// World size of one shadow-map texel (m).
    pub texel_size: f32,
    /// Depth range of the projection along the light direction (m).
    pub depth_range: f32,
    /// The camera distance at which this cascade ends (m).
    pub far: f32,
}

/// Fits one cascade for the slice [near, far] of a camera at `camera` (world from view)
/// with vertical FOV `fov_y` and `aspect`, for a light shining along `direction`.
/// `casters_towards_light` extends the depth range towards the light (m, in light space
/// along −direction) so that casters outside the slice still cast into it.
#[allow(clippy::too_many_arguments)]
pub fn fit_cascade(
    camera: &Mat4,
    fov_y: f32,
    aspect: f32,
    near: f32,
    far: f32,
    direction: Vec3,
    resolution: u32,
    casters_towards_light: f32,
) -> CascadeFit {
    let tan_y = (fov_y * 0.5).tan();
    let k = (tan_y * tan_y * (1.0 + aspect * aspect)).sqrt();
    let (center_distance, radius) = slice_sphere(near, far, k);
    let forward = (-camera.z_axis.truncate())
        .try_normalize()
        .unwrap_or(Vec3::NEG_Z);
    let center = camera.w_axis.truncate() + forward * center_distance;

    let rotation = light_rotation(direction);
    let resolution = resolution.max(2) & !1;
    let texel = 2.0 * radius / resolution as f32;
    let c = rotation.transform_point3(center);
    let snapped = Vec3::new(
        (c.x / texel).floor() * texel,
        (c.y / texel).floor() * texel,
        c.z,
    );
    // Light space looks down −Z: the side towards the light has the larger z.
    let towards_light = (snapped.z + radius).max(casters_towards_light);
    let away = snapped.z - radius;
    let projection = Mat4::orthographic_rh(
        snapped.x - radius,
        snapped.x + radius,
        snapped.y - radius,
        snapped.y + radius,
        -towards_light,
        -away,
    );
    CascadeFit {
        clip_from_world: projection * rotation,
        texel_size: texel,
        depth_range: towards_light - away,
        far,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn practical_splits() {
        let uniform = split_distances(1.0, 101.0, 4, 0.0);
        assert_eq!(uniform, vec![1.0, 26.0, 51.0, 76.0, 101.0]);
        let log = split_distances(1.0, 100.0, 2, 1.0);
        assert!((log[1] - 10.0).abs() < 1e-4);
        let mixed = split_distances(0.1, 30.0, 3, 0.75);
        assert_eq!(mixed.len(), 4);
        assert!(mixed.windows(2).all(|w| w[1] > w[0]));
        assert!((mixed[3] - 30.0).abs() < 1e-4 && (mixed[0] - 0.1).abs() < 1e-6);
        // Out-of-range counts are clamped to 1..=4.
        assert_eq!(split_distances(1.0, 2.0, 9, 0.5).len(), 5);
        assert_eq!(split_distances(1.0, 2.0, 0, 0.5).len(), 2);
    }

    #[test]
    fn slice_sphere_holds_every_corner() {
        for &(n, f, k) in &[(0.1f32, 10.0f32, 0.5f32), (5.0, 30.0, 1.2), (1.0, 2.0, 3.0)] {
            let (c, r) = slice_sphere(n, f, k);
            for (d, radial) in [(n, n * k), (f, f * k)] {
                let dist = ((d - c).powi(2) + radial * radial).sqrt();
                assert!(
                    dist <= r * (1.0 + 1e-5),
                    "corner at {d} outside: {dist} > {r}"
                );
            }
        }
    }

    fn camera(position: Vec3, rotation: Quat) -> Mat4 {
        Mat4::from_rotation_translation(rotation, position)
    }

    #[test]
    fn cascade_contains_the_slice() {
        let dir = Vec3::new(-1.0, -2.0, -1.0).normalize();
        let cam = camera(Vec3::new(0.0, 1.0, 12.0), Quat::from_rotation_y(0.3));
        let fit = fit_cascade(
            &cam,
            45f32.to_radians(),
            16.0 / 9.0,
            0.1,
            30.0,
            dir,
            2048,
            f32::MIN,
        );
        // Every corner of the slice projects inside the shadow map.
        let tan_y = (22.5f32).to_radians().tan();
        for d in [0.1f32, 30.0] {
            for (sx, sy) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let local = Vec3::new(sx * tan_y * 16.0 / 9.0 * d, sy * tan_y * d, -d);
                let world = cam.transform_point3(local);
                let p = fit.clip_from_world.project_point3(world);
                assert!(
                    p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
                    "{p}"
                );
            }
        }
    }

    #[test]
    fn texel_size_is_unchanged_by_camera_rotation() {
        let dir = Vec3::new(1.0, -3.0, 0.5).normalize();
        let sizes: Vec<f32> = (0..12)
            .map(|i| {
                let cam = camera(
                    Vec3::new(3.0, 2.0, 1.0),
                    Quat::from_euler(
                        glam::EulerRot::YXZ,
                        i as f32 * 0.5,
                        (i as f32 * 0.37).sin(),
                        0.1 * i as f32,
                    ),
                );
                fit_cascade(&cam, 1.0, 1.5, 0.5, 20.0, dir, 1024, f32::MIN).texel_size
            })
            .collect();
        assert!(sizes.iter().all(|s| *s == sizes[0]), "{sizes:?}");
    }

    #[test]
    fn world_points_keep_their_place_within_a_texel_as_the_camera_moves() {
        // The sub-texel position of fixed world points must not depend on the camera
        // (that is what makes shadow edges stand still instead of shimmering).
        let dir = Vec3::new(-0.4, -1.0, -0.3).normalize();
        let res = 1024;
        let points = [
            Vec3::new(0.3, 0.0, -2.0),
            Vec3::new(-1.7, 0.5, 1.1),
            Vec3::new(2.2, -0.3, 0.4),
        ];
        let frac_of = |cam: &Mat4| -> Vec<(f32, f32)> {
            let fit = fit_cascade(cam, 0.9, 1.0, 0.1, 15.0, dir, res, f32::MIN);
            points
                .iter()
                .map(|p| {
                    let ndc = fit.clip_from_world.project_point3(*p);
                    let tx = (ndc.x * 0.5 + 0.5) * res as f32;
                    let ty = (ndc.y * 0.5 + 0.5) * res as f32;
                    (tx - tx.floor(), ty - ty.floor())
                })
                .collect()
        };
        let reference = frac_of(&camera(Vec3::ZERO, Quat::IDENTITY));
        for i in 1..40 {
            let t = i as f32;
            let cam = camera(
                Vec3::new(0.013 * t, 0.007 * t, -0.021 * t),
                Quat::from_euler(glam::EulerRot::YXZ, 0.05 * t, 0.01 * t, 0.0),
            );
            for (a, b) in frac_of(&cam).iter().zip(&reference) {
                // Within float rounding of a texel (1e-2 texel).
                let d = ((a.0 - b.0).abs().min(1.0 - (a.0 - b.0).abs()))
                    .max((a.1 - b.1).abs().min(1.0 - (a.1 - b.1).abs()));
                assert!(d < 1e-2, "step {i}: {a:?} vs {b:?}");
            }
        }
    }

    #[test]
    fn casters_towards_the_light_extend_the_depth_range() {
        let dir = Vec3::NEG_Y;
        let cam = camera(Vec3::new(0.0, 2.0, 5.0), Quat::IDENTITY);
        let plain = fit_cascade(&cam, 1.0, 1.0, 0.1, 10.0, dir, 512, f32::MIN);
        let tall = fit_cascade(&cam, 1.0, 1.0, 0.1, 10.0, dir, 512, 100.0);
        assert!(tall.depth_range > plain.depth_range + 50.0);
        // A caster 100 m up (light space z = 100 for a light looking down) projects inside.
        let p = tall
            .clip_from_world
            .project_point3(Vec3::new(0.0, 100.0, 0.0) + Vec3::new(0.0, 0.0, 0.0));
        assert!((0.0..=1.0).contains(&p.z), "{p}");
    }
}

//! The shadow views of a frame: one per cascade, per spot light, and six per point light,
//! each a clip-from-world matrix, a requested resolution and what the lighting pass needs
//! to bias and filter it.

pub mod cascades;

use crate::scene::{Cascades, ShadowSettings};
use cascades::{fit_cascade, light_rotation, split_distances};
use glam::{Mat4, Vec3, Vec4};

/// Texels of guard band around each cube face: the faces' field of view is widened by
/// this much so that filter kernels near a face's edge stay inside the face.
pub const CUBE_GUARD_TEXELS: f32 = 8.0;

/// One shadow view before atlas placement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowView {
    /// Clip from world: depth 0 nearest the light, 1 farthest.
    pub clip_from_world: Mat4,
    /// Requested side in texels.
    pub resolution: u32,
    /// Orthographic views: world size of a texel (m). Perspective views: world size of a
    /// texel per metre of distance from the light.
    pub texel: f32,
    /// Whether the projection is perspective (spot, cube face) or orthographic (cascade).
    pub perspective: bool,
    /// Perspective: near plane (m). Orthographic: depth range (m).
    pub near_or_depth_range: f32,
    /// Perspective: far plane (m). Orthographic: unused.
    pub far: f32,
    /// Cascades: camera distance (m) where this cascade ends.
    pub cascade_far: f32,
}

/// The camera as the cascades need it.
#[derive(Clone, Copy, Debug)]
pub struct CameraForShadows {
    /// World from view.
    pub world_from_view: Mat4,
    /// Vertical FOV (rad).
    pub fov_y: f32,
    /// Width / height.
    pub aspect: f32,
    /// Near plane (m).
    pub near: f32,
    /// Far plane (m).
    pub far: f32,
}

/// Cascades of a directional light shining along `direction`. `casters` are bounding
/// spheres (centre, radius) of every shadow caster.
pub fn directional_views(
    camera: &CameraForShadows,
    direction: Vec3,
    settings: &ShadowSettings,
    cascades: &Cascades,
    casters: &[(Vec3, f32)],
) -> Vec<ShadowView> {
    let rotation = light_rotation(direction);
    let towards_light = casters
        .iter()
        .map(|(c, r)| rotation.transform_point3(*c).z + r)
        .fold(f32::MIN, f32::max);
    let far = camera
        .far
        .min(cascades.max_distance_m.max(camera.near * 2.0));
    let splits = split_distances(camera.near, far, cascades.count, cascades.split_lambda);
    splits
        .windows(2)
        .map(|w| {
            let fit = fit_cascade(
                &camera.world_from_view,
                camera.fov_y,
                camera.aspect,
                w[0],
                w[1],
                direction,
                settings.resolution,
                towards_light,
            );
            ShadowView {
                clip_from_world: fit.clip_from_world,
                resolution: settings.resolution,
                texel: fit.texel_size,
                perspective: false,
                near_or_depth_range: fit.depth_range,
                far: 0.0,
                cascade_far: w[1],
            }
        })
        .collect()
}

/// Near and far planes (m) for a light at `position` reaching `range_m` among `bounds`.
fn light_depth_range(
    position: Vec3,
    range_m: f32,
    radius_m: f32,
    bounds: &[(Vec3, f32)],
) -> (f32, f32) {
    let scene_far = bounds
        .iter()
        .map(|(c, r)| (*c - position).length() + r)
        .fold(0.0f32, f32::max);
    let far = if range_m.is_finite() && range_m > 0.0 {
        range_m.min(scene_far.max(1e-3))
    } else {
        scene_far
    }
    .max(0.1);
    let near = radius_m.clamp(0.02, 0.5).min(far * 0.01);
    (near, far)
}

fn perspective_view(
    position: Vec3,
    forward: Vec3,
    up: Vec3,
    fov: f32,
    near: f32,
    far: f32,
    resolution: u32,
) -> ShadowView {
    let projection = Mat4::perspective_rh(fov, 1.0, near, far);
    let view = Mat4::look_to_rh(position, forward, up);
    ShadowView {
        clip_from_world: projection * view,
        resolution,
        texel: 2.0 * (fov * 0.5).tan() / resolution as f32,
        perspective: true,
        near_or_depth_range: near,
        far,
        cascade_far: 0.0,
    }
}

/// The perspective view of a spot light at `position` shining along `forward`, covering
/// its outer cone.
pub fn spot_view(
    position: Vec3,
    forward: Vec3,
    outer_angle_rad: f32,
    range_m: f32,
    radius_m: f32,
    settings: &ShadowSettings,
    bounds: &[(Vec3, f32)],
) -> ShadowView {
    let forward = forward.try_normalize().unwrap_or(Vec3::NEG_Y);
    let up = if forward.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    };
    let outer = if outer_angle_rad.is_finite() {
        outer_angle_rad
    } else {
        std::f32::consts::FRAC_PI_4
    };
    let fov = (2.0 * outer).clamp(1f32.to_radians(), 170f32.to_radians());
    let (near, far) = light_depth_range(position, range_m, radius_m, bounds);
    perspective_view(position, forward, up, fov, near, far, settings.resolution)
}

/// The six cube faces of a point light, in the order +X, −X, +Y, −Y, +Z, −Z (the shader
/// picks a face by the major axis of the direction from the light).
pub fn point_views(
    position: Vec3,
    range_m: f32,
    radius_m: f32,
    settings: &ShadowSettings,
    bounds: &[(Vec3, f32)],
) -> Vec<ShadowView> {
    let (near, far) = light_depth_range(position, range_m, radius_m, bounds);
    let res = settings.resolution.max(64) as f32;
    let fov = 2.0 * (1.0 + 2.0 * CUBE_GUARD_TEXELS / res).atan();
    [
        (Vec3::X, Vec3::NEG_Y),
        (Vec3::NEG_X, Vec3::NEG_Y),
        (Vec3::Y, Vec3::Z),
        (Vec3::NEG_Y, Vec3::NEG_Z),
        (Vec3::Z, Vec3::NEG_Y),
        (Vec3::NEG_Z, Vec3::NEG_Y),
    ]
    .into_iter()
    .map(|(forward, up)| {
        perspective_view(position, forward, up, fov, near, far, settings.resolution)
    })
    .collect()
}

/// The six planes (xyz normal pointing inside, w offset) of a clip-from-world matrix with
/// depth in [0, 1] (Gribb & Hartmann 2001).
pub fn frustum_planes(m: &Mat4) -> [Vec4; 6] {
    let r = [m.row(0), m.row(1), m.row(2), m.row(3)];
    [
        r[3] + r[0],
        r[3] - r[0],
        r[3] + r[1],
        r[3] - r[1],
        r[2],
        r[3] - r[2],
    ]
    .map(|p| {
        let len = p.truncate().length();
        if len > 0.0 { p / len } else { p }
    })
}

/// Whether a sphere touches the frustum.
pub fn sphere_in_frustum(planes: &[Vec4; 6], center: Vec3, radius: f32) -> bool {
    planes
        .iter()
        .all(|p| p.truncate().dot(center) + p.w >= -radius)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(resolution: u32) -> ShadowSettings {
        ShadowSettings {
            resolution,
            ..ShadowSettings::spot()
        }
    }

    #[test]
    fn cube_faces_cover_every_direction_with_a_guard_band() {
        let pos = Vec3::new(1.0, 2.0, 3.0);
        let views = point_views(pos, 10.0, 0.05, &settings(256), &[(Vec3::ZERO, 5.0)]);
        assert_eq!(views.len(), 6);
        // Any direction lands inside the face of its major axis, away from the edge.
        let dirs = [
            Vec3::new(1.0, 0.99, -0.99),
            Vec3::new(-0.2, -1.0, 0.999),
            Vec3::new(0.3, 0.1, 1.0),
        ];
        for d in dirs {
            let a = d.abs();
            let face = if a.x >= a.y && a.x >= a.z {
                if d.x > 0.0 { 0 } else { 1 }
            } else if a.y >= a.z {
                if d.y > 0.0 { 2 } else { 3 }
            } else if d.z > 0.0 {
                4
            } else {
                5
            };
            let p = views[face]
                .clip_from_world
                .project_point3(pos + d.normalize() * 2.0);
            let guard = 2.0 * CUBE_GUARD_TEXELS / 256.0 * 0.9;
            assert!(
                p.x.abs() <= 1.0 - guard && p.y.abs() <= 1.0 - guard,
                "face {face}: {p}"
            );
            assert!((0.0..=1.0).contains(&p.z));
        }
    }

    /// A 512² spot 4 m above the origin pointing down, outer half-angle 0.5 rad.
    fn spot_down() -> ShadowView {
        spot_view(
            Vec3::new(0.0, 4.0, 0.0),
            Vec3::NEG_Y,
            0.5,
            20.0,
            0.05,
            &settings(512),
            &[(Vec3::ZERO, 3.0)],
        )
    }

    #[test]
    fn spot_view_covers_the_cone() {
        let v = spot_down();
        // A point on the outer cone, 3 m below the light, projects inside.
        let p = v
            .clip_from_world
            .project_point3(Vec3::new(3.0 * 0.5f32.tan() * 0.99, 1.0, 0.0));
        assert!(
            p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
            "{p}"
        );
        assert!(v.perspective && v.far <= 20.0 && v.far >= 7.0);
        // Degenerate input stays finite.
        let v = spot_view(
            Vec3::ZERO,
            Vec3::ZERO,
            f32::NAN,
            f32::INFINITY,
            0.0,
            &settings(64),
            &[],
        );
        assert!(v.clip_from_world.is_finite());
    }

    #[test]
    fn frustum_culling() {
        let v = spot_down();
        let planes = frustum_planes(&v.clip_from_world);
        assert!(sphere_in_frustum(&planes, Vec3::ZERO, 0.5));
        assert!(!sphere_in_frustum(&planes, Vec3::new(10.0, 0.0, 0.0), 0.5));
        assert!(!sphere_in_frustum(&planes, Vec3::new(0.0, 10.0, 0.0), 0.5));
        assert!(sphere_in_frustum(&planes, Vec3::new(2.0, 0.0, 0.0), 0.5));
    }

    #[test]
    fn cascades_cover_up_to_the_max_distance() {
        let camera = CameraForShadows {
            world_from_view: Mat4::from_translation(Vec3::new(0.0, 2.0, 10.0)),
            fov_y: 0.8,
            aspect: 1.5,
            near: 0.1,
            far: 100.0,
        };
        let cascades = Cascades {
            count: 3,
            max_distance_m: 40.0,
            ..Cascades::default()
        };
        let views = directional_views(
            &camera,
            Vec3::new(-1.0, -2.0, -1.0),
            &settings(1024),
            &cascades,
            &[(Vec3::ZERO, 2.0)],
        );
        assert_eq!(views.len(), 3);
        assert!((views[2].cascade_far - 40.0).abs() < 1e-3);
        assert!(
            views
                .windows(2)
                .all(|w| w[0].cascade_far < w[1].cascade_far && w[0].texel < w[1].texel)
        );
        assert!(views.iter().all(|v| !v.perspective));
    }
}

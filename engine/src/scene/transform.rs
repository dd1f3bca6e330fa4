//! Local and world transforms, and the system that propagates them down the hierarchy.
//!
//! The hierarchy is `bevy_ecs`'s own relationship: a child carries [`ChildOf`]`(parent)` and
//! the parent gets [`Children`]. Positions are in metres; right-handed, +Y up, and an
//! entity's "forward" is its local −Z (glTF's convention).

use bevy_ecs::hierarchy::{ChildOf, Children};
use bevy_ecs::prelude::*;
use glam::{Mat4, Quat, Vec3};

/// Position (m), orientation and scale of an entity relative to its parent (or the world).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(GlobalTransform)]
pub struct Transform {
    /// Translation in metres.
    pub translation: Vec3,
    /// Orientation.
    pub rotation: Quat,
    /// Non-uniform scale (dimensionless).
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    /// No translation, rotation or scale.
    pub const IDENTITY: Transform = Transform {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };

    /// A translation by (x, y, z) metres.
    pub fn from_xyz(x: f32, y: f32, z: f32) -> Self {
        Transform::from_translation(Vec3::new(x, y, z))
    }

    /// A translation in metres.
    pub fn from_translation(translation: Vec3) -> Self {
        Transform {
            translation,
            ..Transform::IDENTITY
        }
    }

    /// Returns this transform with a uniform or non-uniform scale.
    pub fn with_scale(mut self, scale: Vec3) -> Self {
        self.scale = scale;
        self
    }

    /// Returns this transform with a rotation.
    pub fn with_rotation(mut self, rotation: Quat) -> Self {
        self.rotation = rotation;
        self
    }

    /// Rotates so that the local −Z axis points at `target`, with local +Y as close to
    /// `up` as possible. A target at the entity's own position, or an `up` parallel to
    /// the view direction, keeps a valid (if arbitrary) orientation instead of NaN.
    pub fn looking_at(mut self, target: Vec3, up: Vec3) -> Self {
        let forward = target - self.translation;
        if forward.length_squared() < 1e-12 {
            return self;
        }
        let forward = forward.normalize();
        let mut up = up.normalize_or_zero();
        if up == Vec3::ZERO || forward.cross(up).length_squared() < 1e-8 {
            up = if forward.y.abs() < 0.9 {
                Vec3::Y
            } else {
                Vec3::Z
            };
        }
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        self.rotation = Quat::from_mat3(&glam::Mat3::from_cols(right, up, -forward));
        self
    }

    /// The local-to-parent matrix.
    pub fn to_matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// The local-to-world matrix, written by [`propagate_transforms`]. Read it, don't write it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct GlobalTransform(pub Mat4);

impl Default for GlobalTransform {
    fn default() -> Self {
        GlobalTransform(Mat4::IDENTITY)
    }
}

impl GlobalTransform {
    /// World-space position in metres.
    pub fn translation(&self) -> Vec3 {
        self.0.w_axis.truncate()
    }

    /// World-space forward direction (the local −Z axis), normalised; −Z if degenerate.
    pub fn forward(&self) -> Vec3 {
        (-self.0.z_axis.truncate())
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z)
    }
}

/// Computes every [`GlobalTransform`] from the [`Transform`]s along the `ChildOf`
/// hierarchy. An entity whose parent has no `Transform` is treated as a root.
pub fn propagate_transforms(
    roots: Query<(Entity, Option<&ChildOf>), With<Transform>>,
    mut nodes: Query<(&Transform, &mut GlobalTransform, Option<&Children>)>,
) {
    let mut stack: Vec<(Entity, Mat4)> = roots
        .iter()
        .filter(|(_, parent)| parent.is_none_or(|p| !nodes.contains(p.parent())))
        .map(|(entity, _)| (entity, Mat4::IDENTITY))
        .collect();
    while let Some((entity, parent_matrix)) = stack.pop() {
        let Ok((transform, mut global, children)) = nodes.get_mut(entity) else {
            continue;
        };
        let world = parent_matrix * transform.to_matrix();
        // Written only when it moved, so `Changed<GlobalTransform>` means a move (probe
        // captures restart on it).
        if global.0 != world {
            global.0 = world;
        }
        if let Some(children) = children {
            stack.extend(children.iter().map(|child| (child, world)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_ecs::schedule::Schedule;

    #[test]
    fn children_inherit_parent_transforms() {
        let mut world = World::new();
        let parent = world
            .spawn(Transform::from_xyz(1.0, 0.0, 0.0).with_scale(Vec3::splat(2.0)))
            .id();
        let child = world
            .spawn((Transform::from_xyz(0.0, 1.0, 0.0), ChildOf(parent)))
            .id();
        let grandchild = world
            .spawn((
                Transform::from_xyz(0.0, 0.0, 1.0)
                    .with_rotation(Quat::from_rotation_y(std::f32::consts::FRAC_PI_2)),
                ChildOf(child),
            ))
            .id();
        let lone = world.spawn(Transform::from_xyz(5.0, 5.0, 5.0)).id();
        let mut schedule = Schedule::default();
        schedule.add_systems(propagate_transforms);
        schedule.run(&mut world);

        let pos = |world: &World, e| world.get::<GlobalTransform>(e).map(|g| g.translation());
        assert_eq!(pos(&world, parent), Some(Vec3::new(1.0, 0.0, 0.0)));
        assert_eq!(pos(&world, child), Some(Vec3::new(1.0, 2.0, 0.0)));
        assert!(
            pos(&world, grandchild).is_some_and(|p| p.abs_diff_eq(Vec3::new(1.0, 2.0, 2.0), 1e-5))
        );
        assert_eq!(pos(&world, lone), Some(Vec3::new(5.0, 5.0, 5.0)));
        // The grandchild's −Z (forward) is rotated by 90° about Y: −Z → −X.
        let fwd = world
            .get::<GlobalTransform>(grandchild)
            .map(|g| g.forward());
        assert!(fwd.is_some_and(|f| f.abs_diff_eq(Vec3::NEG_X, 1e-5)));

        // Moving the parent moves the whole subtree on the next run.
        if let Some(mut t) = world.get_mut::<Transform>(parent) {
            t.translation.x = -1.0;
        }
        schedule.run(&mut world);
        assert!(
            pos(&world, grandchild).is_some_and(|p| p.abs_diff_eq(Vec3::new(-1.0, 2.0, 2.0), 1e-5))
        );
    }

    #[test]
    fn looking_at_points_forward_at_the_target() {
        let t = Transform::from_xyz(1.0, 2.0, 1.0).looking_at(Vec3::ZERO, Vec3::Y);
        let g = GlobalTransform(t.to_matrix());
        assert!(
            g.forward()
                .abs_diff_eq(-Vec3::new(1.0, 2.0, 1.0).normalize(), 1e-5)
        );
        // Degenerate inputs keep a finite orientation.
        let t = Transform::from_xyz(0.0, 5.0, 0.0).looking_at(Vec3::ZERO, Vec3::Y);
        assert!(t.rotation.is_finite());
        assert!(
            GlobalTransform(t.to_matrix())
                .forward()
                .abs_diff_eq(Vec3::NEG_Y, 1e-5)
        );
        let t = Transform::IDENTITY.looking_at(Vec3::ZERO, Vec3::Y);
        assert_eq!(t.rotation, Quat::IDENTITY);
    }
}

//! The environment's extraction: the first environment entity's image or uniform
//! radiance, its intensity and rotation, and how the background shows it.

use super::extracted_frame::{ExtractedEnvironment, ExtractedFrame, Viewpoint};
use super::values::finite_or;
use crate::scene::{Background, Environment, EnvironmentSource};
use bevy_ecs::prelude::*;
use glam::Vec3;

/// Extracts [`ExtractedFrame::environment`] from the environment entity spawned first
/// (`None` without one), its values clamped: negative or non-finite radiance and
/// intensity to 0, the background blur into 0..1.
pub fn extract_environment(
    environments: Query<(Entity, &Environment)>,
    viewpoint: Res<Viewpoint>,
    mut frame: ResMut<ExtractedFrame>,
) {
    if viewpoint.view().is_none() {
        return;
    }
    frame.environment = environments.iter().min_by_key(|(e, _)| *e).map(|(_, env)| {
        let (image, uniform) = match &env.source {
            EnvironmentSource::Image(img) => (Some(img.clone()), Vec3::ZERO),
            EnvironmentSource::Uniform(c) => (
                None,
                Vec3::new(
                    finite_or(c.x, 0.0),
                    finite_or(c.y, 0.0),
                    finite_or(c.z, 0.0),
                )
                .max(Vec3::ZERO),
            ),
        };
        let (show_background, blur) = match env.background {
            Background::Environment { blur } => (true, finite_or(blur, 0.0).clamp(0.0, 1.0)),
            Background::CameraColor => (false, 0.0),
        };
        ExtractedEnvironment {
            image,
            uniform,
            intensity: finite_or(env.intensity, 0.0).max(0.0),
            rotation: finite_or(env.rotation_y_rad, 0.0),
            show_background,
            background_blur: blur,
        }
    });
}

//! The lights' extraction: every light as the lighting shader reads it, pre-exposed, in
//! the order it loops over them.

use super::extracted_frame::{ExtractedFrame, LightCounts, LightShadow, LightShadows, Viewpoint};
use super::values::{exposed, finite_or};
use crate::render::gpu_types::GpuLight;
use crate::scene::{DirectionalLight, GlobalTransform, PointLight, SpotLight};
use crate::shading::punctual::spot_scale_offset;
use bevy_ecs::prelude::*;

/// Extracts [`ExtractedFrame::lights`] (directional, then point, then spot; within each
/// kind the shadowed ones first, as the lighting shader loops over them with shadow
/// lookups and over the rest without), their counts, and the view's counts. A light's
/// shadow fields are those [`LightShadows`] holds for it.
pub fn extract_lights(
    directional: Query<(Entity, &DirectionalLight, &GlobalTransform)>,
    points: Query<(Entity, &PointLight, &GlobalTransform)>,
    spots: Query<(Entity, &SpotLight, &GlobalTransform)>,
    viewpoint: Res<Viewpoint>,
    shadows: Res<LightShadows>,
    mut frame: ResMut<ExtractedFrame>,
) {
    let Some(view) = viewpoint.view() else {
        return;
    };
    let exposure = view.exposure;
    let shadow = |entity| shadows.0.get(&entity).copied().unwrap_or(LightShadow::NONE);
    let frame = &mut *frame;
    frame.lights.clear();
    let mut counts = LightCounts::default();
    for (entity, light, transform) in &directional {
        let s = shadow(entity);
        let c = exposed(light.color.to_linear_rgb(), light.illuminance_lux, exposure);
        let direction = (-transform.forward()).extend(0.0).into();
        frame.lights.push(gpu_light(
            s,
            [0.0; 4],
            direction,
            [c[0], c[1], c[2], 0.0],
            [0.0; 4],
        ));
        counts.directional += 1;
    }
    for (entity, light, transform) in &points {
        let s = shadow(entity);
        let c = exposed(light.color.to_linear_rgb(), light.candela(), exposure);
        let position = transform.translation().extend(1.0).into();
        let color = [c[0], c[1], c[2], inv_range_squared(light.range_m)];
        frame
            .lights
            .push(gpu_light(s, position, [0.0; 4], color, [0.0; 4]));
        counts.point += 1;
    }
    for (entity, light, transform) in &spots {
        let s = shadow(entity);
        let c = exposed(light.color.to_linear_rgb(), light.candela(), exposure);
        let (scale, offset) = spot_scale_offset(
            finite_or(light.inner_angle_rad, 0.0),
            finite_or(light.outer_angle_rad, 0.0),
        );
        let position = transform.translation().extend(1.0).into();
        let direction = transform.forward().extend(0.0).into();
        let color = [c[0], c[1], c[2], inv_range_squared(light.range_m)];
        let spot = [scale, offset, 0.0, 0.0];
        frame
            .lights
            .push(gpu_light(s, position, direction, color, spot));
        counts.spot += 1;
    }
    let (dir, rest) = frame.lights.split_at_mut(counts.directional as usize);
    let (point, spot) = rest.split_at_mut(counts.point as usize);
    let mut shadowed = [0u32; 3];
    for (k, lights) in [dir, point, spot].into_iter().enumerate() {
        lights.sort_by_key(|l| l.shadow[0] < 0.0);
        shadowed[k] = lights.iter().filter(|l| l.shadow[0] >= 0.0).count() as u32;
    }
    frame.shadowed_counts = shadowed;
    frame.light_counts = counts;
    frame.view.light_counts = [
        counts.directional,
        counts.point,
        counts.spot,
        counts.total(),
    ];
    frame.view.shadowed_counts = [shadowed[0], shadowed[1], shadowed[2], 0];
}

/// `1 / range²` (m⁻²) of a light's range: 0 (unbounded) for an infinite or NaN range,
/// and that of a 1 µm range for a zero or negative one, which reaches nothing.
fn inv_range_squared(range_m: f32) -> f32 {
    if range_m.is_finite() && range_m > 0.0 {
        1.0 / (range_m * range_m)
    } else if range_m.is_finite() {
        1.0 / (1e-6 * 1e-6)
    } else {
        0.0
    }
}

/// The GPU record of one light: its position (w = 1) or none, the direction it shines
/// along (w = 0) or none, its exposed colour with 1/range² (m⁻²) in w, the spot cone's
/// scale and offset, and its shadow `s`.
fn gpu_light(
    s: LightShadow,
    position: [f32; 4],
    direction: [f32; 4],
    color_inv_range2: [f32; 4],
    spot: [f32; 4],
) -> GpuLight {
    GpuLight {
        position,
        direction,
        color_inv_range2,
        spot,
        shadow: s.shadow,
        cascade_far: s.cascade_far,
        shadow_bias: s.bias,
    }
}

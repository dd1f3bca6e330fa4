//! The shadows' extraction: the shadow views of every light that casts this frame
//! (directional cascades, six cube faces per point light, one view per spot light), and
//! each such light's shadow fields for the light extraction.

use super::extracted_frame::{
    ExtractedFrame, InstanceSpheres, LightShadow, LightShadows, ShadowCounts, Viewpoint,
};
use super::values::finite_or;
use crate::quality::Quality;
use crate::render::extract::shadow_views::{directional_views, point_views, spot_view};
use crate::scene::{
    Cascades, DirectionalLight, GlobalTransform, PointLight, ShadowSettings, SpotLight,
};
use bevy_ecs::prelude::*;
use glam::Vec3;

/// What the shadows' extraction reads of a directional light.
type Directional = (
    Entity,
    &'static DirectionalLight,
    &'static GlobalTransform,
    Option<&'static ShadowSettings>,
    Option<&'static Cascades>,
);

/// Extracts [`ExtractedFrame::shadow_views`] and [`ExtractedFrame::shadow_counts`], in
/// the order the light extraction lists the lights (directional, point, spot), and each
/// casting light's fields into [`LightShadows`]. Nothing casts where shadows are off
/// (`Quality::shadows`), nothing casts a shadow or nothing receives one: the lights that
/// asked for shadows are then counted as skipped.
#[allow(clippy::too_many_arguments)]
pub fn extract_shadow_views(
    directional: Query<Directional>,
    points: Query<(
        Entity,
        &PointLight,
        &GlobalTransform,
        Option<&ShadowSettings>,
    )>,
    spots: Query<(
        Entity,
        &SpotLight,
        &GlobalTransform,
        Option<&ShadowSettings>,
    )>,
    quality: Res<Quality>,
    viewpoint: Res<Viewpoint>,
    spheres: Res<InstanceSpheres>,
    mut frame: ResMut<ExtractedFrame>,
    mut shadows: ResMut<LightShadows>,
) {
    let Some(view) = viewpoint.view() else {
        return;
    };
    let frame = &mut *frame;
    let caster_spheres: Vec<(Vec3, f32)> =
        frame.casters.iter().map(|c| (c.center, c.radius)).collect();
    frame.shadows_disabled = !quality.shadows;
    let shadows_on = quality.shadows && !frame.casters.is_empty() && frame.receivers > 0;
    frame.shadow_views.clear();
    frame.shadow_counts = ShadowCounts::default();
    shadows.0.clear();
    // Whether a light's shadow is drawn: one that asks for it (or every light, with
    // `all_lights_cast_shadows`) is counted as skipped where nothing can cast.
    let all = quality.all_lights_cast_shadows;
    let drawn = |asked: bool, counts: &mut ShadowCounts| {
        let casts = asked || all;
        counts.skipped += u32::from(casts && !shadows_on);
        casts && shadows_on
    };
    let scale = quality.shadow_resolution_scale;
    for (entity, light, transform, settings, cascades) in &directional {
        if !drawn(light.cast_shadows, &mut frame.shadow_counts) {
            continue;
        }
        let s = sanitized(
            settings
                .copied()
                .unwrap_or_else(ShadowSettings::directional),
            scale,
        );
        let mut c = cascades.copied().unwrap_or_default();
        c.count = c.count.min(quality.max_cascades.max(1));
        let views = directional_views(
            &view.shadow_camera,
            transform.forward(),
            &s,
            &c,
            &caster_spheres,
        );
        let tan_radius = (finite_or(light.angular_diameter_rad, 0.0).clamp(0.0, 0.5) * 0.5).tan();
        let mut fields = fields(frame.shadow_views.len(), views.len(), tan_radius, &s);
        fields.shadow[3] = finite_or(c.blend_fraction, 0.0).clamp(0.0, 0.5);
        for (far, v) in fields.cascade_far.iter_mut().zip(&views) {
            *far = v.cascade_far;
        }
        frame.shadow_views.extend(views);
        frame.shadow_counts.directional += 1;
        shadows.0.insert(entity, fields);
    }
    for (entity, light, transform, settings) in &points {
        if !drawn(light.cast_shadows, &mut frame.shadow_counts) {
            continue;
        }
        let s = sanitized(
            settings.copied().unwrap_or_else(ShadowSettings::point),
            scale,
        );
        let radius = finite_or(light.radius_m, 0.0).max(0.0);
        let position = transform.translation();
        let views = point_views(position, light.range_m, radius, &s, &spheres.0);
        let fields = fields(frame.shadow_views.len(), views.len(), radius, &s);
        frame.shadow_views.extend(views);
        frame.shadow_counts.point += 1;
        shadows.0.insert(entity, fields);
    }
    for (entity, light, transform, settings) in &spots {
        if !drawn(light.cast_shadows, &mut frame.shadow_counts) {
            continue;
        }
        let s = sanitized(
            settings.copied().unwrap_or_else(ShadowSettings::spot),
            scale,
        );
        let radius = finite_or(light.radius_m, 0.0).max(0.0);
        let view = spot_view(
            transform.translation(),
            transform.forward(),
            light.outer_angle_rad,
            light.range_m,
            radius,
            &s,
            &spheres.0,
        );
        let fields = fields(frame.shadow_views.len(), 1, radius, &s);
        frame.shadow_views.push(view);
        frame.shadow_counts.spot += 1;
        shadows.0.insert(entity, fields);
    }
}

/// Shadow settings with out-of-range values clamped (resolution × `scale` into 64..=8192,
/// biases ≥ 0).
fn sanitized(s: ShadowSettings, scale: f32) -> ShadowSettings {
    let bias = |b: f32| {
        if b.is_finite() {
            b.clamp(0.0, 100.0)
        } else {
            1.0
        }
    };
    ShadowSettings {
        resolution: (s.resolution as f32 * finite_or(scale, 1.0).clamp(0.0, 64.0))
            .round()
            .clamp(64.0, 8192.0) as u32,
        depth_bias: bias(s.depth_bias),
        slope_bias: bias(s.slope_bias),
        normal_bias: bias(s.normal_bias),
    }
}

/// The fields of a light whose `views` shadow views start at `first`, with a source of
/// `size` (tan of the angular radius, or radius in m) and the biases of `s`.
fn fields(first: usize, views: usize, size: f32, s: &ShadowSettings) -> LightShadow {
    LightShadow {
        shadow: [
            first as f32,
            views as f32,
            finite_or(size, 0.0).max(0.0),
            0.0,
        ],
        bias: [s.depth_bias, s.slope_bias, s.normal_bias, 0.0],
        ..LightShadow::NONE
    }
}

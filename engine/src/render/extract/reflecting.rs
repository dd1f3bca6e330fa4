//! Whether the frame has screen-space reflections to trace, for the passes of several
//! stages that take part in them. The G-buffer, the first of them, decides with
//! [`reflections_skip_reason`] (and writes the specular level the reflections read only
//! when they run); the depth pyramid and the reflection pass follow its decision
//! ([`skip_after_gbuffer`]), so the condition is computed once a frame while reflections
//! run. It lives here, beside the extracted frame it reads, so that no stage imports
//! another for it.

use crate::quality::Quality;
use crate::quality::knob::Value;
use crate::quality::knobs::SSR;
use crate::render::device::Gpu;
use crate::render::extract::ExtractedFrame;
use crate::render::graph::slots::GBUFFER_SPECULAR_LEVEL;
use crate::render::graph::{FramePlan, PassId};
use bevy_ecs::prelude::*;

/// Why screen-space reflections are not traced this frame, if they are not: the reflection
/// pass's run condition, which the passes that serve it decide with too (the G-buffer's
/// specular level target, the depth pyramid).
pub fn reflections_skip_reason(world: &World) -> Option<String> {
    let quality = world.resource::<Quality>();
    let ssr = quality.ssr;
    let frame = world.resource::<ExtractedFrame>();
    if !ssr.enabled {
        return Some(format!(
            "screen-space reflections are off ({})",
            SSR.setting(Value::Bool(false))
        ));
    }
    if frame.instances.is_empty() {
        return Some("nothing is drawn".into());
    }
    // A roughness map can only lower a material's roughness factor; maps without one
    // (the neutral maps of forward-drawn materials) leave it as it is.
    let smoothest = frame
        .instances
        .iter()
        .map(|i| i.params[1])
        .fold(f32::INFINITY, f32::min);
    let factors_only = frame
        .material_maps
        .iter()
        .all(|m| m.maps.metallic_roughness.is_none());
    if factors_only && smoothest > ssr.max_roughness {
        return Some(format!(
            "no surface smoother than the cutoff (roughness {:.2}; the smoothest is {smoothest:.2})",
            ssr.max_roughness
        ));
    }
    let gpu = world.resource::<Gpu>();
    if !gpu
        .adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::COMPUTE_SHADERS)
    {
        return Some("the adapter has no compute shaders to build the depth pyramid".into());
    }
    // The G-buffer's three targets, the motion vectors and the specular level.
    if quality.aa.temporal() && gpu.device.limits().max_color_attachments < 5 {
        return Some(
            "the adapter draws to fewer than 5 targets at once: the G-buffer's 3, the motion \
             vectors and the specular level the reflections read"
                .into(),
        );
    }
    None
}

/// Why the passes after the G-buffer do not serve reflections this frame, if they do not:
/// they run exactly where the G-buffer wrote the specular level (its decision, made with
/// [`reflections_skip_reason`]), and only a skip computes the reason again.
pub fn skip_after_gbuffer(world: &World, plan: &FramePlan) -> Option<String> {
    if plan.writes_optional(PassId::GBuffer, GBUFFER_SPECULAR_LEVEL) {
        return None;
    }
    Some(
        reflections_skip_reason(world)
            .unwrap_or_else(|| "the G-buffer did not write the specular level".into()),
    )
}

//! glTF animations into [`AnimationClip`]s: node translation, rotation, scale and morph
//! target weight channels with `STEP`, `LINEAR` and `CUBICSPLINE` samplers. A channel
//! that cannot be used (bad times, too few values, non-finite values, a node outside the
//! loaded scene, weights for a node whose mesh has no morph targets) is left out with a
//! warning.

use super::gltf_buffers::check_accessor;
use crate::scene::animation::{AnimationClip, Channel, Interpolation, Keyframes};
use bevy_ecs::prelude::Entity;
use glam::{Quat, Vec3};
use gltf::animation::util::ReadOutputs;
use std::collections::HashMap;

/// Every animation of `document` whose channels target nodes in `nodes` (glTF node index
/// → the entity spawned for it); `morph_targets` tells how many morph targets a node
/// entity's weights drive (0: none). Clips without a usable channel are left out.
pub(super) fn read_animations(
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    nodes: &HashMap<usize, Entity>,
    morph_targets: &dyn Fn(Entity) -> usize,
    warnings: &mut Vec<String>,
) -> Vec<AnimationClip> {
    let mut clips = Vec::new();
    for animation in document.animations() {
        let name = animation.name().map_or_else(
            || format!("animation {}", animation.index()),
            str::to_string,
        );
        let mut channels = Vec::new();
        for channel in animation.channels() {
            let what = format!("animation '{name}' channel {}", channel.index());
            match read_channel(&channel, buffers, nodes, morph_targets) {
                Ok(c) => channels.push(c),
                Err(e) => warnings.push(format!("{what}: {e}; left out")),
            }
        }
        if channels.is_empty() {
            continue;
        }
        let duration_s = channels
            .iter()
            .filter_map(|c| c.times_s.last().copied())
            .fold(0.0, f32::max);
        clips.push(AnimationClip {
            name,
            duration_s,
            channels,
        });
    }
    clips
}

fn read_channel(
    channel: &gltf::animation::Channel,
    buffers: &[gltf::buffer::Data],
    nodes: &HashMap<usize, Entity>,
    morph_targets: &dyn Fn(Entity) -> usize,
) -> Result<Channel, String> {
    let node = channel.target().node().index();
    let target = *nodes
        .get(&node)
        .ok_or(format!("node {node} is not in the loaded scene"))?;
    let sampler = channel.sampler();
    check_accessor(&sampler.input(), buffers)?;
    check_accessor(&sampler.output(), buffers)?;
    let reader = channel.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let times_s: Vec<f32> = reader
        .read_inputs()
        .ok_or("its key times cannot be read")?
        .collect();
    if times_s.is_empty() {
        return Err("no keys".into());
    }
    if times_s.iter().any(|t| !t.is_finite() || *t < 0.0) {
        return Err("a key time is negative or not finite".into());
    }
    if times_s.windows(2).any(|w| w[1] <= w[0]) {
        return Err("key times do not increase".into());
    }
    let interpolation = match sampler.interpolation() {
        gltf::animation::Interpolation::Step => Interpolation::Step,
        gltf::animation::Interpolation::Linear => Interpolation::Linear,
        gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let keyframes = match reader.read_outputs().ok_or("its values cannot be read")? {
        ReadOutputs::Translations(v) => Keyframes::Translation(v.map(Vec3::from).collect()),
        ReadOutputs::Scales(v) => Keyframes::Scale(v.map(Vec3::from).collect()),
        ReadOutputs::Rotations(r) => {
            Keyframes::Rotation(r.into_f32().map(Quat::from_array).collect())
        }
        ReadOutputs::MorphTargetWeights(w) => {
            let targets = morph_targets(target);
            if targets == 0 {
                return Err(format!(
                    "morph weights for node {node}, whose mesh has no morph targets"
                ));
            }
            let values: Vec<f32> = w.into_f32().collect();
            if !values.len().is_multiple_of(targets) {
                return Err(format!(
                    "{} weights is not a whole number of values for {targets} morph targets",
                    values.len()
                ));
            }
            Keyframes::Weights { targets, values }
        }
    };
    let count = keyframes.len();
    let finite = keyframes.is_finite();
    let per_key = if interpolation == Interpolation::CubicSpline {
        3
    } else {
        1
    };
    if count != times_s.len() * per_key {
        return Err(format!(
            "{count} values for {} keys ({per_key} per key expected)",
            times_s.len()
        ));
    }
    if !finite {
        return Err("a value is not finite".into());
    }
    Ok(Channel {
        target,
        times_s,
        keyframes,
        interpolation,
    })
}

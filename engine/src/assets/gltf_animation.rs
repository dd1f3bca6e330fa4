//! glTF animations into [`AnimationClip`]s: node translation, rotation and scale
//! channels with `STEP`, `LINEAR` and `CUBICSPLINE` samplers. A channel that cannot be
//! used (bad times, too few values, non-finite values, a node outside the loaded scene)
//! is left out with a warning; morph-target weight channels are left out with one
//! warning per clip (Lumen draws no morph targets yet).

use super::gltf_buffers::check_accessor;
use crate::scene::animation::{AnimationClip, Channel, Interpolation, Keyframes};
use bevy_ecs::prelude::Entity;
use glam::{Quat, Vec3};
use gltf::animation::Property;
use gltf::animation::util::ReadOutputs;
use std::collections::HashMap;

/// Every animation of `document` whose channels target nodes in `nodes` (glTF node index
/// → the entity spawned for it). Clips without a usable channel are left out.
pub(super) fn read_animations(
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    nodes: &HashMap<usize, Entity>,
    warnings: &mut Vec<String>,
) -> Vec<AnimationClip> {
    let mut clips = Vec::new();
    for animation in document.animations() {
        let name = animation.name().map_or_else(
            || format!("animation {}", animation.index()),
            str::to_string,
        );
        let mut channels = Vec::new();
        let mut morph = false;
        for channel in animation.channels() {
            let what = format!("animation '{name}' channel {}", channel.index());
            if channel.target().property() == Property::MorphTargetWeights {
                morph = true;
                continue;
            }
            match read_channel(&channel, buffers, nodes) {
                Ok(c) => channels.push(c),
                Err(e) => warnings.push(format!("{what}: {e}; left out")),
            }
        }
        if morph {
            warnings.push(format!(
                "animation '{name}': morph target weights are not animated (Lumen draws no morph targets)"
            ));
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
        ReadOutputs::MorphTargetWeights(_) => return Err("morph target weights".into()),
    };
    let count = keyframes.len();
    let finite = (0..count).all(|i| keyframes.get(i).is_finite());
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

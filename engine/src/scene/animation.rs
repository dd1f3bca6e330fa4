//! Keyframe animation of node transforms and morph target weights: [`AnimationClip`]s
//! (glTF's animations) played by an [`AnimationPlayer`] component.
//!
//! Sampling follows the glTF 2.0 specification, Appendix C ("Animation Sampler
//! Interpolation Modes"). Between keyframes k and k+1 at times `t_k < t_{k+1}`, with
//! `Δt = t_{k+1} − t_k` and `s = (t − t_k) / Δt`:
//! - `STEP`: `v_k`;
//! - `LINEAR`: `(1 − s) v_k + s v_{k+1}`; rotations by spherical linear interpolation
//!   along the shorter arc (Shoemake 1985, "Animating Rotation with Quaternion Curves");
//! - `CUBICSPLINE`: the cubic Hermite spline
//!   `(2s³ − 3s² + 1) v_k + Δt (s³ − 2s² + s) b_k + (−2s³ + 3s²) v_{k+1} + Δt (s³ − s²) a_{k+1}`,
//!   with `b_k` the out-tangent of key k and `a_{k+1}` the in-tangent of key k+1 (units per
//!   second); a rotation is normalised after.
//!
//! Before the first key a channel holds the first value, after the last the last.
//! Translations are in metres, rotations unit quaternions, scales factors, morph weights
//! unitless (each weight interpolated like a scalar), times seconds.

use crate::scene::deform::MorphWeights;
use crate::scene::transform::Transform;
use crate::time::Time;
use bevy_ecs::prelude::*;
use glam::{Quat, Vec3, Vec4};
use std::ops::{Add, Mul};
use std::sync::Arc;

/// How a channel's values are interpolated between keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the previous key, held.
    Step,
    /// Linear (rotations: spherical linear).
    Linear,
    /// Cubic Hermite spline with per-key in- and out-tangents.
    CubicSpline,
}

/// The values of a channel: one per key, or, for [`Interpolation::CubicSpline`], three
/// per key (in-tangent, value, out-tangent). A morph weight "value" is one weight per
/// target.
#[derive(Clone, Debug, PartialEq)]
pub enum Keyframes {
    /// Node translations (m).
    Translation(Vec<Vec3>),
    /// Node rotations (unit quaternions).
    Rotation(Vec<Quat>),
    /// Node scales.
    Scale(Vec<Vec3>),
    /// Morph target weights: `targets` consecutive weights per value.
    Weights {
        /// Weights per value (the mesh's morph target count, at least 1).
        targets: usize,
        /// Every value's weights, one after the other.
        values: Vec<f32>,
    },
}

impl Keyframes {
    /// How many values are stored.
    pub fn len(&self) -> usize {
        match self {
            Keyframes::Translation(v) | Keyframes::Scale(v) => v.len(),
            Keyframes::Rotation(q) => q.len(),
            Keyframes::Weights { targets, values } => values.len() / (*targets).max(1),
        }
    }

    /// Whether every stored number is finite.
    pub fn is_finite(&self) -> bool {
        match self {
            Keyframes::Translation(v) | Keyframes::Scale(v) => v.iter().all(|v| v.is_finite()),
            Keyframes::Rotation(q) => q.iter().all(|q| q.is_finite()),
            Keyframes::Weights { values, .. } => values.iter().all(|w| w.is_finite()),
        }
    }

    /// Whether no value is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Value `i` of a transform channel as four floats (xyz0 for vectors, xyzw for
    /// quaternions); `i` < `len()`. Weights have no such form: `None`.
    fn get(&self, i: usize) -> Option<Vec4> {
        match self {
            Keyframes::Translation(v) | Keyframes::Scale(v) => Some(v[i].extend(0.0)),
            Keyframes::Rotation(q) => Some(Vec4::from(q[i])),
            Keyframes::Weights { .. } => None,
        }
    }
}

/// One animated property of one entity.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The entity whose [`Transform`] (or [`MorphWeights`]) the channel drives.
    pub target: Entity,
    /// Key times (s), strictly increasing.
    pub times_s: Vec<f32>,
    /// The values at the keys.
    pub keyframes: Keyframes,
    /// How values between keys are found.
    pub interpolation: Interpolation,
}

/// A named set of channels played together.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationClip {
    /// The clip's name (glTF's, or `animation N` when it has none).
    pub name: String,
    /// The last key time of all channels (s).
    pub duration_s: f32,
    /// The animated properties.
    pub channels: Vec<Channel>,
}

/// Plays one of its clips on the entities their channels name. The glTF loader puts one
/// on a file's root entity, playing the first clip, looping, at speed 1.
#[derive(Component, Clone, Debug)]
pub struct AnimationPlayer {
    clips: Vec<Arc<AnimationClip>>,
    current: Option<usize>,
    time_s: f32,
    speed: f32,
    paused: bool,
    looping: bool,
}

impl AnimationPlayer {
    /// A player of `clips` playing the first (if any) from 0 s, looping, at speed 1.
    pub fn new(clips: Vec<Arc<AnimationClip>>) -> AnimationPlayer {
        AnimationPlayer {
            current: (!clips.is_empty()).then_some(0),
            clips,
            time_s: 0.0,
            speed: 1.0,
            paused: false,
            looping: true,
        }
    }

    /// Every clip, in the file's order.
    pub fn clips(&self) -> &[Arc<AnimationClip>] {
        &self.clips
    }

    /// The index of the clip being played, if any.
    pub fn current(&self) -> Option<usize> {
        self.current
    }

    /// The clip's time the next frame shows (s).
    pub fn time_s(&self) -> f32 {
        self.time_s
    }

    /// Whether the clip's time stands still.
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// The playing speed (× real time).
    pub fn speed(&self) -> f32 {
        self.speed
    }

    /// Whether the clip starts over at its end.
    pub fn is_looping(&self) -> bool {
        self.looping
    }

    /// Plays clip `index` from 0 s (unpaused). An index past the clips is an error
    /// naming how many there are.
    pub fn play(&mut self, index: usize) -> Result<(), String> {
        if index >= self.clips.len() {
            return Err(format!(
                "no animation {index}: there are {}",
                self.clips.len()
            ));
        }
        self.current = Some(index);
        self.time_s = 0.0;
        self.paused = false;
        Ok(())
    }

    /// Plays the clip called `name` from 0 s; an unknown name is an error listing the
    /// clips.
    pub fn play_named(&mut self, name: &str) -> Result<(), String> {
        match self.clips.iter().position(|c| c.name == name) {
            Some(i) => self.play(i),
            None => Err(format!(
                "no animation '{name}' (the file has: {})",
                self.clips
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }

    /// Stops the clip's time (the pose stays).
    pub fn pause(&mut self) {
        self.paused = true;
    }

    /// Lets the clip's time run again.
    pub fn resume(&mut self) {
        self.paused = false;
    }

    /// Jumps to `time_s` seconds of the clip (wrapped into it when looping, clamped to it
    /// otherwise; a non-finite time is ignored).
    pub fn seek(&mut self, time_s: f32) {
        if time_s.is_finite() {
            self.time_s = self.wrapped(time_s);
        }
    }

    /// Plays at `speed` times real time (negative plays backwards; non-finite is
    /// ignored).
    pub fn set_speed(&mut self, speed: f32) {
        if speed.is_finite() {
            self.speed = speed;
        }
    }

    /// Whether the clip starts over at its end (or stops on its last pose).
    pub fn set_looping(&mut self, looping: bool) {
        self.looping = looping;
    }

    fn duration_s(&self) -> f32 {
        self.current
            .and_then(|i| self.clips.get(i))
            .map_or(0.0, |c| c.duration_s)
    }

    fn wrapped(&self, t: f32) -> f32 {
        let d = self.duration_s();
        if d <= 0.0 {
            0.0
        } else if self.looping {
            t.rem_euclid(d)
        } else {
            t.clamp(0.0, d)
        }
    }
}

/// The index k of the key interval holding `t` and the position s ∈ [0, 1] in it; `None`
/// before the first key or at or after the last (the channel holds that key's value).
fn interval(times: &[f32], t: f32) -> Option<(usize, f32)> {
    let last = times.len().checked_sub(1)?;
    if last == 0 || t <= times[0] || t >= times[last] {
        return None;
    }
    let k = times
        .partition_point(|&x| x <= t)
        .saturating_sub(1)
        .min(last - 1);
    let dt = times[k + 1] - times[k];
    Some((k, if dt > 0.0 { (t - times[k]) / dt } else { 0.0 }))
}

/// The cubic Hermite spline of the module docs between values `v0` and `v1` with
/// out-tangent `b0` and in-tangent `a1` (per second), at `s` ∈ [0, 1] of an interval of
/// `dt` seconds.
fn hermite<T: Copy + Mul<f32, Output = T> + Add<Output = T>>(
    v0: T,
    b0: T,
    v1: T,
    a1: T,
    s: f32,
    dt: f32,
) -> T {
    let (s2, s3) = (s * s, s * s * s);
    v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
        + b0 * (dt * (s3 - 2.0 * s2 + s))
        + v1 * (-2.0 * s3 + 3.0 * s2)
        + a1 * (dt * (s3 - s2))
}

/// A transform channel's value at `t` seconds, as four floats (xyz for vectors, xyzw for
/// quaternions), by the formulas of the module docs; `None` for a weights channel (see
/// [`sample_weights`]).
pub fn sample(channel: &Channel, t: f32) -> Option<Vec4> {
    let keys = &channel.keyframes;
    let cubic = channel.interpolation == Interpolation::CubicSpline;
    let per_key = if cubic { 3 } else { 1 };
    let times = &channel.times_s;
    if times.is_empty() || keys.len() < times.len() * per_key {
        return None;
    }
    keys.get(0)?;
    let value = |k: usize| {
        keys.get(k * per_key + usize::from(cubic))
            .unwrap_or(Vec4::ZERO)
    };
    let is_rotation = matches!(channel.keyframes, Keyframes::Rotation(_));
    let Some((k, s)) = interval(times, t) else {
        let k = if t <= times[0] { 0 } else { times.len() - 1 };
        return Some(value(k));
    };
    let v = match channel.interpolation {
        Interpolation::Step => value(k),
        Interpolation::Linear if is_rotation => Vec4::from(slerp_short(
            Quat::from_vec4(value(k)),
            Quat::from_vec4(value(k + 1)),
            s,
        )),
        Interpolation::Linear => value(k).lerp(value(k + 1), s),
        Interpolation::CubicSpline => hermite(
            value(k),
            keys.get(k * 3 + 2).unwrap_or(Vec4::ZERO),
            value(k + 1),
            keys.get((k + 1) * 3).unwrap_or(Vec4::ZERO),
            s,
            times[k + 1] - times[k],
        ),
    };
    Some(if is_rotation {
        v.normalize_or(Vec4::W)
    } else {
        v
    })
}

/// A morph weights channel's weights at `t` seconds (one per target), each interpolated
/// as a scalar by the formulas of the module docs; `None` for a transform channel.
pub fn sample_weights(channel: &Channel, t: f32) -> Option<Vec<f32>> {
    let Keyframes::Weights { targets, values } = &channel.keyframes else {
        return None;
    };
    let n = *targets;
    let cubic = channel.interpolation == Interpolation::CubicSpline;
    let per_key = if cubic { 3 } else { 1 };
    let times = &channel.times_s;
    if n == 0 || times.is_empty() || values.len() < times.len() * per_key * n {
        return None;
    }
    // Entry `e` (in keys × per_key) of target `j`.
    let at = |e: usize, j: usize| values[e * n + j];
    let value = |k: usize, j: usize| at(k * per_key + usize::from(cubic), j);
    let Some((k, s)) = interval(times, t) else {
        let k = if t <= times[0] { 0 } else { times.len() - 1 };
        return Some((0..n).map(|j| value(k, j)).collect());
    };
    Some(
        (0..n)
            .map(|j| match channel.interpolation {
                Interpolation::Step => value(k, j),
                Interpolation::Linear => value(k, j) * (1.0 - s) + value(k + 1, j) * s,
                Interpolation::CubicSpline => hermite(
                    value(k, j),
                    at(k * 3 + 2, j),
                    value(k + 1, j),
                    at((k + 1) * 3, j),
                    s,
                    times[k + 1] - times[k],
                ),
            })
            .collect(),
    )
}

/// Spherical linear interpolation from `a` to `b` along the shorter arc (`b` is negated
/// when the two are more than 180° apart as quaternions: −b is the same rotation).
pub fn slerp_short(a: Quat, b: Quat, s: f32) -> Quat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    let cos = a.dot(b).clamp(-1.0, 1.0);
    if cos > 0.9995 {
        return Quat::from_vec4(Vec4::from(a).lerp(Vec4::from(b), s)).normalize();
    }
    let angle = cos.acos();
    let sin = angle.sin();
    let wa = ((1.0 - s) * angle).sin() / sin;
    let wb = (s * angle).sin() / sin;
    Quat::from_vec4(Vec4::from(a) * wa + Vec4::from(b) * wb).normalize()
}

/// Writes `channel`'s value at `t` into `transform`.
fn apply(channel: &Channel, t: f32, transform: &mut Transform) {
    let Some(v) = sample(channel, t) else {
        return;
    };
    if !v.is_finite() {
        return;
    }
    match channel.keyframes {
        Keyframes::Translation(_) => transform.translation = v.truncate(),
        Keyframes::Rotation(_) => transform.rotation = Quat::from_vec4(v),
        Keyframes::Scale(_) => transform.scale = v.truncate(),
        Keyframes::Weights { .. } => {}
    }
}

/// Poses every player's entities at the clip's time, then advances that time by the
/// frame's step × speed (so a frame shows the time a `seek` asked for). Runs in
/// [`crate::app::PostUpdate`], before transforms propagate.
pub fn animate(
    time: Res<Time>,
    mut players: Query<&mut AnimationPlayer>,
    mut transforms: Query<&mut Transform>,
    mut morph_weights: Query<&mut MorphWeights>,
) {
    for mut player in &mut players {
        let Some(clip) = player.current.and_then(|i| player.clips.get(i)).cloned() else {
            continue;
        };
        let t = player.time_s;
        for channel in &clip.channels {
            if let Some(weights) = sample_weights(channel, t) {
                if let Ok(mut morph) = morph_weights.get_mut(channel.target)
                    && weights.iter().all(|w| w.is_finite())
                {
                    let n = weights.len().min(morph.0.len());
                    morph.0[..n].copy_from_slice(&weights[..n]);
                }
            } else if let Ok(mut transform) = transforms.get_mut(channel.target) {
                apply(channel, t, &mut transform);
            }
        }
        if !player.paused {
            let next = t + time.delta_secs() * player.speed;
            player.time_s = player.wrapped(next);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(keyframes: Keyframes, times: &[f32], interpolation: Interpolation) -> Channel {
        Channel {
            target: Entity::PLACEHOLDER,
            times_s: times.to_vec(),
            keyframes,
            interpolation,
        }
    }

    #[test]
    fn the_short_arc_is_taken_whichever_sign_the_keys_have() {
        let a = Quat::from_rotation_y(0.0);
        let b = -Quat::from_rotation_y(0.5);
        let mid = slerp_short(a, b, 0.5);
        assert!(mid.angle_between(Quat::from_rotation_y(0.25)) < 1e-5);
    }

    #[test]
    fn speed_scales_the_clock_and_a_negative_one_plays_backwards() {
        use bevy_ecs::system::RunSystemOnce;
        let clip = AnimationClip {
            name: "c".into(),
            duration_s: 2.0,
            channels: Vec::new(),
        };
        let mut world = World::new();
        let mut time = Time::default();
        time.advance(0.25);
        world.insert_resource(time);
        let mut player = AnimationPlayer::new(vec![Arc::new(clip)]);
        player.set_speed(2.0);
        let entity = world.spawn(player).id();
        let step = |world: &mut World| {
            world.run_system_once(animate).expect("animate runs");
            world
                .get::<AnimationPlayer>(entity)
                .expect("player")
                .time_s()
        };
        // Two 0.25 s frames at twice real time: 1 s of the clip.
        assert_eq!(step(&mut world), 0.5);
        assert_eq!(step(&mut world), 1.0);
        let mut player = world.get_mut::<AnimationPlayer>(entity).expect("player");
        player.set_speed(-1.0);
        player.set_speed(f32::INFINITY);
        assert_eq!(player.speed(), -1.0);
        // Backwards, wrapping past 0 to the clip's end when looping.
        assert_eq!(step(&mut world), 0.75);
        assert_eq!(step(&mut world), 0.5);
        world
            .get_mut::<AnimationPlayer>(entity)
            .expect("player")
            .seek(0.1);
        assert!((step(&mut world) - 1.85).abs() < 1e-6);
        // Not looping, it stops at 0.
        let mut player = world.get_mut::<AnimationPlayer>(entity).expect("player");
        player.set_looping(false);
        player.seek(0.1);
        assert_eq!(step(&mut world), 0.0);
    }

    #[test]
    fn a_player_wraps_when_looping_and_clamps_otherwise() {
        let clip = AnimationClip {
            name: "c".into(),
            duration_s: 2.0,
            channels: Vec::new(),
        };
        let mut p = AnimationPlayer::new(vec![Arc::new(clip)]);
        p.seek(5.0);
        assert_eq!(p.time_s(), 1.0);
        p.set_looping(false);
        p.seek(5.0);
        assert_eq!(p.time_s(), 2.0);
        p.seek(f32::NAN);
        assert_eq!(p.time_s(), 2.0);
        assert!(p.play(1).unwrap_err().contains("there are 1"));
        assert!(
            p.play_named("walk")
                .unwrap_err()
                .contains("the file has: c")
        );
    }

    #[test]
    fn weights_interpolate_per_target() {
        let weights = |values: Vec<f32>| Keyframes::Weights { targets: 2, values };
        let linear = channel(
            weights(vec![0.0, 1.0, 1.0, 0.0]),
            &[0.0, 2.0],
            Interpolation::Linear,
        );
        assert_eq!(sample_weights(&linear, 0.5), Some(vec![0.25, 0.75]));
        assert_eq!(sample_weights(&linear, 3.0), Some(vec![1.0, 0.0]));
        assert_eq!(sample(&linear, 0.5), None);
        let step = channel(
            weights(vec![0.0, 1.0, 1.0, 0.0]),
            &[0.0, 2.0],
            Interpolation::Step,
        );
        assert_eq!(sample_weights(&step, 1.9), Some(vec![0.0, 1.0]));
        // Cubic with zero tangents: the smoothstep 3s² − 2s³, 0.5 at the middle.
        let cubic = channel(
            weights(vec![
                0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
            ]),
            &[0.0, 1.0],
            Interpolation::CubicSpline,
        );
        assert_eq!(sample_weights(&cubic, 0.5), Some(vec![0.5, 0.5]));
        assert_eq!(sample_weights(&cubic, 0.25), Some(vec![0.156_25, 0.843_75]));
    }

    #[test]
    fn scales_and_degenerate_channels_sample_safely() {
        let c = channel(
            Keyframes::Scale(vec![Vec3::ONE, Vec3::splat(3.0)]),
            &[1.0, 1.0],
            Interpolation::Linear,
        );
        // Two keys at the same time: no interval to interpolate in; the first key's
        // value up to it, the last's after.
        assert_eq!(sample(&c, 0.5), Some(Vec4::new(1.0, 1.0, 1.0, 0.0)));
        assert_eq!(sample(&c, 2.0), Some(Vec4::new(3.0, 3.0, 3.0, 0.0)));
        let short = channel(
            Keyframes::Scale(vec![Vec3::ONE]),
            &[0.0, 1.0],
            Interpolation::Linear,
        );
        assert_eq!(sample(&short, 0.5), None, "fewer values than keys");
    }
}

//! [`Time`]: the clock your systems read. [`crate::App`] advances it once per frame, by
//! the real time between frames (the viewer) or by a fixed step (headless apps, 1/60 s
//! unless [`crate::App::set_fixed_delta`] says otherwise), so that a scripted headless
//! sequence gives the same frames on every machine.

use bevy_ecs::prelude::Resource;
use std::time::Instant;

/// The fixed step of a headless app until [`crate::App::set_fixed_delta`] sets another
/// (s).
pub const HEADLESS_DELTA_S: f32 = 1.0 / 60.0;

/// The longest real-time step (s): a frame that took longer (a breakpoint, a window
/// dragged, a shader compiled) advances time by this much, so motion does not jump.
pub const MAX_REAL_DELTA_S: f32 = 0.25;

/// The frame clock, a resource: read it with `Res<Time>` in a system.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Time {
    delta_s: f32,
    elapsed_s: f64,
    frames: u64,
}

impl Time {
    /// Time since the previous frame (s); 0 before the first.
    pub fn delta_secs(&self) -> f32 {
        self.delta_s
    }

    /// Time since the first frame (s), the sum of every delta so far. Kept in `f64` so
    /// that hours of frames still add up to the microsecond.
    pub fn elapsed_secs(&self) -> f64 {
        self.elapsed_s
    }

    /// Frames advanced so far (the first frame is frame 1).
    pub fn frame_count(&self) -> u64 {
        self.frames
    }

    /// Advances the clock by one frame of `delta_s` seconds.
    pub fn advance(&mut self, delta_s: f32) {
        self.delta_s = delta_s;
        self.elapsed_s += f64::from(delta_s);
        self.frames += 1;
    }
}

/// Where [`Time`]'s steps come from.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Clock {
    /// `Some`: every frame lasts this long (s); `None`: real time.
    pub fixed_delta_s: Option<f32>,
    last_tick: Option<Instant>,
}

impl Clock {
    /// A clock of fixed steps of `delta_s` seconds, or of real time (`None`).
    pub fn new(fixed_delta_s: Option<f32>) -> Clock {
        Clock {
            fixed_delta_s,
            last_tick: None,
        }
    }

    /// The step of the frame that starts now (s): the fixed step, or the real time since
    /// the previous tick within [0, [`MAX_REAL_DELTA_S`]] (1/60 s on the first).
    pub fn tick(&mut self) -> f32 {
        let now = Instant::now();
        let real = self.last_tick.map_or(HEADLESS_DELTA_S, |last| {
            (now - last).as_secs_f32().clamp(0.0, MAX_REAL_DELTA_S)
        });
        self.last_tick = Some(now);
        self.fixed_delta_s.unwrap_or(real)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advancing_adds_deltas_and_counts_frames() {
        let mut t = Time::default();
        assert_eq!(
            (t.delta_secs(), t.elapsed_secs(), t.frame_count()),
            (0.0, 0.0, 0)
        );
        for _ in 0..120 {
            t.advance(1.0 / 60.0);
        }
        assert_eq!(t.frame_count(), 120);
        assert!(
            (t.elapsed_secs() - 2.0).abs() < 1e-6,
            "{}",
            t.elapsed_secs()
        );
        assert_eq!(t.delta_secs(), 1.0 / 60.0);
    }

    #[test]
    fn a_fixed_clock_ignores_real_time_and_a_real_one_is_bounded() {
        let mut fixed = Clock::new(Some(0.5));
        assert_eq!(fixed.tick(), 0.5);
        std::thread::sleep(std::time::Duration::from_millis(5));
        assert_eq!(fixed.tick(), 0.5);
        let mut real = Clock::new(None);
        assert_eq!(real.tick(), HEADLESS_DELTA_S);
        std::thread::sleep(std::time::Duration::from_millis(5));
        let d = real.tick();
        assert!((0.005..=MAX_REAL_DELTA_S).contains(&d), "{d}");
    }
}

//! The renders that make one image.
//!
//! Most images are one render. Two anti-aliasing methods make an image of several:
//! - `--accumulate N` renders the frame N times, each jittered inside the pixel
//!   ([`Jitter::halton`]), and the accumulate pass averages them ([`SubFrame`]);
//! - TAA blends each render with its reprojected history ([`TaaState`]). A viewer renders
//!   one jittered frame per call (progressive); a still image converges from a fresh
//!   history in one call, over one jitter period ([`TAA_JITTER_PERIOD`]).
//!
//! [`Renders`] owns that schedule: the app asks it how many renders an image takes and
//! lets it set each one up and take stock after it, without knowing why.

use crate::quality::{MAX_ACCUMULATE, Quality};
use crate::render::extract::ExtractedFrame;
use crate::render::frame::FrameDelta;
use crate::render::jitter::Jitter;
use crate::render::post::antialias::accumulate::SubFrame;
use crate::render::post::antialias::taa::{TAA_JITTER_PERIOD, TaaState, history_change};
use bevy_ecs::prelude::*;

/// The renders of one image and the TAA history they carry.
#[derive(Debug)]
pub struct Renders {
    /// Renders the accumulate pass averages (1: none).
    accumulated: u32,
    /// TAA runs.
    taa: bool,
    /// Renders TAA blends in this call (0 without TAA).
    temporal_frames: u32,
    /// The history's state, carried from render to render.
    state: TaaState,
    /// The output size (pixels).
    size: (u32, u32),
}

impl Renders {
    /// The renders of the next image of `size`: takes the TAA state out of `world` and
    /// resets it where the history cannot carry over (a camera `cut` the app was asked
    /// for, a change in the scene or the settings, a resize, or a still image that
    /// converges from its own history, `progressive` being false).
    pub fn plan(world: &mut World, size: (u32, u32), progressive: bool, cut: bool) -> Renders {
        let aa = world
            .get_resource::<Quality>()
            .map(|q| q.aa)
            .unwrap_or_default();
        let taa = aa.temporal();
        let change = world.run_system_cached(history_change).ok().flatten();
        let mut reset = match (cut, change) {
            (true, _) => Some("camera cut".to_string()),
            (false, Some(why)) => Some(why.to_string()),
            (false, None) => None,
        };
        if taa && !progressive {
            reset = Some("a still image converges from its own history".into());
        }
        let mut state = world.remove_resource::<TaaState>().unwrap_or_default();
        if state.size.is_some_and(|s| s != size) && reset.is_none() {
            reset = Some("resized".into());
        }
        if reset.is_some() || !taa {
            state.frame = 0;
        }
        state.reset = reset;
        Renders {
            accumulated: aa.accumulate.clamp(1, MAX_ACCUMULATE),
            taa,
            temporal_frames: match (taa, progressive) {
                (false, _) => 0,
                (true, true) => 1,
                (true, false) => TAA_JITTER_PERIOD,
            },
            state,
            size,
        }
    }

    /// How many renders the image takes.
    pub fn count(&self) -> u32 {
        self.accumulated.max(self.temporal_frames)
    }

    /// Renders the accumulate pass averages (1: none).
    pub fn accumulated(&self) -> u32 {
        self.accumulated
    }

    /// Renders TAA blends in this call (0 without TAA).
    pub fn temporal_frames(&self) -> u32 {
        self.temporal_frames
    }

    /// Sets render `index` up: its sub-frame, its jitter and the history's state.
    /// Automatic exposure adapts once per image, not once per render: renders after the
    /// first see no time pass.
    pub fn begin(&self, world: &mut World, index: u32) {
        let (taa, count) = (self.taa, self.accumulated);
        world.insert_resource(SubFrame {
            index: if taa { 0 } else { index },
            count: if taa { 1 } else { count },
        });
        world.insert_resource(if count > 1 {
            Jitter::halton(index)
        } else if taa {
            Jitter::halton(self.state.frame % TAA_JITTER_PERIOD)
        } else {
            Jitter::default()
        });
        world.insert_resource(self.state.clone());
        if index > 0 {
            world.insert_resource(FrameDelta(0.0));
        }
    }

    /// Takes stock after a render: the history has one more frame, at this size and
    /// exposure.
    pub fn end(&mut self, world: &World) {
        let state = &mut self.state;
        state.frame = if self.taa { state.frame + 1 } else { 0 };
        state.reset = None;
        state.size = Some(self.size);
        state.exposure = world
            .resource::<ExtractedFrame>()
            .camera
            .as_ref()
            .map(|c| c.exposure);
    }

    /// Puts the history's state back into `world` for the next image.
    pub fn finish(self, world: &mut World) {
        world.insert_resource(self.state);
    }
}

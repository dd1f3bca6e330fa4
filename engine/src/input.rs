//! Keyboard and mouse input for your systems: the resources [`Keys`],
//! [`MouseButtons`] and [`Mouse`].
//!
//! Events reach an app through [`crate::App::send_input`]: the viewer sends its window's
//! events, and a test or a headless script can send its own. They are applied at the
//! start of the next [`crate::App::update`], before your systems run, so a key pressed
//! between two updates is "just pressed" during exactly one update. A headless app that
//! is sent nothing sees no key pressed and the cursor outside the window.
//!
//! Key codes name a key's place on a US keyboard, whatever the layout
//! ([`KeyCode::KeyW`] is the key left of `E`), as winit's physical keys do; they are
//! winit's own types.

use bevy_ecs::prelude::{Resource, World};
use glam::Vec2;
use std::collections::HashSet;
use std::hash::Hash;

pub use winit::event::MouseButton;
pub use winit::keyboard::KeyCode;

/// Which buttons of one kind (keys, mouse buttons) are held, and which changed during
/// the last update.
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub struct ButtonInput<T: Copy + Eq + Hash + Send + Sync + 'static> {
    pressed: HashSet<T>,
    just_pressed: HashSet<T>,
    just_released: HashSet<T>,
}

impl<T: Copy + Eq + Hash + Send + Sync + 'static> Default for ButtonInput<T> {
    fn default() -> Self {
        ButtonInput {
            pressed: HashSet::new(),
            just_pressed: HashSet::new(),
            just_released: HashSet::new(),
        }
    }
}

impl<T: Copy + Eq + Hash + Send + Sync + 'static> ButtonInput<T> {
    /// Whether `button` is held down.
    pub fn pressed(&self, button: T) -> bool {
        self.pressed.contains(&button)
    }

    /// Whether `button` went down since the previous update (true during one update).
    pub fn just_pressed(&self, button: T) -> bool {
        self.just_pressed.contains(&button)
    }

    /// Whether `button` came up since the previous update (true during one update).
    pub fn just_released(&self, button: T) -> bool {
        self.just_released.contains(&button)
    }

    /// Whether any of `buttons` is held down.
    pub fn any_pressed(&self, buttons: impl IntoIterator<Item = T>) -> bool {
        buttons.into_iter().any(|b| self.pressed(b))
    }

    /// Every button held down, in no particular order.
    pub fn get_pressed(&self) -> impl Iterator<Item = &T> {
        self.pressed.iter()
    }

    /// Records `button` going down. A repeat of a held button is not a new press.
    pub fn press(&mut self, button: T) {
        if self.pressed.insert(button) {
            self.just_pressed.insert(button);
        }
    }

    /// Records `button` coming up (nothing if it was not held).
    pub fn release(&mut self, button: T) {
        if self.pressed.remove(&button) {
            self.just_released.insert(button);
        }
    }

    /// Releases every held button (the window lost the focus: its key-up events will not
    /// come).
    pub fn release_all(&mut self) {
        let held: Vec<T> = self.pressed.iter().copied().collect();
        for b in held {
            self.release(b);
        }
    }

    /// Forgets what changed: the start of a new update.
    fn clear_changes(&mut self) {
        self.just_pressed.clear();
        self.just_released.clear();
    }
}

/// The keyboard, by physical key.
pub type Keys = ButtonInput<KeyCode>;

/// The mouse buttons.
pub type MouseButtons = ButtonInput<MouseButton>;

/// The mouse pointer: where it is and how it moved during the last update.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct Mouse {
    /// Cursor position in physical pixels from the window's top-left corner; `None`
    /// while it is outside the window (and in a headless app that was sent none).
    pub position: Option<Vec2>,
    /// How far the cursor moved since the previous update (physical pixels, +y down).
    pub motion: Vec2,
    /// Wheel turns since the previous update, in lines (+y away from the user).
    pub wheel: Vec2,
}

/// One input event, as [`crate::App::send_input`] takes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InputEvent {
    /// A key went down (`pressed`) or came up.
    Key {
        /// The physical key.
        code: KeyCode,
        /// Down (true) or up.
        pressed: bool,
    },
    /// A mouse button went down (`pressed`) or came up.
    MouseButton {
        /// The button.
        button: MouseButton,
        /// Down (true) or up.
        pressed: bool,
    },
    /// The cursor moved to this position (physical pixels from the top-left corner).
    CursorMoved(Vec2),
    /// The cursor left the window.
    CursorLeft,
    /// The wheel turned by this many lines.
    Wheel(Vec2),
    /// The window lost the keyboard focus: every held key and button is released.
    FocusLost,
}

/// Events sent since the last update, applied by the next.
#[derive(Resource, Clone, Debug, Default)]
pub(crate) struct PendingInput(pub Vec<InputEvent>);

/// Starts a new update of `world`'s input resources: applies the [`PendingInput`].
pub(crate) fn apply_pending(world: &mut World) {
    let events = std::mem::take(&mut world.resource_mut::<PendingInput>().0);
    let mut keys = world.remove_resource::<Keys>().unwrap_or_default();
    let mut buttons = world.remove_resource::<MouseButtons>().unwrap_or_default();
    let mut mouse = world.remove_resource::<Mouse>().unwrap_or_default();
    apply(events, &mut keys, &mut buttons, &mut mouse);
    world.insert_resource(keys);
    world.insert_resource(buttons);
    world.insert_resource(mouse);
}

/// Starts a new update: forgets the last update's changes, then applies `events` in order.
fn apply(events: Vec<InputEvent>, keys: &mut Keys, buttons: &mut MouseButtons, mouse: &mut Mouse) {
    keys.clear_changes();
    buttons.clear_changes();
    mouse.motion = Vec2::ZERO;
    mouse.wheel = Vec2::ZERO;
    for e in events {
        match e {
            InputEvent::Key {
                code,
                pressed: true,
            } => keys.press(code),
            InputEvent::Key {
                code,
                pressed: false,
            } => keys.release(code),
            InputEvent::MouseButton {
                button,
                pressed: true,
            } => buttons.press(button),
            InputEvent::MouseButton {
                button,
                pressed: false,
            } => buttons.release(button),
            InputEvent::CursorMoved(p) if p.is_finite() => {
                if let Some(old) = mouse.position {
                    mouse.motion += p - old;
                }
                mouse.position = Some(p);
            }
            InputEvent::CursorMoved(_) => {}
            InputEvent::CursorLeft => mouse.position = None,
            InputEvent::Wheel(w) if w.is_finite() => mouse.wheel += w,
            InputEvent::Wheel(_) => {}
            InputEvent::FocusLost => {
                keys.release_all();
                buttons.release_all();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn update(events: &[InputEvent], state: &mut (Keys, MouseButtons, Mouse)) {
        apply(events.to_vec(), &mut state.0, &mut state.1, &mut state.2);
    }

    #[test]
    fn a_press_is_just_pressed_for_one_update_and_held_until_released() {
        let mut s = Default::default();
        let w = KeyCode::KeyW;
        update(
            &[InputEvent::Key {
                code: w,
                pressed: true,
            }],
            &mut s,
        );
        assert!(s.0.pressed(w) && s.0.just_pressed(w) && !s.0.just_released(w));
        update(
            &[InputEvent::Key {
                code: w,
                pressed: true,
            }],
            &mut s,
        );
        assert!(
            s.0.pressed(w) && !s.0.just_pressed(w),
            "a repeat is no new press"
        );
        update(
            &[InputEvent::Key {
                code: w,
                pressed: false,
            }],
            &mut s,
        );
        assert!(!s.0.pressed(w) && s.0.just_released(w));
        update(&[], &mut s);
        assert!(!s.0.just_released(w));
    }

    #[test]
    fn a_tap_between_two_updates_is_seen_as_pressed_and_released() {
        let mut s = Default::default();
        let b = MouseButton::Left;
        update(
            &[
                InputEvent::MouseButton {
                    button: b,
                    pressed: true,
                },
                InputEvent::MouseButton {
                    button: b,
                    pressed: false,
                },
            ],
            &mut s,
        );
        assert!(s.1.just_pressed(b) && s.1.just_released(b) && !s.1.pressed(b));
    }

    #[test]
    fn motion_and_wheel_add_up_within_an_update_and_reset_after() {
        let mut s: (Keys, MouseButtons, Mouse) = Default::default();
        update(&[InputEvent::CursorMoved(Vec2::new(10.0, 10.0))], &mut s);
        assert_eq!(s.2.motion, Vec2::ZERO, "the first position is no motion");
        update(
            &[
                InputEvent::CursorMoved(Vec2::new(13.0, 10.0)),
                InputEvent::CursorMoved(Vec2::new(15.0, 6.0)),
                InputEvent::Wheel(Vec2::new(0.0, 1.0)),
                InputEvent::Wheel(Vec2::new(0.0, 2.0)),
                InputEvent::CursorMoved(Vec2::NAN),
            ],
            &mut s,
        );
        assert_eq!(s.2.position, Some(Vec2::new(15.0, 6.0)));
        assert_eq!(
            (s.2.motion, s.2.wheel),
            (Vec2::new(5.0, -4.0), Vec2::new(0.0, 3.0))
        );
        update(&[InputEvent::CursorLeft], &mut s);
        assert_eq!(
            (s.2.position, s.2.motion, s.2.wheel),
            (None, Vec2::ZERO, Vec2::ZERO)
        );
    }

    #[test]
    fn losing_the_focus_releases_everything_held() {
        let mut s = Default::default();
        update(
            &[
                InputEvent::Key {
                    code: KeyCode::ShiftLeft,
                    pressed: true,
                },
                InputEvent::MouseButton {
                    button: MouseButton::Right,
                    pressed: true,
                },
            ],
            &mut s,
        );
        update(&[InputEvent::FocusLost], &mut s);
        assert!(!s.0.pressed(KeyCode::ShiftLeft) && s.0.just_released(KeyCode::ShiftLeft));
        assert!(!s.1.pressed(MouseButton::Right));
    }
}

//! The viewer's camera controls: an orbit camera around a target and a fly camera.
//!
//! Orbit: drag to turn around the target, scroll to zoom. Fly: drag to look, `W A S D`
//! to move, `Q`/`E` down and up, `Shift` four times faster, scroll to change the speed.
//! `F` switches between them, keeping the view.

use lumen::prelude::*;

/// Which controller drives the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraMode {
    /// Turn around a target point.
    Orbit,
    /// Move freely.
    Fly,
}

/// Keys the fly camera reads, as held down or not.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlyKeys {
    /// `W`
    pub forward: bool,
    /// `S`
    pub back: bool,
    /// `A`
    pub left: bool,
    /// `D`
    pub right: bool,
    /// `E`
    pub up: bool,
    /// `Q`
    pub down: bool,
    /// `Shift`
    pub fast: bool,
}

/// Drives one camera entity from mouse and keyboard.
#[derive(Clone, Debug)]
pub struct CameraControls {
    /// The active controller.
    pub mode: CameraMode,
    /// Orbit target (m).
    pub target: Vec3,
    /// Orbit distance (m).
    pub distance_m: f32,
    /// Camera position (m).
    pub position: Vec3,
    /// Heading around +Y (rad); 0 looks along −Z.
    pub yaw: f32,
    /// Elevation (rad), within ±1.5.
    pub pitch: f32,
    /// Fly speed (m/s).
    pub speed_m_s: f32,
    /// Held keys.
    pub keys: FlyKeys,
    /// Whether the camera moved since [`CameraControls::take_transform`] last returned.
    dirty: bool,
}

const MAX_PITCH: f32 = 1.5;

impl CameraControls {
    /// Controls that start at `transform`, orbiting the point `distance_m` ahead of it.
    pub fn new(transform: &Transform, distance_m: f32) -> CameraControls {
        let forward = transform.rotation * Vec3::NEG_Z;
        let distance_m = if distance_m.is_finite() {
            distance_m.max(0.05)
        } else {
            1.0
        };
        CameraControls {
            mode: CameraMode::Orbit,
            target: transform.translation + forward * distance_m,
            distance_m,
            position: transform.translation,
            yaw: (-forward.x).atan2(-forward.z),
            pitch: forward
                .y
                .clamp(-1.0, 1.0)
                .asin()
                .clamp(-MAX_PITCH, MAX_PITCH),
            speed_m_s: (distance_m * 0.5).clamp(0.1, 100.0),
            keys: FlyKeys::default(),
            dirty: false,
        }
    }

    /// The direction the camera looks along.
    pub fn forward(&self) -> Vec3 {
        Vec3::new(
            -self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            -self.pitch.cos() * self.yaw.cos(),
        )
    }

    /// The camera's transform.
    pub fn transform(&self) -> Transform {
        Transform::from_translation(self.position)
            .looking_at(self.position + self.forward(), Vec3::Y)
    }

    /// Switches orbit ↔ fly without moving the camera.
    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            CameraMode::Orbit => CameraMode::Fly,
            CameraMode::Fly => {
                self.target = self.position + self.forward() * self.distance_m;
                CameraMode::Orbit
            }
        };
    }

    /// A mouse drag of `(dx, dy)` pixels.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        self.yaw -= dx * 0.005;
        // Dragging down looks down: the fly camera tilts, the orbit camera rises.
        self.pitch = (self.pitch - dy * 0.005).clamp(-MAX_PITCH, MAX_PITCH);
        self.place_orbit();
        self.dirty = true;
    }

    /// Scroll by `steps` notches (positive: away from the user).
    pub fn scroll(&mut self, steps: f32) {
        if !steps.is_finite() {
            return;
        }
        match self.mode {
            CameraMode::Orbit => {
                self.distance_m = (self.distance_m * 0.9f32.powf(steps)).clamp(0.05, 1e4);
                self.place_orbit();
                self.dirty = true;
            }
            CameraMode::Fly => {
                self.speed_m_s = (self.speed_m_s * 1.2f32.powf(steps)).clamp(0.01, 1e3)
            }
        }
    }

    /// Advances the fly camera by `dt_s` seconds of held keys.
    pub fn advance(&mut self, dt_s: f32) {
        if self.mode != CameraMode::Fly || !dt_s.is_finite() || dt_s <= 0.0 {
            return;
        }
        let k = self.keys;
        let axis = |pos: bool, neg: bool| f32::from(u8::from(pos)) - f32::from(u8::from(neg));
        let forward = self.forward();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let step = forward * axis(k.forward, k.back)
            + right * axis(k.right, k.left)
            + Vec3::Y * axis(k.up, k.down);
        if step == Vec3::ZERO {
            return;
        }
        let speed = self.speed_m_s * if k.fast { 4.0 } else { 1.0 };
        self.position += step.normalize() * speed * dt_s.min(0.25);
        self.dirty = true;
    }

    /// The new transform if the camera moved since the last call.
    pub fn take_transform(&mut self) -> Option<Transform> {
        std::mem::take(&mut self.dirty).then(|| self.transform())
    }

    fn place_orbit(&mut self) {
        if self.mode == CameraMode::Orbit {
            self.position = self.target - self.forward() * self.distance_m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn starting_keeps_the_camera_where_it_is() {
        let t = Transform::from_xyz(1.0, 2.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y);
        let c = CameraControls::new(&t, 5.477);
        let back = c.transform();
        assert!(close(back.translation, t.translation));
        assert!(close(back.rotation * Vec3::NEG_Z, t.rotation * Vec3::NEG_Z));
        assert!(close(c.target, Vec3::ZERO) || (c.target - Vec3::ZERO).length() < 1e-3);
    }

    #[test]
    fn orbiting_keeps_the_distance_and_looks_at_the_target() {
        let t = Transform::from_xyz(0.0, 0.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y);
        let mut c = CameraControls::new(&t, 4.0);
        c.drag(300.0, -120.0);
        let m = c.take_transform().expect("moved");
        assert!(((m.translation - c.target).length() - 4.0).abs() < 1e-4);
        let look = m.rotation * Vec3::NEG_Z;
        assert!(close(look, (c.target - m.translation).normalize()));
        assert!(c.take_transform().is_none(), "nothing moved since");
        c.scroll(1.0);
        assert!(((c.transform().translation - c.target).length() - 3.6).abs() < 1e-4);
    }

    #[test]
    fn flying_moves_along_the_view_and_switching_keeps_the_view() {
        let t = Transform::from_xyz(0.0, 1.0, 4.0).looking_at(Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
        let mut c = CameraControls::new(&t, 4.0);
        c.toggle_mode();
        assert_eq!(c.mode, CameraMode::Fly);
        c.speed_m_s = 4.0;
        c.keys.forward = true;
        c.advance(0.25);
        assert!(
            close(c.position, Vec3::new(0.0, 1.0, 3.0)),
            "{}",
            c.position
        );
        c.keys = FlyKeys {
            right: true,
            up: true,
            ..FlyKeys::default()
        };
        c.advance(0.25);
        let d = std::f32::consts::FRAC_1_SQRT_2;
        assert!(
            close(c.position, Vec3::new(d, 1.0 + d, 3.0)),
            "{}",
            c.position
        );
        let before = c.transform();
        c.toggle_mode();
        assert_eq!(c.mode, CameraMode::Orbit);
        let after = c.transform();
        assert!(close(before.translation, after.translation));
        assert!(close(
            before.rotation * Vec3::NEG_Z,
            after.rotation * Vec3::NEG_Z
        ));
    }

    #[test]
    fn bad_input_changes_nothing() {
        let t = Transform::from_xyz(0.0, 0.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y);
        let mut c = CameraControls::new(&t, f32::NAN);
        c.drag(f32::NAN, 1.0);
        c.scroll(f32::INFINITY);
        c.advance(f32::NAN);
        assert!(c.transform().translation.is_finite());
        c.drag(0.0, 1e9);
        assert!(c.pitch.abs() <= MAX_PITCH);
    }
}

//! The orbit camera of every perspective view: orbit (left drag), pan (right or middle drag),
//! zoom (wheel) about a focus point; and the pointer's motion over the window each frame,
//! measured once for every view that steers by it.

use bevy::input::mouse::AccumulatedMouseScroll;
use bevy::prelude::*;

/// Orbit state of a perspective camera (Bevy frame, y up).
#[derive(Component, Debug, Clone)]
pub struct OrbitCamera {
    /// The point the camera orbits (Bevy frame).
    pub focus: Vec3,
    /// Radians about the vertical axis.
    pub yaw: f32,
    /// Radians above the ground plane.
    pub pitch: f32,
    /// Distance from the focus (m).
    pub distance: f32,
    /// Keep robot 0's centre of mass in focus (the control window's follow mode).
    pub follow: bool,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera {
            focus: Vec3::new(0.0, 0.05, -0.2),
            yaw: -0.9,
            pitch: 0.55,
            distance: 1.4,
            follow: true,
        }
    }
}

impl OrbitCamera {
    /// Mouse steering: left drag orbits, right or middle drag pans the focus over the
    /// ground, the wheel zooms. `t` is the camera's current transform; returns whether it
    /// panned.
    pub fn steer(
        &mut self,
        t: &Transform,
        buttons: &ButtonInput<MouseButton>,
        drag: Vec2,
        wheel: f32,
    ) -> bool {
        let mut panned = false;
        if buttons.pressed(MouseButton::Left) {
            self.yaw -= drag.x * 0.006;
            self.pitch = (self.pitch + drag.y * 0.006).clamp(-0.2, 1.5);
        } else if buttons.pressed(MouseButton::Right) || buttons.pressed(MouseButton::Middle) {
            let right = t.right().as_vec3();
            let forward = Vec3::new(t.forward().x, 0.0, t.forward().z).normalize_or_zero();
            let k = self.distance * 0.0015;
            self.focus += (-right * drag.x + forward * drag.y) * k;
            panned = true;
        }
        if wheel != 0.0 {
            self.distance = (self.distance * (1.0 - 0.1 * wheel)).clamp(0.05, 50.0);
        }
        panned
    }

    /// The camera transform for this orbit.
    pub fn transform(&self) -> Transform {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        Transform::from_translation(self.focus + dir * self.distance)
            .looking_at(self.focus, Vec3::Y)
    }
}

/// A configuration point (z up) in Bevy's frame (y up).
pub fn to_bevy(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0] as f32, p[2] as f32, -p[1] as f32)
}

/// What the pointer did over the window since the last frame: the cursor's motion (not the
/// device's raw motion, which synthetic and remote input lack) and the wheel.
#[derive(Resource, Debug, Default, Clone, Copy)]
pub struct PointerMotion {
    /// The cursor's position now (None: outside the window).
    pub cursor: Option<Vec2>,
    /// Logical pixels the cursor moved since the last frame.
    pub delta: Vec2,
    /// Wheel lines (or pixels) scrolled since the last frame.
    pub wheel: f32,
}

/// Measures [`PointerMotion`] for this frame.
pub fn measure_pointer(
    windows: Query<&Window, With<bevy::window::PrimaryWindow>>,
    scroll: Res<AccumulatedMouseScroll>,
    mut motion: ResMut<PointerMotion>,
) {
    let cursor = windows.iter().next().and_then(Window::cursor_position);
    let delta = match (motion.cursor, cursor) {
        (Some(a), Some(b)) => b - a,
        _ => Vec2::ZERO,
    };
    *motion = PointerMotion {
        cursor,
        delta,
        wheel: scroll.delta.y,
    };
}

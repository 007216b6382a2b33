//! The viewer's camera: orbit (left drag), pan (right or middle drag), zoom (wheel) about a
//! focus point, and an optional follow mode that keeps the robot's centre of mass in focus.
//! Mouse input over egui panels is left to egui ([`crate::gui::pointer`]).

use crate::gui::pointer::PointerRouting;
use bevy::input::mouse::AccumulatedMouseScroll;
use bevy::prelude::*;

use crate::gui::control::session::SimSession;

/// The viewer camera's orbit as the last frame left it (for scripts' state).
#[derive(Resource, Debug, Default, Clone, Copy)]
pub struct CameraReadout {
    /// Radians about the vertical axis.
    pub yaw: f32,
    /// Radians above the ground plane.
    pub pitch: f32,
}

/// Orbit state of the viewer camera (Bevy frame, y up).
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
    /// Keep robot 0's centre of mass in focus.
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

/// Spawns the viewer camera.
pub fn spawn_camera(mut commands: Commands) {
    let orbit = OrbitCamera::default();
    commands.spawn((
        Name::new("viewer camera"),
        Camera3d::default(),
        orbit.transform(),
        orbit,
    ));
}

/// A configuration point (z up) in Bevy's frame (y up).
pub fn to_bevy(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0] as f32, p[2] as f32, -p[1] as f32)
}

/// The mouse as the camera reads it: its buttons, the window's cursor, the wheel, and
/// whether the pointer is over the scene.
#[derive(bevy::ecs::system::SystemParam)]
pub struct Mouse<'w, 's> {
    buttons: Res<'w, ButtonInput<MouseButton>>,
    windows: Query<'w, 's, &'static Window, With<bevy::window::PrimaryWindow>>,
    scroll: Res<'w, AccumulatedMouseScroll>,
    routing: Res<'w, PointerRouting>,
}

/// Mouse orbit / pan / zoom and follow mode. A drag is the cursor's motion over the window
/// since the last frame (not the device's raw motion, which synthetic and remote input
/// lack).
pub fn orbit_camera(
    mouse: Mouse,
    mut last_cursor: Local<Option<Vec2>>,
    session: NonSend<SimSession>,
    selection: Res<crate::gui::control::picking::Selection>,
    mut cameras: Query<(&mut OrbitCamera, &mut Transform)>,
    mut readout: ResMut<CameraReadout>,
) {
    let cursor = mouse
        .windows
        .iter()
        .next()
        .and_then(Window::cursor_position);
    let moved = match (*last_cursor, cursor) {
        (Some(a), Some(b)) => b - a,
        _ => Vec2::ZERO,
    };
    *last_cursor = cursor;
    for (mut orbit, mut t) in &mut cameras {
        if mouse.routing.scene_gets_pointer() {
            // A left drag on a body moves the body (see picking), not the camera.
            let drag = if selection.dragging && mouse.buttons.pressed(MouseButton::Left) {
                Vec2::ZERO
            } else {
                moved
            };
            if orbit.steer(&t, &mouse.buttons, drag, mouse.scroll.delta.y) {
                orbit.follow = false;
            }
        }
        if orbit.follow
            && let Ok(com) = session.simulator.com(0)
        {
            let target = to_bevy(com);
            // Smooth, so the camera does not shake with the gait.
            orbit.focus = orbit.focus.lerp(target, 0.2);
        }
        *t = orbit.transform();
        *readout = CameraReadout {
            yaw: orbit.yaw,
            pitch: orbit.pitch,
        };
    }
}

/// The viewer's camera: spawned at start, steered by the mouse after the scene moved.
pub struct CameraPlugin;

impl Plugin for CameraPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<CameraReadout>()
            .add_systems(Startup, spawn_camera)
            .add_systems(
                Update,
                orbit_camera.in_set(crate::gui::control::schedule::GuiSystems::Camera),
            );
    }
}

//! The viewer's camera: the shared orbit camera ([`crate::gui::view3d::orbit`]) with a
//! follow mode that keeps the robot's centre of mass in focus.
//! Mouse input over egui panels is left to egui ([`crate::gui::pointer`]).

use bevy::prelude::*;

use crate::gui::control::session::SimSession;
use crate::gui::pointer::PointerRouting;
use crate::gui::view3d::orbit::{OrbitCamera, PointerMotion, to_bevy};

/// The viewer camera's orbit as the last frame left it (for scripts' state).
#[derive(Resource, Debug, Default, Clone, Copy)]
pub struct CameraReadout {
    /// Radians about the vertical axis.
    pub yaw: f32,
    /// Radians above the ground plane.
    pub pitch: f32,
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

/// Mouse orbit / pan / zoom ([`PointerMotion`]) and follow mode.
pub fn orbit_camera(
    motion: Res<PointerMotion>,
    buttons: Res<ButtonInput<MouseButton>>,
    routing: Res<PointerRouting>,
    session: NonSend<SimSession>,
    selection: Res<crate::gui::control::picking::Selection>,
    mut cameras: Query<(&mut OrbitCamera, &mut Transform)>,
    mut readout: ResMut<CameraReadout>,
) {
    for (mut orbit, mut t) in &mut cameras {
        if routing.scene_gets_pointer() {
            // A left drag on a body moves the body (see picking), not the camera.
            let drag = if selection.dragging && buttons.pressed(MouseButton::Left) {
                Vec2::ZERO
            } else {
                motion.delta
            };
            if orbit.steer(&t, &buttons, drag, motion.wheel) {
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

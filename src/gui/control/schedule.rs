//! The order of the control window's per-frame work: the sets every view's plugin puts
//! its systems in, chained once here ([`SchedulePlugin`]).

use bevy::prelude::*;

/// Ordering of the window's per-frame work, in this order each frame.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GuiSystems {
    /// Script commands (tests, screenshots), after the module library's changes.
    Script,
    /// The keyboard's shortcuts.
    Keys,
    /// The pointer's drags of bodies.
    Pointer,
    /// The gamepad's bindings.
    Gamepad,
    /// The real robot's exchange with its servos.
    Robot,
    /// Simulation steps of this frame.
    Simulate,
    /// The scene follows the new state: meshes built, bodies followed, pads coloured.
    Scene,
    /// The camera.
    Camera,
    /// The physics debug drawing (seen from the camera just moved).
    Debug,
    /// What captures the frame (the Record button).
    Capture,
}

/// Chains the [`GuiSystems`] in `Update`.
pub struct SchedulePlugin;

impl Plugin for SchedulePlugin {
    fn build(&self, app: &mut App) {
        app.configure_sets(
            Update,
            (
                GuiSystems::Script,
                GuiSystems::Keys,
                GuiSystems::Pointer,
                GuiSystems::Gamepad,
                GuiSystems::Robot,
                GuiSystems::Simulate,
                GuiSystems::Scene,
                GuiSystems::Camera,
                GuiSystems::Debug,
                GuiSystems::Capture,
            )
                .chain(),
        );
    }
}

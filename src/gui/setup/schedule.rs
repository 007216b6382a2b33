//! The order of the configuration window's per-frame work: the sets its plugins put their
//! systems in, chained once here ([`SetupSchedulePlugin`]).

use bevy::prelude::*;

/// Ordering of the window's per-frame work, in this order each frame.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SetupSystems {
    /// Script commands.
    Script,
    /// The keyboard's shortcuts.
    Keys,
    /// The pointer's clicks and drags on the scene.
    Pointer,
    /// A library item dropped on a view lands.
    Drop,
    /// The scene follows the models.
    Scene,
    /// Cameras and viewports.
    Views,
}

/// Chains the [`SetupSystems`] in `Update`.
pub struct SetupSchedulePlugin;

impl Plugin for SetupSchedulePlugin {
    fn build(&self, app: &mut App) {
        app.configure_sets(
            Update,
            (
                SetupSystems::Script,
                SetupSystems::Keys,
                SetupSystems::Pointer,
                SetupSystems::Drop,
                SetupSystems::Scene,
                SetupSystems::Views,
            )
                .chain(),
        );
    }
}

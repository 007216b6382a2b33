//! The environment editor's keyboard shortcuts (when no text field has the keyboard):
//! Delete removes the selection, Ctrl+Z undoes, Ctrl+Y or Ctrl+Shift+Z redoes.

use bevy::prelude::*;
use bevy_egui::input::EguiWantsInput;

use crate::gui::setup::state::{SetupState, Status};

/// Carries out this frame's shortcuts while an environment is edited.
pub fn shortcuts(
    keys: Res<ButtonInput<KeyCode>>,
    egui: Res<EguiWantsInput>,
    mut state: ResMut<SetupState>,
) {
    if egui.wants_any_keyboard_input() || !state.editing_env() {
        return;
    }
    let ctrl = keys.any_pressed([KeyCode::ControlLeft, KeyCode::ControlRight]);
    let shift = keys.any_pressed([KeyCode::ShiftLeft, KeyCode::ShiftRight]);
    if keys.just_pressed(KeyCode::Delete) {
        if let Err(e) = state.env_mut().delete() {
            state.status = Some(Status::Error(e.to_string()));
        }
    } else if ctrl
        && (keys.just_pressed(KeyCode::KeyY) || (shift && keys.just_pressed(KeyCode::KeyZ)))
    {
        state.env_mut().redo();
    } else if ctrl && keys.just_pressed(KeyCode::KeyZ) {
        state.env_mut().undo();
    }
}

/// The configuration window's keyboard shortcuts.
pub struct SetupKeysPlugin;

impl Plugin for SetupKeysPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            Update,
            shortcuts.in_set(crate::gui::setup::schedule::SetupSystems::Keys),
        );
    }
}

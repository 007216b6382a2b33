//! The environment editor (thesis 4.4.6), alone or as the wizard's environment page: its
//! panels ([`view`]), the mouse on its 3D views ([`mouse`]), its keys and the library items
//! dropped from the panel onto the views (here).

pub mod mouse;
pub mod view;

use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

use crate::gui::setup::state::{EditorDrag, SetupState};
use crate::gui::view3d::picking::GesturesPlugin;

/// The editor's state and systems: the drag in progress, the pointer's gestures on its
/// items, keys and drops read after the window's panels are laid out.
pub struct EditorPlugin;

impl Plugin for EditorPlugin {
    fn build(&self, app: &mut App) {
        use crate::gui::setup::schedule::SetupSystems;
        app.init_resource::<EditorDrag>()
            .add_plugins(GesturesPlugin::<crate::gui::setup::scene::ItemVisual>::default())
            .add_systems(
                Update,
                (
                    mouse::read_gestures.in_set(SetupSystems::Pointer),
                    mouse::apply_drop.in_set(SetupSystems::Drop),
                ),
            )
            .add_systems(
                EguiPrimaryContextPass,
                editor_input.after(crate::gui::setup::draw_ui),
            );
    }
}

/// The editor's keyboard and the library's drops, while an environment is edited.
fn editor_input(mut contexts: EguiContexts, mut state: ResMut<SetupState>) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    if !state.editing_env() {
        return Ok(());
    }
    editor_keys(&ctx, &mut state);
    if let Some(central) = state.central {
        library_drop(&ctx, &mut state, central);
    }
    Ok(())
}

/// The environment editor's keys: Ctrl+Z undo, Ctrl+Y / Ctrl+Shift+Z redo, Delete removes
/// the selection.
fn editor_keys(ctx: &egui::Context, state: &mut SetupState) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    let (undo, redo, delete) = ctx.input(|i| {
        let cmd = i.modifiers.command;
        (
            cmd && !i.modifiers.shift && i.key_pressed(egui::Key::Z),
            cmd && (i.key_pressed(egui::Key::Y)
                || (i.modifiers.shift && i.key_pressed(egui::Key::Z))),
            i.key_pressed(egui::Key::Delete),
        )
    });
    let env = state.env_mut();
    if undo {
        env.undo();
    }
    if redo {
        env.redo();
    }
    if delete && env.selected.is_some() {
        let r = env.delete();
        state.report(r, |_| "deleted".into());
    }
}

/// A library item released over the 3D views is dropped there.
fn library_drop(ctx: &egui::Context, state: &mut SetupState, central: egui::Rect) {
    if let Some(i) = egui::DragAndDrop::payload::<usize>(ctx)
        && ctx.input(|inp| inp.pointer.any_released())
        && let Some(pos) = ctx.input(|inp| inp.pointer.interact_pos())
        && central.contains(pos)
    {
        if let Some(item) = state.library.get(*i).cloned() {
            state.drop = Some((item, Vec2::new(pos.x, pos.y)));
        }
        egui::DragAndDrop::clear_payload(ctx);
    }
}

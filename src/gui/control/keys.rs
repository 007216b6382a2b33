//! The control window's keyboard shortcuts (when no text field has the keyboard):
//!
//! | key | does |
//! |---|---|
//! | Space | start / pause |
//! | R | restart |
//! | F | follow the robot on / off |
//! | D | physics debug view on / off |
//! | V | start / stop recording (the Record button) |

use bevy::prelude::*;
use bevy_egui::input::EguiWantsInput;

use crate::gui::control::debug_view::DebugView;
use crate::gui::control::recorder::Recorder;
use crate::gui::control::session::SimSession;
use crate::gui::view3d::orbit::OrbitCamera;

/// Carries out this frame's shortcuts.
pub fn shortcuts(
    keys: Res<ButtonInput<KeyCode>>,
    egui: Res<EguiWantsInput>,
    mut session: NonSendMut<SimSession>,
    mut debug: ResMut<DebugView>,
    mut recorder: ResMut<Recorder>,
    mut cameras: Query<&mut OrbitCamera>,
) {
    // A text field has the keyboard, or a modifier makes the key a command of another
    // kind (Ctrl+R is not R).
    let modified = [
        KeyCode::ControlLeft,
        KeyCode::ControlRight,
        KeyCode::AltLeft,
        KeyCode::AltRight,
        KeyCode::SuperLeft,
        KeyCode::SuperRight,
    ]
    .iter()
    .any(|k| keys.pressed(*k) || keys.just_released(*k));
    if egui.wants_any_keyboard_input() || modified {
        return;
    }
    if keys.just_pressed(KeyCode::Space) {
        session.running = !session.running;
    }
    if keys.just_pressed(KeyCode::KeyR) {
        session.restart();
    }
    if keys.just_pressed(KeyCode::KeyF) {
        for mut c in &mut cameras {
            c.follow = !c.follow;
        }
    }
    if keys.just_pressed(KeyCode::KeyD) {
        debug.0 = !debug.0;
    }
    if keys.just_pressed(KeyCode::KeyV) {
        if recorder.recording() {
            recorder.stop();
        } else {
            recorder.start(&session.path, None);
        }
    }
}

/// The window's keyboard shortcuts.
pub struct KeysPlugin;

impl Plugin for KeysPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            Update,
            shortcuts.in_set(crate::gui::control::schedule::GuiSystems::Keys),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shortcut system alone on the demo's session, as Bevy's how_to_test_systems.
    fn app() -> App {
        let mut app = App::new();
        let session = SimSession::open(
            std::path::Path::new("configs/demo.simulation.xml"),
            None,
            &crate::control::ModuleRegistry::standard(),
        )
        .unwrap();
        app.insert_non_send(session)
            .init_resource::<ButtonInput<KeyCode>>()
            .init_resource::<EguiWantsInput>()
            .init_resource::<DebugView>()
            .init_resource::<Recorder>()
            .add_systems(Update, shortcuts);
        app.world_mut().spawn(OrbitCamera::default());
        app
    }

    fn press(app: &mut App, key: KeyCode) {
        let mut keys = app.world_mut().resource_mut::<ButtonInput<KeyCode>>();
        keys.release_all();
        keys.clear();
        keys.press(key);
        app.update();
    }

    #[test]
    fn space_starts_and_pauses_r_restarts_f_and_d_toggle() {
        let mut app = app();
        press(&mut app, KeyCode::Space);
        assert!(app.world().non_send::<SimSession>().running);
        app.world_mut()
            .non_send_mut::<SimSession>()
            .simulator
            .run_steps(100);
        press(&mut app, KeyCode::Space);
        assert!(!app.world().non_send::<SimSession>().running);
        press(&mut app, KeyCode::KeyR);
        assert_eq!(app.world().non_send::<SimSession>().steps(), 0, "restarted");
        press(&mut app, KeyCode::KeyF);
        let follow = app
            .world_mut()
            .query::<&OrbitCamera>()
            .single(app.world())
            .unwrap()
            .follow;
        assert!(!follow);
        press(&mut app, KeyCode::KeyD);
        assert!(app.world().resource::<DebugView>().0);
    }
}

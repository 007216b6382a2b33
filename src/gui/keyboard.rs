//! Keys to egui in the order they were typed, each with the modifiers held at that moment.
//!
//! bevy_egui reads the modifier keys once per frame and stamps every key of the frame with
//! that state. At a few frames per second a whole Ctrl+A (Ctrl down, A down, A up, Ctrl
//! up) falls into one frame, the frame's state says "no Ctrl", and egui typed an "a"
//! instead of selecting all (a path typed next then landed mid-string). This replaces
//! bevy_egui's keyboard system with one that follows the modifiers key by key; text, keys
//! and their releases reach egui exactly as bevy_egui would send them otherwise.

use bevy::input::ButtonState;
use bevy::input::keyboard::{Key, KeyboardInput};
use bevy::prelude::*;
use bevy_egui::helpers::{bevy_to_egui_key, bevy_to_egui_physical_key};
use bevy_egui::input::EguiInputEvent;
use bevy_egui::{EguiContextSettings, EguiInputSet, PrimaryEguiContext, egui};

/// The ordered keyboard input, in place of bevy_egui's.
pub struct OrderedKeysPlugin;

impl Plugin for OrderedKeysPlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(
            PreUpdate,
            (take_over_keyboard, write_keys)
                .chain()
                .in_set(EguiInputSet::ReadBevyMessages),
        );
    }
}

/// Turns bevy_egui's own keyboard system off for each new context.
fn take_over_keyboard(mut contexts: Query<&mut EguiContextSettings, Added<EguiContextSettings>>) {
    for mut settings in &mut contexts {
        settings
            .input_system_settings
            .run_write_keyboard_input_messages_system = false;
    }
}

/// Which modifier `key` is, if any.
fn modifier(key: &Key) -> Option<fn(&mut egui::Modifiers, bool)> {
    match key {
        Key::Shift => Some(|m, on| m.shift = on),
        Key::Control => Some(|m, on| {
            m.ctrl = on;
            m.command = on;
        }),
        Key::Alt => Some(|m, on| m.alt = on),
        Key::Super | Key::Meta => Some(|m, on| m.mac_cmd = on),
        _ => None,
    }
}

/// The egui events of one key press or release, given the modifiers held.
fn key_events(message: &KeyboardInput, modifiers: egui::Modifiers) -> Vec<egui::Event> {
    let pressed = message.state == ButtonState::Pressed;
    let mut out = Vec::new();
    // Text only without Ctrl/Cmd (Ctrl+A is a command, not an "a"); AltGr layouts keep it.
    let text_allowed = !modifiers.command || modifiers.alt;
    if pressed && text_allowed {
        match &message.logical_key {
            Key::Character(c) if !c.chars().any(char::is_control) => {
                out.push(egui::Event::Text(c.to_string()));
            }
            Key::Space => out.push(egui::Event::Text(" ".to_string())),
            _ => {}
        }
    }
    let physical_key = bevy_to_egui_physical_key(&message.key_code);
    if let Some(key) = bevy_to_egui_key(&message.logical_key).or(physical_key) {
        out.push(egui::Event::Key {
            key,
            physical_key,
            pressed,
            repeat: message.repeat,
            modifiers,
        });
    }
    out
}

/// Sends this frame's keys to the primary egui context in order, tracking the modifiers
/// from key to key.
fn write_keys(
    mut keys: MessageReader<KeyboardInput>,
    mut held: Local<egui::Modifiers>,
    context: Query<Entity, With<PrimaryEguiContext>>,
    mut out: MessageWriter<EguiInputEvent>,
) {
    let Some(context) = context.iter().next() else {
        keys.clear();
        return;
    };
    for message in keys.read() {
        if let Some(set) = modifier(&message.logical_key) {
            set(&mut held, message.state == ButtonState::Pressed);
        }
        for event in key_events(message, *held) {
            out.write(EguiInputEvent { context, event });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::input::keyboard::KeyCode;

    fn message(code: KeyCode, key: Key, pressed: bool) -> KeyboardInput {
        KeyboardInput {
            key_code: code,
            logical_key: key,
            state: if pressed {
                ButtonState::Pressed
            } else {
                ButtonState::Released
            },
            text: None,
            repeat: false,
            window: Entity::PLACEHOLDER,
        }
    }

    /// A whole Ctrl+A and a typed "b" in one frame.
    #[test]
    fn a_quick_ctrl_a_in_one_frame_is_select_all_not_text() {
        let mut app = App::new();
        app.add_message::<KeyboardInput>()
            .add_message::<EguiInputEvent>()
            .add_systems(Update, write_keys);
        let context = app.world_mut().spawn(PrimaryEguiContext).id();
        let a = || Key::Character("a".into());
        for m in [
            message(KeyCode::ControlLeft, Key::Control, true),
            message(KeyCode::KeyA, a(), true),
            message(KeyCode::KeyA, a(), false),
            message(KeyCode::ControlLeft, Key::Control, false),
            message(KeyCode::KeyB, Key::Character("b".into()), true),
        ] {
            app.world_mut().write_message(m);
        }
        app.update();
        let sent: Vec<egui::Event> = app
            .world_mut()
            .resource_mut::<Messages<EguiInputEvent>>()
            .drain()
            .inspect(|e| assert_eq!(e.context, context))
            .map(|e| e.event)
            .collect();
        let texts: Vec<&str> = sent
            .iter()
            .filter_map(|e| match e {
                egui::Event::Text(t) => Some(t.as_str()),
                _ => None,
            })
            .collect();
        assert_eq!(texts, ["b"], "{sent:?}");
        let select_all = sent.iter().any(|e| {
            matches!(e, egui::Event::Key { key: egui::Key::A, pressed: true, modifiers, .. }
                if modifiers.command)
        });
        assert!(select_all, "{sent:?}");
    }
}

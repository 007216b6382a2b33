//! The gamepad remote (feature `gui`): any gamepad Bevy's gilrs integration sees, as a
//! [`Remote`]. [`read_gamepads`] keeps the list of connected pads and a snapshot of the
//! active one each frame; the control window (or a test) hands the snapshot to a
//! [`crate::remote::RemoteMapper`]. Commands: `rumble STRENGTH [SECONDS]`.

use std::time::Duration;

use bevy::input::gamepad::{
    Gamepad, GamepadAxis, GamepadButton, GamepadRumbleIntensity, GamepadRumbleRequest,
};
use bevy::prelude::*;

use crate::remote::device::{ElementInfo, Remote, RemoteData, RemoteError, gamepad_elements};

/// Axes by the names bindings use.
pub const AXES: [(&str, GamepadAxis); 6] = [
    ("LeftStickX", GamepadAxis::LeftStickX),
    ("LeftStickY", GamepadAxis::LeftStickY),
    ("RightStickX", GamepadAxis::RightStickX),
    ("RightStickY", GamepadAxis::RightStickY),
    ("LeftZ", GamepadAxis::LeftZ),
    ("RightZ", GamepadAxis::RightZ),
];

/// Buttons by the names bindings use.
pub const BUTTONS: [(&str, GamepadButton); 19] = [
    ("South", GamepadButton::South),
    ("East", GamepadButton::East),
    ("North", GamepadButton::North),
    ("West", GamepadButton::West),
    ("C", GamepadButton::C),
    ("Z", GamepadButton::Z),
    ("LeftTrigger", GamepadButton::LeftTrigger),
    ("LeftTrigger2", GamepadButton::LeftTrigger2),
    ("RightTrigger", GamepadButton::RightTrigger),
    ("RightTrigger2", GamepadButton::RightTrigger2),
    ("Select", GamepadButton::Select),
    ("Start", GamepadButton::Start),
    ("Mode", GamepadButton::Mode),
    ("LeftThumb", GamepadButton::LeftThumb),
    ("RightThumb", GamepadButton::RightThumb),
    ("DPadUp", GamepadButton::DPadUp),
    ("DPadDown", GamepadButton::DPadDown),
    ("DPadLeft", GamepadButton::DPadLeft),
    ("DPadRight", GamepadButton::DPadRight),
];

/// Every element's value of one gamepad.
pub fn snapshot(pad: &Gamepad) -> RemoteData {
    let mut d = RemoteData::default();
    for (name, axis) in AXES {
        d.set(name, f64::from(pad.get(axis).unwrap_or(0.0)));
    }
    for (name, button) in BUTTONS {
        d.set(name, if pad.pressed(button) { 1.0 } else { 0.0 });
    }
    d
}

/// The gamepads present and the one used as the remote.
#[derive(Resource, Debug, Default)]
pub struct GamepadRemote {
    /// Connected gamepads: entity and name.
    pub pads: Vec<(Entity, String)>,
    /// The pad read (the first one connected unless chosen).
    pub active: Option<Entity>,
    /// Whether the remote is switched on.
    pub enabled: bool,
    data: RemoteData,
    /// Commands waiting for [`read_gamepads`] (rumble).
    pending: Vec<String>,
}

impl Remote for GamepadRemote {
    fn name(&self) -> String {
        self.active
            .and_then(|a| self.pads.iter().find(|(e, _)| *e == a))
            .map_or_else(|| "no gamepad".into(), |(_, n)| n.clone())
    }

    fn connect(&mut self) -> Result<(), RemoteError> {
        if self.pads.is_empty() {
            return Err(RemoteError::NoDevice("gamepad"));
        }
        self.enabled = true;
        Ok(())
    }

    fn disconnect(&mut self) {
        self.enabled = false;
        self.data = RemoteData::default();
    }

    fn is_connected(&self) -> bool {
        self.enabled && self.active.is_some()
    }

    fn available_elements(&self) -> Vec<ElementInfo> {
        gamepad_elements()
    }

    fn available_commands(&self) -> Vec<String> {
        vec!["rumble".into()]
    }

    fn read_all(&mut self) -> RemoteData {
        if self.is_connected() {
            self.data.clone()
        } else {
            RemoteData::default()
        }
    }

    fn receive_command(&mut self, command: &str) -> Result<(), RemoteError> {
        let mut words = command.split_whitespace();
        match words.next() {
            Some("rumble") => {
                let strength: f32 = words.next().and_then(|w| w.parse().ok()).unwrap_or(1.0);
                if !(0.0..=1.0).contains(&strength) {
                    return Err(RemoteError::BadValue {
                        command: format!("rumble {strength}"),
                        why: "the strength lies in 0..1",
                    });
                }
                self.pending.push(command.to_string());
                Ok(())
            }
            _ => Err(RemoteError::UnknownCommand {
                device: "gamepad".into(),
                command: command.to_string(),
                understands: "rumble STRENGTH [SECONDS]".into(),
            }),
        }
    }
}

/// Updates the pad list and the active pad's snapshot; sends pending rumbles.
pub fn read_gamepads(
    mut remote: ResMut<GamepadRemote>,
    pads: Query<(Entity, &Gamepad, Option<&Name>)>,
    mut rumble: MessageWriter<GamepadRumbleRequest>,
) {
    let list: Vec<(Entity, String)> = pads
        .iter()
        .map(|(e, _, n)| {
            (
                e,
                n.map_or_else(|| format!("gamepad {e}"), |n| n.to_string()),
            )
        })
        .collect();
    if remote.pads != list {
        remote.pads = list;
    }
    if remote.active.is_none_or(|a| pads.get(a).is_err()) {
        remote.active = remote.pads.first().map(|(e, _)| *e);
    }
    let data = remote
        .active
        .and_then(|a| pads.get(a).ok())
        .map(|(_, pad, _)| snapshot(pad))
        .unwrap_or_default();
    remote.data = data;
    let pending = std::mem::take(&mut remote.pending);
    if let Some(gamepad) = remote.active {
        for c in pending {
            let mut w = c.split_whitespace().skip(1);
            let strength: f32 = w.next().and_then(|v| v.parse().ok()).unwrap_or(1.0);
            let seconds: f32 = w.next().and_then(|v| v.parse().ok()).unwrap_or(0.3);
            rumble.write(GamepadRumbleRequest::Add {
                duration: Duration::from_secs_f32(seconds.clamp(0.0, 10.0)),
                intensity: GamepadRumbleIntensity {
                    strong_motor: strength,
                    weak_motor: strength,
                },
                gamepad,
            });
        }
    }
}

/// Reads gamepads into [`GamepadRemote`] before `Update` (after Bevy's input systems).
pub struct GamepadRemotePlugin;

impl Plugin for GamepadRemotePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<GamepadRemote>()
            .add_message::<GamepadRumbleRequest>()
            .add_systems(PreUpdate, read_gamepads.after(bevy::input::InputSystems));
    }
}

//! The remote interface (thesis listing A.5): a device is connected and disconnected,
//! lists the elements it has (axes, buttons) and the commands it understands, hands a
//! snapshot of all its values, and receives commands. Implementations: the gamepad
//! (`remote::gamepad`), and [`VirtualRemote`], whose values code sets (tests, a network
//! joystick or a phone would feed one).

/// Whether an element gives a continuous value (-1..1) or a pressed state (0 / 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// A continuous input (stick, trigger), -1..1 or 0..1.
    Axis,
    /// A button, 0 or 1.
    Button,
}

/// One element of a remote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElementInfo {
    /// The element's name in binding files.
    pub name: String,
    /// Axis or button.
    pub kind: ElementKind,
}

/// A snapshot of a remote's values by element name (axes -1..1, buttons 0 or 1).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RemoteData {
    values: Vec<(String, f64)>,
}

impl RemoteData {
    /// The value of `element` (0 when the remote does not report it).
    pub fn get(&self, element: &str) -> f64 {
        self.values
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(element))
            .map_or(0.0, |(_, v)| *v)
    }

    /// Sets an element's value (non-finite values count as 0).
    pub fn set(&mut self, element: &str, value: f64) {
        let v = if value.is_finite() { value } else { 0.0 };
        match self
            .values
            .iter_mut()
            .find(|(n, _)| n.eq_ignore_ascii_case(element))
        {
            Some(e) => e.1 = v,
            None => self.values.push((element.to_string(), v)),
        }
    }

    /// Every element's name and current value.
    pub fn iter(&self) -> impl Iterator<Item = (&str, f64)> {
        self.values.iter().map(|(n, v)| (n.as_str(), *v))
    }
}

/// A remote control device (listing A.5).
pub trait Remote {
    /// A name for the user ("Xbox Wireless Controller").
    fn name(&self) -> String;
    /// Opens the device.
    fn connect(&mut self) -> Result<(), RemoteError>;
    /// Closes the device.
    fn disconnect(&mut self);
    /// Whether the device is open.
    fn is_connected(&self) -> bool;
    /// The elements bindings may name.
    fn available_elements(&self) -> Vec<ElementInfo>;
    /// The commands [`Remote::receive_command`] understands.
    fn available_commands(&self) -> Vec<String>;
    /// The current value of every element.
    fn read_all(&mut self) -> RemoteData;
    /// A command for the device (e.g. `rumble 0.5`); unknown ones are an error.
    fn receive_command(&mut self, command: &str) -> Result<(), RemoteError>;
}

/// Why a remote device refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RemoteError {
    /// No device of this kind is there.
    #[error("no {0} is connected")]
    NoDevice(&'static str),
    /// A command the device does not understand.
    #[error("{device}: unknown command \"{command}\"; it understands: {understands}")]
    UnknownCommand {
        /// The device.
        device: String,
        /// The command.
        command: String,
        /// What it understands.
        understands: String,
    },
    /// A command's value out of its range.
    #[error("{command}: {why}")]
    BadValue {
        /// The command.
        command: String,
        /// The range it must lie in.
        why: &'static str,
    },
}

/// A remote whose values are set by code.
#[derive(Debug, Clone, Default)]
pub struct VirtualRemote {
    /// The device's name, for the user.
    pub label: String,
    /// Its input elements.
    pub elements: Vec<ElementInfo>,
    /// Their current values.
    pub data: RemoteData,
    connected: bool,
    /// Commands received, newest last.
    pub received: Vec<String>,
}

impl VirtualRemote {
    /// A remote with a gamepad's elements.
    pub fn gamepad_like(label: &str) -> Self {
        VirtualRemote {
            label: label.to_string(),
            elements: gamepad_elements(),
            ..VirtualRemote::default()
        }
    }
}

impl Remote for VirtualRemote {
    fn name(&self) -> String {
        self.label.clone()
    }

    fn connect(&mut self) -> Result<(), RemoteError> {
        self.connected = true;
        Ok(())
    }

    fn disconnect(&mut self) {
        self.connected = false;
        self.data = RemoteData::default();
    }

    fn is_connected(&self) -> bool {
        self.connected
    }

    fn available_elements(&self) -> Vec<ElementInfo> {
        self.elements.clone()
    }

    fn available_commands(&self) -> Vec<String> {
        vec!["rumble".into()]
    }

    fn read_all(&mut self) -> RemoteData {
        self.data.clone()
    }

    fn receive_command(&mut self, command: &str) -> Result<(), RemoteError> {
        let verb = command.split_whitespace().next().unwrap_or("");
        if !self.available_commands().iter().any(|c| c == verb) {
            return Err(RemoteError::UnknownCommand {
                device: self.label.clone(),
                command: command.to_string(),
                understands: self.available_commands().join(", "),
            });
        }
        self.received.push(command.to_string());
        Ok(())
    }
}

/// The axes of a standard gamepad (as Bevy names them).
pub const GAMEPAD_AXES: [&str; 6] = [
    "LeftStickX",
    "LeftStickY",
    "RightStickX",
    "RightStickY",
    "LeftZ",
    "RightZ",
];

/// The buttons of a standard gamepad (as Bevy names them).
pub const GAMEPAD_BUTTONS: [&str; 19] = [
    "South",
    "East",
    "North",
    "West",
    "C",
    "Z",
    "LeftTrigger",
    "LeftTrigger2",
    "RightTrigger",
    "RightTrigger2",
    "Select",
    "Start",
    "Mode",
    "LeftThumb",
    "RightThumb",
    "DPadUp",
    "DPadDown",
    "DPadLeft",
    "DPadRight",
];

/// A standard gamepad's elements.
pub fn gamepad_elements() -> Vec<ElementInfo> {
    GAMEPAD_AXES
        .iter()
        .map(|n| (n, ElementKind::Axis))
        .chain(GAMEPAD_BUTTONS.iter().map(|n| (n, ElementKind::Button)))
        .map(|(n, kind)| ElementInfo {
            name: n.to_string(),
            kind,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn virtual_remote_follows_the_interface() {
        let mut r = VirtualRemote::gamepad_like("test pad");
        assert!(!r.is_connected());
        r.connect().unwrap();
        r.data.set("LeftStickX", 0.5);
        r.data.set("South", f64::NAN);
        let d = r.read_all();
        assert_eq!(d.get("leftstickx"), 0.5);
        assert_eq!(d.get("South"), 0.0);
        assert_eq!(d.get("Nothing"), 0.0);
        assert!(r.available_elements().iter().any(|e| e.name == "DPadUp"));
        r.receive_command("rumble 0.3").unwrap();
        assert!(matches!(
            r.receive_command("explode"),
            Err(RemoteError::UnknownCommand { understands, .. }) if understands.contains("rumble")
        ));
        r.disconnect();
        assert!(!r.is_connected() && r.read_all().get("LeftStickX") == 0.0);
    }
}

//! What an off-screen renderer asks of the process's environment before Vulkan starts.
//!
//! Mesa's implicit device-select layer looks for a Wayland compositor to pick the default
//! GPU whenever an application enables Wayland surfaces (Bevy's renderer does), and
//! libwayland prints `error: XDG_RUNTIME_DIR is invalid or not set in the environment.`
//! when there is no session to look in: twice per video on a headless machine, a failure
//! that is not one. Where there is no session there is no compositor to ask, so the layer
//! is turned off (`NODEVICE_SELECT=1`, Mesa's switch) unless the user set it either way;
//! with a session nothing changes.

use std::ffi::OsStr;
use std::path::Path;

/// Mesa's switch for its device-select layer.
pub const DEVICE_SELECT_SWITCH: &str = "NODEVICE_SELECT";

/// The variable to set, and its value, before a renderer starts in a process whose
/// environment has `runtime_dir` as `XDG_RUNTIME_DIR` and `switch` as
/// [`DEVICE_SELECT_SWITCH`]; `None`: leave the environment as it is. Callers set it while
/// the process has one thread (the command line's `main`) or through their own
/// environment's API (Python's `os.environ`).
pub fn headless_setting(
    runtime_dir: Option<&OsStr>,
    switch: Option<&OsStr>,
) -> Option<(&'static str, &'static str)> {
    let session = runtime_dir.is_some_and(|d| !d.is_empty() && Path::new(d).is_dir());
    (!session && switch.is_none()).then_some((DEVICE_SELECT_SWITCH, "1"))
}

/// [`headless_setting`] for this process's environment now.
pub fn headless_setting_here() -> Option<(&'static str, &'static str)> {
    headless_setting(
        std::env::var_os("XDG_RUNTIME_DIR").as_deref(),
        std::env::var_os(DEVICE_SELECT_SWITCH).as_deref(),
    )
}

#[cfg(test)]
mod tests {
    use std::ffi::OsStr;

    use super::headless_setting;

    #[test]
    fn the_device_select_layer_is_switched_off_only_without_a_session_and_a_users_choice() {
        let tmp = std::env::temp_dir();
        let none = headless_setting(None, None);
        assert_eq!(none, Some(("NODEVICE_SELECT", "1")));
        assert_eq!(headless_setting(Some(OsStr::new("")), None), none);
        assert_eq!(
            headless_setting(Some(OsStr::new("/no/such/runtime/dir")), None),
            none
        );
        assert_eq!(headless_setting(Some(tmp.as_os_str()), None), None);
        assert_eq!(headless_setting(None, Some(OsStr::new("0"))), None);
    }
}

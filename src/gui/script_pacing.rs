//! What the scripts of both windows share: frames left of a `wait`, and screenshots
//! asked of Bevy that the script waits for until the file is written.

use std::path::PathBuf;

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};

/// Frames to wait for a screenshot file before giving up.
pub const SHOT_FRAMES: u32 = 600;

/// A script's pauses.
#[derive(Debug, Clone, Default)]
pub struct Pacing {
    /// Frames left of a `wait`.
    pub waiting: u32,
    /// A screenshot being written: path and frames waited for it.
    pub pending_shot: Option<(PathBuf, u32)>,
}

impl Pacing {
    /// Whether the script waits this frame; an error when a screenshot never appeared.
    pub fn hold(&mut self) -> Result<bool, String> {
        if self.waiting > 0 {
            self.waiting -= 1;
            return Ok(true);
        }
        if let Some((path, waited)) = self.pending_shot.as_mut() {
            if !path.exists() && *waited < SHOT_FRAMES {
                *waited += 1;
                return Ok(true);
            }
            let missing = !path.exists();
            let shot = path.display().to_string();
            self.pending_shot = None;
            if missing {
                return Err(format!("screenshot {shot} was not written"));
            }
        }
        Ok(false)
    }

    /// Asks for a screenshot of the window into `path`; the script waits for the file.
    pub fn screenshot(&mut self, commands: &mut Commands, path: PathBuf) {
        crate::gui::control::widgets::ensure_parent(&path);
        let _ = std::fs::remove_file(&path);
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path.clone()));
        self.pending_shot = Some((path, 0));
    }
}

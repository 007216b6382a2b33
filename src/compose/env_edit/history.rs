//! Undo and redo in the environment editor: snapshots of the editable part of the scene,
//! at most [`UNDO_LIMIT`] kept.

use crate::config::environment::EnvObject;
use crate::config::transform::Pose;

/// Most undo steps kept.
const UNDO_LIMIT: usize = 200;

/// The editable part of the scene (what undo restores).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Snapshot {
    pub objects: Vec<EnvObject>,
    pub robot_pose: Pose,
}

/// The edits that can be undone, and those undone that can be redone.
#[derive(Debug, Clone, Default)]
pub(super) struct History {
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
}

impl History {
    /// Records the state before a change (a new change forgets what was undone).
    pub fn record(&mut self, before: Snapshot) {
        self.undo.push(before);
        if self.undo.len() > UNDO_LIMIT {
            self.undo.remove(0);
        }
        self.redo.clear();
    }

    /// Whether there is an edit to undo.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether there is an undone edit to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// The state to go back to, `now` kept for redo; none when there is nothing to undo.
    pub fn undo(&mut self, now: Snapshot) -> Option<Snapshot> {
        let back = self.undo.pop()?;
        self.redo.push(now);
        Some(back)
    }

    /// The state to go forward to, `now` kept for undo; none when nothing was undone.
    pub fn redo(&mut self, now: Snapshot) -> Option<Snapshot> {
        let forward = self.redo.pop()?;
        self.undo.push(now);
        Some(forward)
    }
}

//! Small egui helpers shared by the views.

use std::collections::BTreeSet;

use bevy_egui::egui;

/// A check box that adds `key` to or removes it from `set`.
pub fn set_checkbox<K: Ord>(
    ui: &mut egui::Ui,
    set: &mut BTreeSet<K>,
    key: K,
    label: String,
) -> egui::Rect {
    let mut on = set.contains(&key);
    let response = ui.checkbox(&mut on, label);
    if response.changed() {
        if on {
            set.insert(key);
        } else {
            set.remove(&key);
        }
    }
    response.rect
}

/// A file's parent folder created (best effort: writing the file reports the error).
pub fn ensure_parent(path: &std::path::Path) {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        let _ = std::fs::create_dir_all(dir);
    }
}

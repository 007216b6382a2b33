//! What every 3D view shares (the control window, the configuration window, videos): the
//! orbit camera and the pointer's motion ([`orbit`]), configuration geometry drawn in Bevy
//! ([`meshes`]), and the pointer's gestures on scene objects ([`picking`]). Each window
//! decides what a gesture does; this folder only measures and draws.

pub mod meshes;
pub mod orbit;
pub mod picking;

use bevy::prelude::*;

/// The pointer's motion measured once a frame, before any view steers by it.
pub struct PointerMotionPlugin;

impl Plugin for PointerMotionPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<orbit::PointerMotion>().add_systems(
            PreUpdate,
            orbit::measure_pointer.after(bevy::input::InputSystems),
        );
    }
}

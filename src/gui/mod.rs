//! The graphical user interfaces (feature `gui`), built with Bevy's renderer and bevy_egui
//! on top of the headless core:
//!
//! - [`control`]: the control window (thesis 4.5) — 3D viewer, toolbar, live plots,
//!   control-algorithm properties, data file inspection, optimization view.
//! - [`script_pacing`]: waits and screenshots of both windows' scripts
//! - [`setup`]: the configuration window (thesis 4.4) — beginner wizard, expert
//!   composition, 3D environment editor.

pub mod control;
pub mod script_pacing;
pub mod setup;

pub use control::run;

//! The graphical user interfaces (feature `gui`), built with Bevy's renderer and bevy_egui
//! on top of the headless core:
//!
//! - [`control`]: the control window (thesis 4.5) — 3D viewer, toolbar, live plots,
//!   control-algorithm properties, data file inspection, optimization view.
//!
//! The configuration GUI (wizard, expert dialog, environment editor; thesis 4.4) will sit
//! beside it in `setup/`.

pub mod control;

pub use control::run;

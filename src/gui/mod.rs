//! The graphical user interfaces (feature `gui`), built with Bevy's renderer and bevy_egui
//! on top of the headless core:
//!
//! - [`control`]: the control window (thesis 4.5) — 3D viewer, toolbar, live plots,
//!   control-algorithm properties, data file inspection, optimization view.
//! - [`module_editor`]: the user module library in the windows (thesis 4.4.4)
//! - [`error`]: the windows' errors
//! - [`desktop`]: reactive rendering, a clean exit on SIGTERM, child windows reaped
//! - [`keyboard`]: keys reach egui in typed order with the modifiers of their moment
//! - [`meter`]: frame rate and real-time factor achieved over the last wall second
//! - [`pointer`]: who gets the pointer, the panels or the 3D scene behind them
//! - [`scripting`]: what both windows' scripts share (parsing, waits, screenshots)
//! - [`setup`]: the configuration window (thesis 4.4) — beginner wizard, expert
//!   composition, 3D environment editor.
//! - [`video`]: videos of a run rendered off-screen (`proleg run --video`)
//! - [`view3d`]: what every 3D view shares: orbit camera, pointer motion, geometry meshes,
//!   the pointer's gestures on scene objects

pub mod control;
pub mod desktop;
pub mod error;
pub mod keyboard;
pub mod meter;
pub mod module_editor;
pub mod pointer;
#[cfg(feature = "scripts")]
pub mod scripting;
pub mod setup;
pub mod video;
pub mod view3d;

pub use control::run;

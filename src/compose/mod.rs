//! Composing configurations without writing XML (thesis 4.4): the pure logic behind the
//! configuration GUI (`gui::setup`), free of rendering so it tests headless.
//!
//! - [`behaviour`]: actuation modules on groups of joints, with parameter values
//! - [`library`]: the environment editor's object library (box, ramp, stairs, meshes, ...)
//! - [`env_edit`]: the environment editor's model: add, move, rotate, scale, friction,
//!   undo / redo, robot start pose
//! - [`optimization`]: registering module parameters for the GA / great deluge
//! - [`wizard`]: the beginner wizard's pages, validation and the files it writes
//! - [`expert`]: composing a simulation from existing files
//! - [`paths`]: relative paths between the written files, time-stamped names, and a
//!   file source that sees unsaved files over the disk
//! - [`error`]: the composing layer's errors
//!
//! The robot builder the wizard uses lives with the formats
//! ([`crate::config::robot_builder`]).

pub mod behaviour;
pub mod env_edit;
pub mod error;
pub mod expert;
pub mod library;
pub mod optimization;
pub mod paths;
pub mod wizard;

/// The robot builder lives with the formats (the optimizers build bodies too).
pub use crate::config::robot_builder;

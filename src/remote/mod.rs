//! Remote controls (thesis 4.3.4, 4.5.7, 5.4): devices whose sticks and buttons change
//! module parameters while the robot runs, through the same
//! [`crate::control::ControlKernel::set_parameter`] the GUI and the optimizers use.
//!
//! - [`device`]: the remote interface of listing A.5 (connect, elements, commands, read
//!   all data, receive a command) and a virtual remote set from code
//! - [`mapper`]: applies a binding file ([`crate::config::remote`]) to a kernel: dead
//!   zones, rate / absolute axes, button steps and toggles, limits, reset and pause
//! - `gamepad` (feature `gui`): any gamepad through Bevy's gilrs input

pub mod device;
#[cfg(feature = "gui")]
pub mod gamepad;
pub mod mapper;

pub use device::{ElementInfo, ElementKind, Remote, RemoteData, VirtualRemote};
pub use mapper::RemoteMapper;

//! Errors building or running a simulation.

use std::fmt;

use crate::config::ConfigError;
use crate::control::kernel::KernelError;

/// Why a simulation could not be built or changed.
#[derive(Debug, Clone)]
pub enum SimError {
    Config(ConfigError),
    Kernel(KernelError),
    Mesh { file: String, message: String },
    TooManyRobots { requested: usize, max: usize },
    NoSuchRobot { index: usize, count: usize },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Config(e) => e.fmt(f),
            SimError::Kernel(e) => e.fmt(f),
            SimError::Mesh { file, message } => {
                write!(f, "{file}: cannot build the collision mesh: {message}")
            }
            SimError::TooManyRobots { requested, max } => {
                write!(
                    f,
                    "{requested} robots in one world; at most {max} fit (one collision group each)"
                )
            }
            SimError::NoSuchRobot { index, count } => {
                write!(f, "no robot {index}: the world holds {count}")
            }
        }
    }
}

impl std::error::Error for SimError {}

impl From<ConfigError> for SimError {
    fn from(e: ConfigError) -> Self {
        SimError::Config(e)
    }
}

impl From<KernelError> for SimError {
    fn from(e: KernelError) -> Self {
        SimError::Kernel(e)
    }
}

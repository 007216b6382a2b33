//! Errors building or running a simulation.

use std::fmt;

use crate::config::ConfigError;
use crate::control::kernel::KernelError;

/// Why a simulation could not be built or changed.
#[derive(Debug, Clone)]
pub enum SimError {
    /// A configuration that does not load or check.
    Config(ConfigError),
    /// A kernel that cannot be built or changed (module, parameter, joint).
    Kernel(KernelError),
    /// A collision mesh that cannot be built.
    Mesh {
        /// The mesh file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// More robots than one world holds.
    TooManyRobots {
        /// Robots asked for.
        requested: usize,
        /// Robots one world holds.
        max: usize,
    },
    /// A robot index beyond the world's robots.
    NoSuchRobot {
        /// The index given.
        index: usize,
        /// Robots in the world.
        count: usize,
    },
    /// A link index beyond the robot's links.
    NoSuchLink {
        /// The index given.
        link: usize,
        /// The robot's links.
        count: usize,
    },
    /// A tactile pad that lies on none of its link's geometries (it reads their contacts).
    PadOffLink {
        /// The sensor's name.
        sensor: String,
        /// Its link's name.
        link: String,
    },
    /// The MuJoCo engine: a missing or wrong library, a model it rejects.
    Mujoco(crate::sim::engine::mujoco::MujocoError),
    /// A setting of the configuration the engine has no counterpart for.
    Unsupported {
        /// The engine.
        engine: crate::config::simulation::EngineKind,
        /// What it cannot do, and what to use instead.
        what: String,
    },
}

impl From<crate::sim::engine::mujoco::MujocoError> for SimError {
    fn from(e: crate::sim::engine::mujoco::MujocoError) -> Self {
        SimError::Mujoco(e)
    }
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Config(e) => e.fmt(f),
            SimError::Mujoco(e) => e.fmt(f),
            SimError::Unsupported { engine, what } => {
                write!(f, "{engine} cannot simulate this: {what}")
            }
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
            SimError::NoSuchLink { link, count } => {
                write!(f, "no link {link}: the robot has {count}")
            }
            SimError::PadOffLink { sensor, link } => write!(
                f,
                "tactile pad \"{sensor}\" lies on none of link \"{link}\"'s geometries; \
                 a pad reads the contacts of its link's surface, so its box must touch one"
            ),
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

//! Errors building or running a simulation.

use crate::config::ConfigError;
use crate::control::kernel::KernelError;

/// Why a simulation could not be built or changed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SimError {
    /// A configuration that does not load or check.
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// A kernel that cannot be built or changed (module, parameter, joint).
    #[error("{0}")]
    Kernel(#[from] KernelError),
    /// A module that cannot run on the robot, found before the first step.
    #[error("{0}")]
    Module(Box<ModuleMismatch>),
    /// A module stopped during an episode whose result would be scored (a plugin's panic,
    /// a network's non-finite output): the episode did not run the file's control.
    #[error("module {module} failed during the episode: {cause}")]
    ModuleFailed {
        /// The module type.
        module: String,
        /// Why it stopped.
        cause: String,
    },
    /// A collision mesh that cannot be built.
    #[error("{file}: cannot build the collision mesh: {message}")]
    Mesh {
        /// The mesh file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// More robots than one world holds.
    #[error("{requested} robots in one world; at most {max} fit (one collision group each)")]
    TooManyRobots {
        /// Robots asked for.
        requested: usize,
        /// Robots one world holds.
        max: usize,
    },
    /// A robot index beyond the world's robots.
    #[error("no robot {index}: the world holds {count}")]
    NoSuchRobot {
        /// The index given.
        index: usize,
        /// Robots in the world.
        count: usize,
    },
    /// A link index beyond the robot's links.
    #[error("no link {link}: the robot has {count}")]
    NoSuchLink {
        /// The index given.
        link: usize,
        /// The robot's links.
        count: usize,
    },
    /// A tactile pad that lies on none of its link's geometries (it reads their contacts).
    #[error(
        "tactile pad \"{sensor}\" lies on none of link \"{link}\"'s geometries; a pad reads the contacts of its link's surface, so its box must touch one"
    )]
    PadOffLink {
        /// The sensor's name.
        sensor: String,
        /// Its link's name.
        link: String,
    },
    /// The MuJoCo engine: a missing or wrong library, a model it rejects.
    #[error("{0}")]
    Mujoco(#[from] crate::sim::engine::mujoco::MujocoError),
    /// A setting of the configuration the engine has no counterpart for.
    #[error("{engine} cannot simulate this: {what}")]
    Unsupported {
        /// The engine.
        engine: crate::config::simulation::EngineKind,
        /// What it cannot do, and what to use instead.
        what: String,
    },
}

/// A module that cannot run on the robot (a network reading another observation than the
/// robot's sensors give): the actuation file and where the module is written in it.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}: {cause}", located(file, *pos))]
pub struct ModuleMismatch {
    /// The actuation file.
    pub file: std::path::PathBuf,
    /// Where its `<actuationModule>` is written (line 0: made in the window).
    pub pos: crate::config::error::Pos,
    /// Why.
    #[source]
    pub cause: KernelError,
}

/// `file:line:col`, or the file alone for a position the file does not have.
fn located(file: &std::path::Path, pos: crate::config::error::Pos) -> String {
    if pos.line == 0 {
        file.display().to_string()
    } else {
        format!("{}:{pos}", file.display())
    }
}

//! What can go wrong with an environment: its file, its world, its options and the actions
//! and shapes handed to it. Each is a variant the Python binding maps to an exception
//! (`ConfigError` for files, `ValueError` for bad input) with the same message.

use crate::config::ConfigError;
use crate::control::kernel::KernelError;
use crate::sim::SimError;

/// Why an environment could not be made, reset or stepped.
#[derive(Debug, thiserror::Error)]
pub enum GymError {
    /// The simulation file does not load.
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// The world cannot be built or read.
    #[error("{0}")]
    Sim(#[from] SimError),
    /// The episode's score cannot be read.
    #[error("{0}")]
    Eval(#[from] crate::optimize::evaluate::EvalError),
    /// The control kernel refused the policy's targets.
    #[error("{0}")]
    Kernel(#[from] KernelError),
    /// An option out of its range.
    #[error("{option} = {value}: {want}")]
    Option {
        /// The option.
        option: &'static str,
        /// Its value.
        value: String,
        /// What it must be.
        want: &'static str,
    },
    /// An option no environment has.
    #[error("no option {name:?}; the options: {known}")]
    UnknownOption {
        /// The name given.
        name: String,
        /// The options there are.
        known: String,
    },
    /// An action or buffer of the wrong length.
    #[error("{what} has {given} values, expected {want}")]
    Shape {
        /// What was handed in.
        what: &'static str,
        /// Its length.
        given: usize,
        /// The length expected.
        want: usize,
    },
    /// A NaN or infinite action.
    #[error("action[{index}] is {value}: actions must be finite numbers")]
    NotFinite {
        /// Its index.
        index: usize,
        /// The value.
        value: f64,
    },
    /// The simulation has no robot to control.
    #[error("{file}: the simulation has no joint to control")]
    NoJoints {
        /// The simulation file.
        file: String,
    },
    /// `step` before the first `reset`, or after `close`.
    #[error("{0}")]
    State(&'static str),
    /// A `terrain` and `difficulty` the suite has no task for.
    #[error("{suite} has no {family} task of difficulty {difficulty}; its {family} tasks: {known}")]
    NoTask {
        /// The suite file.
        suite: String,
        /// The family asked for.
        family: String,
        /// The difficulty asked for.
        difficulty: f64,
        /// The family's tasks there are.
        known: String,
    },
    /// A held-out task asked for with its train seeds.
    #[error(
        "task {task} is held out: it has no train seeds (split=\"test\" runs its test seeds, terrain_seed one course)"
    )]
    HeldOut {
        /// The task.
        task: String,
    },
    /// Terrain options without a `terrain`.
    #[error("{0} is an option of a terrain task: give terrain=\"pegs\" (or another family) too")]
    NoTerrain(&'static str),
    /// The thread pool of a vector environment could not be started.
    #[error("the thread pool could not be started: {0}")]
    Threads(String),
}

//! Why a benchmark, the accuracy gate or a module comparison could not give its figures.

use std::path::PathBuf;

use crate::config::ConfigError;
use crate::sim::SimError;
use crate::sim::engine::EngineSettingsError;

/// A benchmark that could not run, or a gate that failed.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The scenario does not load.
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// Its world cannot be built or read.
    #[error("{0}")]
    Sim(#[from] SimError),
    /// A `--physics` override that cannot be applied (or is for another engine).
    #[error("{0}")]
    Settings(#[from] EngineSettingsError),
    /// A run whose positions became non-finite.
    #[error("the run with {settings} blew up (non-finite positions)")]
    BlewUp {
        /// The settings it ran with.
        settings: String,
    },
    /// No repetition of a figure ran to its end.
    #[error("no repetition ran")]
    NoRepetition,
    /// The recording figure's data file could not be written.
    #[error("recording to {} failed", file.display())]
    Recording {
        /// The data file.
        file: PathBuf,
    },
    /// The module comparison cannot replace the scenario's module.
    #[error("{0}")]
    ModuleSwap(String),
    /// The control kernel produced non-finite joint angles.
    #[error("the kernel produced non-finite angles")]
    NonFiniteAngles,
    /// A suite's task world that cannot be made.
    #[error("{0}")]
    Suite(#[source] Box<crate::suite::SuiteError>),
    /// The accuracy gate failed: its report, which says by how much.
    #[error("{0}")]
    GateFailed(String),
}

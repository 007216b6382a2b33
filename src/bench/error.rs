//! Why a benchmark, the accuracy gate or a module comparison could not give its figures.

use std::path::PathBuf;

use crate::config::ConfigError;
use crate::config::simulation::EngineKind;
use crate::sim::SimError;
use crate::sim::engine::rapier::SettingsError;

/// A benchmark that could not run, or a gate that failed.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The scenario does not load.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// Its world cannot be built or read.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// A `--physics` override that cannot be applied.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// `--physics` (rapier's settings) given for a run on another engine.
    #[error("--physics sets rapier's settings; this {what} is on {engine}")]
    PhysicsOnOtherEngine {
        /// "bench" or "check".
        what: &'static str,
        /// The engine of the run.
        engine: EngineKind,
    },
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
    /// The accuracy gate failed: its report, which says by how much.
    #[error("{0}")]
    GateFailed(String),
}

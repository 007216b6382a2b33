//! Why an optimization cannot start or go on: the optimize layer's errors, typed, turned
//! into text only where the command line or a window prints them.

use std::path::PathBuf;

use crate::optimize::store::error::StoreError;

/// An optimization that cannot be set up or run.
#[derive(Debug, thiserror::Error)]
pub enum OptimizeError {
    /// The simulation's mode is not an optimization (no optimizer file).
    #[error(
        "{}: mode {mode:?} has no optimizer file; optimization needs an optimization mode (\"GA optimization\", \"Great Deluge optimization\", \"CMA-ES optimization\", \"MAP-Elites optimization\", \"Evolution strategy optimization\") with an <optimizer>",
        file.display()
    )]
    NoOptimizer {
        /// The simulation file.
        file: PathBuf,
        /// Its mode.
        mode: String,
    },
    /// The optimizer file registers no parameter.
    #[error("{}: no parameter is registered for optimization", file.display())]
    NothingRegistered {
        /// The optimizer file.
        file: PathBuf,
    },
    /// The actuation's kernel cannot be built (the start candidate is read from it).
    #[error("{0}")]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// An episode could not be run or scored.
    #[error("{0}")]
    Eval(#[from] crate::optimize::evaluate::EvalError),
    /// The experiment store failed.
    #[error("{0}")]
    Store(#[from] StoreError),
    /// A shared store's connection was gone when the round was queued.
    #[error("the shared store went away")]
    StoreGone,
    /// A MAP-Elites descriptor naming a gene the search space does not have.
    #[error("MAP-Elites descriptor gene {gene}: the search space has genes 1..={genes}")]
    Descriptor {
        /// The gene named (0: a missing descriptor).
        gene: u32,
        /// Genes of the space.
        genes: usize,
    },
    /// What co-design (a `<morphology>`) does not do yet.
    #[error("co-design: {0}")]
    CoDesign(&'static str),
    /// An exported design's files do not load where they were written.
    #[error("{}: the exported design does not load (its parts and environment are found from the configuration's folder: export into it): {source}", dir.display())]
    DesignFiles {
        /// The folder written.
        dir: PathBuf,
        /// The loader's error.
        source: Box<crate::config::ConfigError>,
    },
    /// A file that cannot be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A configuration's files that cannot be written into a folder of their own.
    #[error("{0}")]
    Bundle(#[from] crate::config::bundle::BundleError),
    /// A candidate's network that cannot be written.
    #[error("{0}")]
    Policy(#[source] Box<crate::control::policy::PolicyError>),
    /// The configuration does not load.
    #[error("{0}")]
    Config(#[source] Box<crate::config::ConfigError>),
    /// `--resume` without an unfinished run of the same configuration.
    #[error(
        "--resume: {store} holds no unfinished run of {config} with seed {seed}, fitness {fitness} and {duration} s episodes"
    )]
    NothingToResume {
        /// The store, without password.
        store: String,
        /// The configuration.
        config: String,
        /// The seed.
        seed: u64,
        /// The fitness.
        fitness: String,
        /// The episode duration (s).
        duration: f64,
    },
    /// A curriculum's stage given a start candidate that is not of its search space.
    #[error("the start candidate is not of the run's search space")]
    StartOutsideSpace,
    /// A curriculum (`<courses>` with `<stage>`s) opened as one run.
    #[error(
        "{}: its <courses> is a curriculum (<stage>s): `proleg optimize` and the optimization view run its stages one after another",
        file.display()
    )]
    CurriculumAsOneRun {
        /// The optimizer file.
        file: PathBuf,
    },
    /// The optimizer ended without one evaluation.
    #[error("the optimizer evaluated nothing")]
    NothingEvaluated,
    /// Stopped (Ctrl-C, SIGTERM, a window's Stop) before the first round ended: no best
    /// yet; what finished is stored.
    #[error(
        "stopped before the first round ended; every finished evaluation is stored and the run stays unfinished (--resume continues it)"
    )]
    StoppedEarly,
    /// A run setting given on the command line or in the window that cannot be used.
    #[error("{0}")]
    Choice(#[from] BadChoice),
    /// The run's own worker threads stopped with an error.
    #[error("the local workers stopped: {0}")]
    LocalWorkers(Box<OptimizeError>),
    /// A worker thread panicked.
    #[error("a worker thread panicked")]
    Panicked,
    /// A round's scores did not come (the coordinator benchmark's clients stopped).
    #[error("no score arrived for {seconds:.0} s")]
    Stalled {
        /// How long it was waited.
        seconds: f64,
    },
    /// A stored run this host cannot evaluate.
    #[error("run {run}: {why}")]
    Unevaluable {
        /// The run.
        run: i64,
        /// Why not.
        why: UnevaluableRun,
    },
    /// The store holds no run to follow.
    #[error("{store}: {what}")]
    NothingToFollow {
        /// The store, without password.
        store: String,
        /// What was looked for.
        what: String,
    },
    /// The curves could not be drawn.
    #[error("{}: cannot draw: {message}", file.display())]
    Plot {
        /// The image file.
        file: PathBuf,
        /// The plotting library's message, or what is missing.
        message: String,
    },
}

/// A run setting that cannot be used, named as the command line spells it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BadChoice {
    /// `--duration` that is not a positive number of seconds.
    #[error("--duration {0}: give a number of seconds > 0")]
    Duration(f64),
    /// `--lease` that is not a positive number of seconds.
    #[error("--lease {0}: give a number of seconds > 0")]
    Lease(f64),
    /// `--workers 0` without a shared store whose workers evaluate.
    #[error(
        "--workers 0: give at least 1 (0 only with a shared postgres:// store, whose workers evaluate)"
    )]
    NoWorkers,
    /// `--batch` above 1 with a shared store.
    #[error(
        "--batch {0}: a shared store evaluates one robot per world, so that a score does not depend on which worker claimed what"
    )]
    SharedBatch(usize),
    /// A `--store` that is neither a path nor a usable PostgreSQL URL.
    #[error("--store: {0}")]
    Store(String),
}

impl OptimizeError {
    /// A plotting failure (or what is missing to plot) writing `file`.
    pub fn plot(file: &std::path::Path) -> impl Fn(&dyn std::fmt::Display) -> OptimizeError + '_ {
        move |e| OptimizeError::Plot {
            file: file.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// Why this host cannot evaluate a stored run.
#[derive(Debug, thiserror::Error)]
pub enum UnevaluableRun {
    /// Its stored configuration does not load with this host's module types.
    #[error("its configuration does not load on this host: {0}")]
    Config(#[from] crate::config::ConfigError),
    /// A suite run (`proleg suite --store`): its evaluations are episodes of one
    /// controller on a suite's courses, not candidates to export, replay or score again.
    #[error(
        "it is a suite run: its evaluations are episodes of one controller on the suite's courses, not candidates"
    )]
    SuiteRun,
    /// Another program version started it (its scores could differ).
    #[error(
        "started by {started}, this host runs {here}: its scores could differ, so it is left to workers of the same version"
    )]
    Version {
        /// The program that started the run.
        started: String,
        /// This program.
        here: String,
    },
    /// It scores on MuJoCo, whose library this host lacks.
    #[error("it runs on MuJoCo, which this host lacks: {0}")]
    NoMujoco(String),
    /// This host reads other genes from the configuration than the run stored.
    #[error("this host reads other genes from its configuration ({here} instead of {stored})")]
    Genes {
        /// The genes read here.
        here: String,
        /// The run's genes.
        stored: String,
    },
    /// Its search space cannot be set up (the optimizer file).
    #[error("{0}")]
    Setup(Box<OptimizeError>),
    /// Its fitness is not one this host knows.
    #[error("{0}")]
    Fitness(#[from] crate::config::error::UnknownName),
}

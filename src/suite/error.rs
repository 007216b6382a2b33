//! Why a suite cannot be run or its journal read.

use std::path::PathBuf;

/// What went wrong running a suite.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    /// The suite, the controller or a task's course does not load.
    #[error("{0}")]
    Config(#[from] crate::config::ConfigError),
    /// A world that cannot be built or run.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// A task the command names that the suite does not have.
    #[error("the suite has no task {name:?}; it has {known}")]
    UnknownTask {
        /// The name given.
        name: String,
        /// The suite's tasks.
        known: String,
    },
    /// An engine whose library is not here.
    #[error("{0}")]
    Engine(crate::sim::SimError),
    /// The journal of finished episodes cannot be read or written.
    #[error("{}: {source}", path.display())]
    Journal {
        /// The journal file.
        path: PathBuf,
        /// The system's error.
        #[source]
        source: std::io::Error,
    },
    /// A journal line that is not an episode of this suite (another suite's journal, or a
    /// cut line).
    #[error("{}:{line}: {why}", path.display())]
    JournalLine {
        /// The journal file.
        path: PathBuf,
        /// Its line (from 1).
        line: usize,
        /// What is wrong with it.
        #[source]
        why: BadLine,
    },
    /// The chart cannot be drawn or written.
    #[error("{}: cannot draw the chart: {message}", file.display())]
    Chart {
        /// The PNG file.
        file: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The shared store: it cannot be reached or written, or the process's own workers
    /// failed.
    #[error("{0}")]
    Shared(Box<crate::optimize::error::OptimizeError>),
    /// An episode whose worker could not run it (its output says why): stored as failed,
    /// it is not run again in that store's run.
    #[error(
        "{episode} failed on the worker that ran it (run {run} of the store; that worker's output says why)"
    )]
    FailedOnWorker {
        /// The store's run.
        run: i64,
        /// Which episode.
        episode: String,
    },
    /// Ctrl-C / SIGTERM: the run stopped; what finished is in the journal.
    #[error(
        "stopped: {done} of {total} episodes are in the journal; run the same command again to go on"
    )]
    Stopped {
        /// Episodes finished.
        done: usize,
        /// Episodes of the whole run.
        total: usize,
    },
}

impl From<crate::optimize::error::OptimizeError> for SuiteError {
    fn from(e: crate::optimize::error::OptimizeError) -> Self {
        SuiteError::Shared(Box::new(e))
    }
}

impl From<crate::optimize::store::StoreError> for SuiteError {
    fn from(e: crate::optimize::store::StoreError) -> Self {
        SuiteError::Shared(Box::new(e.into()))
    }
}

/// The journal's column header.
pub const COLUMNS: &str = "task,seed,engine,distance,crossed,ended";

/// What is wrong with a journal line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BadLine {
    /// Not the six columns.
    #[error("expected {COLUMNS}, found {0:?}")]
    Columns(String),
    /// A task the suite does not have.
    #[error("task {0:?} is not in the suite")]
    Task(String),
    /// The first line names another run.
    #[error(
        "this journal is of another run ({found}); this run is {this}: choose another output folder"
    )]
    AnotherRun {
        /// The journal's first line.
        found: String,
        /// This run's.
        this: String,
    },
    /// A column that does not read as its kind (column, text).
    #[error("{0} {1:?} does not read")]
    Value(&'static str, String),
}

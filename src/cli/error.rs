//! The command line's errors: each layer's typed error as it reaches a command, and the
//! command line's own (an option value the argument parser cannot check). `main.rs`
//! turns them into text when it prints them.

use std::path::PathBuf;

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A configuration that does not load or check.
    #[error(transparent)]
    Config(#[from] crate::config::ConfigError),
    /// A configuration's files that cannot be copied into a folder of their own.
    #[error(transparent)]
    Bundle(#[from] crate::config::bundle::BundleError),
    /// A world that cannot be built or read.
    #[error(transparent)]
    Sim(#[from] crate::sim::SimError),
    /// A data file that cannot be started.
    #[error(transparent)]
    Record(#[from] crate::sim::runner::RecordError),
    /// A data file that cannot be read.
    #[error(transparent)]
    Data(#[from] crate::data::read::DataError),
    /// A data file that cannot be finished.
    #[error(transparent)]
    DataStore(#[from] crate::data::store::DataStoreError),
    /// An x axis that is none of the known ones.
    #[error(transparent)]
    Axis(#[from] crate::data::export::UnknownAxis),
    /// A series selection that is malformed or not in the file.
    #[error(transparent)]
    Select(#[from] crate::data::export::SelectError),
    /// A name that is none of the accepted ones.
    #[error(transparent)]
    Name(#[from] crate::config::error::UnknownName),
    /// Ctrl-C / SIGTERM cannot be handled.
    #[error(transparent)]
    Signal(#[from] crate::signal::SignalError),
    /// `proleg dashboard` could not serve.
    #[error(transparent)]
    Dashboard(crate::dashboard::DashboardError),
    /// A URDF that cannot be imported.
    #[error(transparent)]
    Import(#[from] crate::cli::interop::ImportError),
    /// A robot that cannot be run to let it settle.
    #[error(transparent)]
    Settle(#[from] crate::cli::interop::SettleError),
    /// A benchmark that cannot run.
    #[error(transparent)]
    Bench(#[from] crate::bench::error::BenchError),
    /// The stages' timing that cannot run.
    #[error(transparent)]
    Stages(#[from] crate::bench::stages::StagesError),
    /// Physics checks that cannot run.
    #[error(transparent)]
    PhysicsCheck(#[from] crate::bench::physics_checks::PhysicsCheckError),
    /// The experiment store.
    #[error(transparent)]
    Store(#[from] crate::optimize::store::StoreError),
    /// An optimization that cannot be set up or run.
    #[error(transparent)]
    Optimize(#[from] crate::optimize::error::OptimizeError),
    /// A servo calibration that cannot be done.
    #[error(transparent)]
    Calibrate(Box<crate::calibrate::CalibrateError>),
    /// A run setting that cannot be used.
    #[error(transparent)]
    Choice(#[from] crate::optimize::error::BadChoice),
    /// An episode that cannot be run.
    #[error(transparent)]
    Eval(#[from] crate::optimize::evaluate::EvalError),
    /// A stored evaluation that cannot be replayed.
    #[error(transparent)]
    Replay(#[from] crate::optimize::replay::ReplayError),
    /// Physics settings that cannot be used.
    #[error(transparent)]
    Physics(#[from] crate::sim::engine::EngineSettingsError),
    /// A kernel that cannot be built.
    #[error(transparent)]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// The real robot's run.
    #[error(transparent)]
    RealMode(#[from] crate::robot_io::real_mode::RealModeError),
    /// The servo emulator.
    #[error(transparent)]
    Emulator(#[from] crate::robot_io::emulator::EmulatorError),
    /// A plugin crate.
    #[error(transparent)]
    Plugin(#[from] crate::plugin_host::error::PluginError),
    /// An import or export.
    #[error(transparent)]
    Interop(#[from] crate::interop::InteropError),
    /// A weights file that cannot be read or written.
    #[error(transparent)]
    Policy(Box<crate::control::policy::PolicyError>),
    /// An environment that cannot run.
    #[error(transparent)]
    Gym(#[from] crate::gym::GymError),
    /// A file that cannot be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// An option whose value the argument parser cannot check.
    #[error("{option} {value}: {want}")]
    Option {
        /// The option as typed (`--gait`).
        option: &'static str,
        /// Its value.
        value: String,
        /// What it must be.
        want: &'static str,
    },
    /// Options that do not go together.
    #[error("{0}")]
    Options(&'static str),
    /// A check that did not pass: its report, printed as the error (exit status 1).
    #[error("{0}")]
    Failed(String),
    /// A run none of the given stores holds.
    #[error("no run {0} in the given store(s)")]
    NoRun(i64),
    /// The real robot's run stopped on an error: what it did, then why.
    #[error("{report}the run stopped: {cause}")]
    RobotStopped {
        /// The run's report.
        report: String,
        /// Why it stopped.
        cause: String,
    },
}

impl CliError {
    /// A write error on `path`.
    pub fn write(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| CliError::Write { path, source }
    }
}

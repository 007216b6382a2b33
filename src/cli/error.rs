//! The command line's errors: each layer's typed error as it reaches a command, and the
//! command line's own (an option value the argument parser cannot check). `main.rs`
//! turns them into text when it prints them.

use std::path::PathBuf;

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A configuration that does not load or check.
    #[error("{0}")]
    Config(#[from] crate::config::ConfigError),
    /// A configuration's files that cannot be copied into a folder of their own.
    #[error("{0}")]
    Bundle(#[from] crate::config::bundle::BundleError),
    /// A world that cannot be built or read.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// A run that ended with a module stopped (a plugin that panicked, a network with a
    /// non-finite output): what it did, then why its figures are not those of the file's
    /// control (exit status 1).
    #[error(
        "{report}module {module} failed during the run: {cause}; its joints got 0 from then on, so the figures above are not the file's control"
    )]
    ModuleFailed {
        /// The run's report, as printed.
        report: String,
        /// The first module that failed.
        module: String,
        /// Why.
        cause: String,
    },
    /// A data file that cannot be started.
    #[error("{0}")]
    Record(#[from] crate::sim::runner::RecordError),
    /// A data file that cannot be read.
    #[error("{0}")]
    Data(#[from] crate::data::read::DataError),
    /// A data file that cannot be finished.
    #[error("{0}")]
    DataStore(#[from] crate::data::store::DataStoreError),
    /// An x axis that is none of the known ones.
    #[error("{0}")]
    Axis(#[from] crate::data::export::UnknownAxis),
    /// A series selection that is malformed or not in the file.
    #[error("{0}")]
    Select(#[from] crate::data::export::SelectError),
    /// A name that is none of the accepted ones.
    #[error("{0}")]
    Name(#[from] crate::config::error::UnknownName),
    /// A 3D replay that cannot be recorded or written.
    #[error("{0}")]
    Playback(#[from] crate::playback::PlaybackError),
    /// Ctrl-C / SIGTERM cannot be handled.
    #[error("{0}")]
    Signal(#[from] crate::signal::SignalError),
    /// `proleg dashboard` could not serve.
    #[error("{0}")]
    Dashboard(#[source] crate::dashboard::DashboardError),
    /// A URDF that cannot be imported.
    #[error("{0}")]
    Import(#[from] crate::cli::interop::ImportError),
    /// A robot that cannot be run to let it settle.
    #[error("{0}")]
    Settle(#[from] crate::cli::interop::SettleError),
    /// A benchmark that cannot run.
    #[error("{0}")]
    Bench(#[from] crate::bench::error::BenchError),
    /// The stages' timing that cannot run.
    #[error("{0}")]
    Stages(#[from] crate::bench::stages::StagesError),
    /// Physics checks that cannot run.
    #[error("{0}")]
    PhysicsCheck(#[from] crate::bench::physics_checks::PhysicsCheckError),
    /// The experiment store.
    #[error("{0}")]
    Store(#[from] crate::optimize::store::StoreError),
    /// An optimization that cannot be set up or run.
    #[error("{0}")]
    Optimize(#[from] crate::optimize::error::OptimizeError),
    /// A servo calibration that cannot be done.
    #[error("{0}")]
    Calibrate(#[source] Box<crate::calibrate::CalibrateError>),
    /// A run setting that cannot be used.
    #[error("{0}")]
    Choice(#[from] crate::optimize::error::BadChoice),
    /// An episode that cannot be run.
    #[error("{0}")]
    Eval(#[from] crate::optimize::evaluate::EvalError),
    /// A stored evaluation that cannot be replayed.
    #[error("{0}")]
    Replay(#[from] crate::optimize::replay::ReplayError),
    /// Physics settings that cannot be used.
    #[error("{0}")]
    Physics(#[from] crate::sim::engine::EngineSettingsError),
    /// A kernel that cannot be built.
    #[error("{0}")]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// The real robot's run.
    #[error("{0}")]
    RealMode(#[from] crate::robot_io::real_mode::RealModeError),
    /// The servo emulator.
    #[error("{0}")]
    Emulator(#[from] crate::robot_io::emulator::EmulatorError),
    /// A plugin crate.
    #[error("{0}")]
    Plugin(#[from] crate::plugin_host::error::PluginError),
    /// An import or export.
    #[error("{0}")]
    Interop(#[from] crate::interop::InteropError),
    /// A weights file that cannot be read or written.
    #[error("{0}")]
    Policy(#[source] Box<crate::control::policy::PolicyError>),
    /// An environment that cannot run.
    #[error("{0}")]
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

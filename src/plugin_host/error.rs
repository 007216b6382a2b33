//! The plugin host's errors: declaring, writing, building and installing plugin crates.
//! A library that does not load is a [`crate::plugin_host::library::LoadError`] (its file
//! and cause), kept in the scan's report.

use std::path::PathBuf;

/// A plugin crate that cannot be declared, written, built or installed.
#[derive(Debug, thiserror::Error)]
pub enum PluginError {
    /// A file or folder operation failed.
    #[error("{what} {}: {source}", path.display())]
    Io {
        /// What was being done.
        what: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A `--param` that is not `NAME=VALUE[:MIN..MAX]`.
    #[error("--param {spec:?}: {why}")]
    Param {
        /// The declaration given.
        spec: String,
        /// What is wrong.
        why: String,
    },
    /// A declaration whose names or values cannot become a crate.
    #[error("{}", .0.iter().map(ToString::to_string).collect::<Vec<_>>().join("; "))]
    Declaration(Vec<DeclProblem>),
    /// A folder that is not the plugin workspace.
    #[error("{} is not the plugin workspace (no api/Cargo.toml)", .0.display())]
    NotAWorkspace(PathBuf),
    /// A crate folder that exists already.
    #[error("{} exists already", .0.display())]
    Exists(PathBuf),
    /// No crate of this name in the workspace.
    #[error("no plugin crate {name} in {}; plugin crates: {}", workspace.display(), known.join(", "))]
    NoCrate {
        /// The name asked for.
        name: String,
        /// The workspace.
        workspace: PathBuf,
        /// Its plugin crates.
        known: Vec<String>,
    },
    /// A workspace without plugin crates.
    #[error("no plugin crates in {} (make one with proleg plugin new NAME)", .0.display())]
    NoCrates(PathBuf),
    /// Cargo could not be run.
    #[error("could not run {}: {source}", cargo.display())]
    Cargo {
        /// The cargo program.
        cargo: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// Cargo ran and failed.
    #[error("the build failed:\n{0}")]
    BuildFailed(String),
    /// The library was built but does not load.
    #[error("built, but it does not load: {0}")]
    DoesNotLoad(crate::plugin_host::library::LoadError),
    /// The module editor cannot do this now (no module open, a build running, the build
    /// thread gone).
    #[error("{0}")]
    Editor(&'static str),
    /// No fresh folder could be made for library copies.
    #[error("{}: no fresh folder {prefix}-N could be made", parent.display())]
    NoFreshFolder {
        /// The parent folder.
        parent: PathBuf,
        /// The folders' prefix.
        prefix: String,
    },
}

/// One problem of a module declaration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DeclProblem {
    /// A module name that is no identifier.
    #[error("module name {0:?}: use letters, digits and _ (starting with a letter)")]
    ModuleName(String),
    /// A parameter name that cannot be a Rust name.
    #[error("parameter name {0:?} is not usable")]
    ParamName(String),
    /// An initial value outside its range.
    #[error("parameter {name}: initial value {initial} outside {min}..{max}")]
    Initial {
        /// The parameter.
        name: String,
        /// Its initial value.
        initial: f64,
        /// Its minimum.
        min: f64,
        /// Its maximum.
        max: f64,
    },
    /// A data series name that cannot be a Rust name.
    #[error("data series name {0:?} is not usable")]
    SeriesName(String),
    /// A helper name that is no Rust function name.
    #[error("helper name {0:?} is not a Rust function name")]
    HelperName(String),
    /// A name declared twice.
    #[error("{0} is declared twice")]
    Twice(String),
}

impl PluginError {
    /// An I/O error while doing `what` with `path`.
    pub fn io(what: &'static str, path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| PluginError::Io { what, path, source }
    }
}

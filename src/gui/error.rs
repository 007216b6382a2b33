//! The windows' errors: what a window could not open, load, connect or write, typed; a
//! window shows them as its status or error line, the command line prints them.

use std::path::PathBuf;

/// Why a window, a view or a device of it failed.
#[derive(Debug, thiserror::Error)]
pub enum GuiError {
    /// A configuration file that does not load or check.
    #[error(transparent)]
    Config(#[from] crate::config::ConfigError),
    /// A world that cannot be built or read.
    #[error(transparent)]
    Sim(#[from] crate::sim::SimError),
    /// A kernel that cannot be built or changed.
    #[error(transparent)]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// A stored evaluation that cannot be replayed.
    #[error(transparent)]
    Replay(#[from] crate::optimize::replay::ReplayError),
    /// A composition (wizard, expert dialog, robot builder).
    #[error(transparent)]
    Compose(#[from] crate::compose::error::ComposeError),
    /// A robot the builder cannot build.
    #[error(transparent)]
    Build(#[from] crate::config::robot_builder::BuildError),
    /// The environment editor or its file.
    #[error(transparent)]
    Edit(#[from] crate::compose::env_edit::EditError),
    /// A script that cannot be read or parsed.
    #[error(transparent)]
    Script(Box<crate::gui::scripting::ScriptError>),
    /// The real robot.
    #[error(transparent)]
    Robot(#[from] crate::robot_io::RobotError),
    /// A video that cannot be recorded.
    #[error(transparent)]
    Video(#[from] crate::gui::video::VideoError),
    /// A file that cannot be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A joint mask that is not one 0 or 1 per joint, or selects none.
    #[error("joint mask {mask:?}: {why}")]
    Mask {
        /// The mask.
        mask: String,
        /// What is wrong.
        why: String,
    },
    /// Something the user named that is not there (a module type, a binding).
    #[error("no {what} {name}")]
    Missing {
        /// What kind of thing.
        what: &'static str,
        /// Its name or number.
        name: String,
    },
    /// What the view cannot do in its state (not connected, no command typed).
    #[error("{0}")]
    NotNow(&'static str),
    /// A step width that is not positive.
    #[error("step width {0} s: give a positive number")]
    StepWidth(f64),
    /// The window's event loop ended with a failure status.
    #[error("the {window} closed with status {code}")]
    Closed {
        /// Which window.
        window: &'static str,
        /// Its status.
        code: std::num::NonZero<u8>,
    },
}

impl From<crate::gui::scripting::ScriptError> for GuiError {
    fn from(e: crate::gui::scripting::ScriptError) -> Self {
        GuiError::Script(Box::new(e))
    }
}

impl GuiError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| GuiError::Io { path, source }
    }
}

//! The windows' errors: what a window could not open, load, connect or write, what a
//! script or a video could not do, typed; a window shows them as its status or error
//! line, the command line prints them. They live together here, so the views that
//! raise them and the errors that wrap each other import no view.

use std::path::PathBuf;

/// Why a window, a view or a device of it failed.
#[derive(Debug, thiserror::Error)]
pub enum GuiError {
    /// A configuration file that does not load or check.
    #[error("{0}")]
    Config(#[from] crate::config::ConfigError),
    /// A world that cannot be built or read.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// A kernel that cannot be built or changed.
    #[error("{0}")]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// A stored evaluation that cannot be replayed.
    #[error("{0}")]
    Replay(#[from] crate::optimize::replay::ReplayError),
    /// A composition (wizard, expert dialog, robot builder).
    #[error("{0}")]
    Compose(#[from] crate::compose::error::ComposeError),
    /// A robot the builder cannot build.
    #[error("{0}")]
    Build(#[from] crate::config::robot_builder::BuildError),
    /// The environment editor or its file.
    #[error("{0}")]
    Edit(#[from] crate::compose::env_edit::EditError),
    /// A script that cannot be read or parsed.
    #[error("{0}")]
    Script(#[source] Box<ScriptError>),
    /// The real robot.
    #[error("{0}")]
    Robot(#[from] crate::robot_io::RobotError),
    /// A video that cannot be recorded.
    #[error("{0}")]
    Video(#[from] VideoError),
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
    /// `--script` in a build without the script interpreters.
    #[error(
        "{}: this proleg was built without the `scripts` feature, so its windows run no scripts (the GUI tests and scripts/screenshots build with --features scripts)",
        .0.display()
    )]
    NoScripts(PathBuf),
    /// The window's event loop ended with a failure status.
    #[error("the {window} closed with status {code}")]
    Closed {
        /// Which window.
        window: &'static str,
        /// Its status.
        code: std::num::NonZero<u8>,
    },
}

impl From<ScriptError> for GuiError {
    fn from(e: ScriptError) -> Self {
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

/// Why a script cannot run: it cannot be read, a line does not parse, or a command failed
/// (its file and line).
#[derive(Debug, thiserror::Error)]
pub enum ScriptError {
    /// The script file cannot be read.
    #[error("{}: {source}", path.display())]
    Read {
        /// The script.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A line that is no command of the window.
    #[error("{}:{line}: {why}", file.display())]
    Parse {
        /// The script.
        file: PathBuf,
        /// The line (from 1).
        line: usize,
        /// The parser's message.
        why: String,
    },
    /// A command that failed.
    #[error("{}:{line}: {source}", file.display())]
    Command {
        /// The script.
        file: PathBuf,
        /// The command's line (from 1); 0 for a screenshot never written.
        line: usize,
        /// Why.
        source: Box<CommandError>,
    },
}

/// Why a script command failed.
#[derive(Debug, thiserror::Error)]
pub enum CommandError {
    /// A screenshot that was never written.
    #[error("screenshot {} was not written", .0.display())]
    NoScreenshot(PathBuf),
    /// A `wait-for` whose condition did not come.
    #[error("waited {frames} frames for {what}")]
    Timeout {
        /// The frames waited.
        frames: u32,
        /// The condition.
        what: String,
    },
    /// A file the command writes.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// Something the command names that the window does not have (a module, a link, a tab).
    #[error("no {what} {name}")]
    Missing {
        /// What kind of thing.
        what: &'static str,
        /// Its name or number.
        name: String,
    },
    /// A command that needs what is not there now (a selection, a paused run, an
    /// optimization).
    #[error("{0}")]
    NotNow(&'static str),
    /// The window refused the command and shows why (its status or error line).
    #[error("{0}")]
    Refused(String),
    /// A word that is not a finite number.
    #[error("{0}")]
    Number(#[from] NotFinite),
    /// A command routed to the wrong group of its window (a programming error).
    #[error("internal: {0} reached the wrong command group")]
    Misrouted(String),
    /// The module library.
    #[error("{0}")]
    Plugin(#[from] crate::plugin_host::error::PluginError),
    /// A view or device of the window.
    #[error("{0}")]
    Gui(#[from] GuiError),
    /// The optimization view's Save best.
    #[error("{0}")]
    SaveBest(#[from] SaveBestError),
    /// The simulation.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// A module parameter.
    #[error("{0}")]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// A series selection.
    #[error("{0}")]
    Select(#[from] crate::data::export::SelectError),
    /// The optimization.
    #[error("{0}")]
    Optimize(#[from] crate::optimize::error::OptimizeError),
    /// A composition (wizard, expert dialog).
    #[error("{0}")]
    Compose(#[from] crate::compose::error::ComposeError),
    /// The environment editor.
    #[error("{0}")]
    Edit(#[from] crate::compose::env_edit::EditError),
}

/// A word that is not a finite number.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{0:?} is not a finite number")]
pub struct NotFinite(pub(crate) String);

/// Why a video could not be recorded.
#[derive(Debug, thiserror::Error)]
pub enum VideoError {
    /// An option out of its range.
    #[error("{option} {value}: {want}")]
    Option {
        /// The option.
        option: &'static str,
        /// Its value.
        value: String,
        /// What it must be.
        want: &'static str,
    },
    /// The simulation cannot be opened.
    #[error("{0}")]
    Session(#[source] Box<GuiError>),
    /// The world cannot be read.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// The renderer failed or gave no frames back.
    #[error("{0}")]
    Renderer(String),
    /// A file or folder cannot be written.
    #[error("{}: cannot {what}: {source}", path.display())]
    Io {
        /// What was being done.
        what: &'static str,
        /// The file or folder.
        path: std::path::PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// ffmpeg failed.
    #[error("ffmpeg: {0}")]
    Ffmpeg(String),
    /// A gallery's store or run cannot give its designs.
    #[error("{0}")]
    Replay(#[source] Box<crate::optimize::replay::ReplayError>),
    /// A gallery's run holds no co-design, or its designs cannot be listed.
    #[error("{0}")]
    Designs(#[source] Box<crate::optimize::error::OptimizeError>),
    /// A gallery's run has no design that ran.
    #[error("run {run} has no design that ran yet")]
    NoDesigns {
        /// The run.
        run: i64,
    },
    /// A gallery's captions cannot be drawn.
    #[error("{}: the captions cannot be drawn: {message}", file.display())]
    Caption {
        /// The gallery.
        file: std::path::PathBuf,
        /// The drawing library's message.
        message: String,
    },
    /// A frame of another size than the video's.
    #[error("frame of {}x{} for a {}x{} video", got.0, got.1, want.0, want.1)]
    FrameSize {
        /// The frame's size.
        got: (u32, u32),
        /// The video's.
        want: (u32, u32),
    },
}

/// Why "Save best" wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum SaveBestError {
    /// No evaluation has finished yet.
    #[error("no candidate evaluated yet")]
    NoCandidate,
    /// The file could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The actuation file.
        path: std::path::PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

//! Configuration errors: which file, where in it, what kind, and what was expected.

use std::fmt;
use std::path::{Path, PathBuf};

/// A 1-based line and column in a source file.
///
/// Positions never take part in equality: a model written out and read back equals
/// the original even though every element now sits on another line.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pos {
    /// Line, from 1 (0: no position).
    pub line: u32,
    /// Column, from 1.
    pub col: u32,
}

impl Pos {
    /// The position at `line`, `col`.
    pub const fn new(line: u32, col: u32) -> Self {
        Pos { line, col }
    }
}

impl PartialEq for Pos {
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.col)
    }
}

/// The class of a configuration error, for callers and tests that branch on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file is not well-formed XML.
    Syntax,
    /// An element or attribute that the format does not have.
    UnknownElement,
    /// A required element or attribute is absent.
    Missing,
    /// A value that does not parse (not a number, NaN, wrong count).
    InvalidValue,
    /// A value outside its allowed range.
    OutOfRange,
    /// A joint mask whose length differs from the robot's joint count.
    MaskLength,
    /// An actuation module name that the registry does not know.
    UnknownModule,
    /// A name that refers to nothing (body, joint, parameter).
    UnknownReference,
    /// A file that cannot be read.
    MissingFile,
    /// A file that includes itself, directly or through others.
    IncludeCycle,
}

/// A configuration error with its location.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}:{}: {}{}", .file.display(), .pos, .message, context(.included_from, .more))]
pub struct ConfigError {
    /// The file with the error.
    pub file: PathBuf,
    /// Where in it.
    pub pos: Pos,
    /// What class of error.
    pub kind: ErrorKind,
    /// What is wrong and what was expected.
    pub message: String,
    /// Where the failing file was included from, innermost first.
    pub included_from: Vec<(PathBuf, Pos)>,
    /// Further faults found in the same pass (a file's physical checks report them all).
    pub more: Box<[ConfigError]>,
    /// The system's error beneath it (a file that cannot be read).
    pub source: Option<std::sync::Arc<std::io::Error>>,
}

impl ConfigError {
    /// An error at `pos` of `file`.
    pub fn new(
        file: impl AsRef<Path>,
        pos: Pos,
        kind: ErrorKind,
        message: impl Into<String>,
    ) -> Self {
        ConfigError {
            file: file.as_ref().to_path_buf(),
            pos,
            kind,
            message: message.into(),
            included_from: Vec::new(),
            more: Box::new([]),
            source: None,
        }
    }

    /// The same error, caused by the system's error `e` (kept as its source).
    pub fn caused_by(mut self, e: std::io::Error) -> Self {
        self.source = Some(std::sync::Arc::new(e));
        self
    }

    /// Adds the place that included the failing file.
    pub fn included_from(mut self, file: impl AsRef<Path>, pos: Pos) -> Self {
        self.included_from.push((file.as_ref().to_path_buf(), pos));
        self
    }

    /// The first of `faults` carrying the others, or `None` when there are none.
    pub fn all(mut faults: Vec<ConfigError>) -> Option<ConfigError> {
        if faults.is_empty() {
            return None;
        }
        let mut first = faults.remove(0);
        first.more = faults.into_boxed_slice();
        Some(first)
    }
}

/// The lines after an error's own: where its file was included from, then the further
/// faults of the same pass.
fn context(included_from: &[(PathBuf, Pos)], more: &[ConfigError]) -> String {
    let mut out = String::new();
    for (file, pos) in included_from {
        out.push_str(&format!("\n  included from {}:{}", file.display(), pos));
    }
    for other in more {
        out.push_str(&format!("\n{other}"));
    }
    out
}

/// Shorthand for results of configuration functions.
pub type ConfigResult<T> = Result<T, ConfigError>;

/// A name that is none of the accepted ones (a fitness, an x axis, a mode).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} {name:?}; expected one of {}", expected.join(", "))]
pub struct UnknownName {
    /// What the name should have named.
    pub what: &'static str,
    /// The name given.
    pub name: String,
    /// The accepted names.
    pub expected: &'static [&'static str],
}

impl UnknownName {
    /// `name` is no `what`; `expected` lists the accepted names.
    pub fn new(what: &'static str, name: &str, expected: &'static [&'static str]) -> Self {
        UnknownName {
            what,
            name: name.to_string(),
            expected,
        }
    }
}

//! Rust errors as Python exceptions, with the same message: a file's error is a
//! `proleg.ConfigError` carrying `file`, `line` and `column`; bad input (a wrong shape, a
//! NaN, an unknown name, an option out of range) a `ValueError`; a closed or unreset
//! environment a `RuntimeError`; anything else a `proleg.ProlegError`.

use proleg::config::ConfigError as FileError;
use proleg::gym::GymError;
use proleg::playback::PlaybackError;
use proleg::sim::SimError;
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _native,
    ProlegError,
    PyException,
    "An error of the proleg library (its message says what failed and why)."
);
create_exception!(
    _native,
    ConfigError,
    ProlegError,
    "A configuration file that does not load: `file`, `line` and `column` say where."
);

/// Adds the exception types to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("ProlegError", py.get_type::<ProlegError>())?;
    m.add("ConfigError", py.get_type::<ConfigError>())?;
    Ok(())
}

/// A file's error, located.
pub fn config_error(e: &FileError) -> PyErr {
    Python::attach(|py| {
        let err = ConfigError::new_err(e.to_string());
        let value = err.value(py);
        let located = value
            .setattr("file", e.file.display().to_string())
            .and_then(|()| value.setattr("line", e.pos.line))
            .and_then(|()| value.setattr("column", e.pos.col));
        match located {
            Ok(()) => err,
            Err(setattr) => setattr,
        }
    })
}

/// An environment's error.
pub fn gym_error(e: GymError) -> PyErr {
    match e {
        GymError::Config(c) => config_error(&c),
        GymError::Sim(s) => sim_error(s),
        GymError::Option { .. } | GymError::Shape { .. } | GymError::NotFinite { .. } => {
            PyValueError::new_err(e.to_string())
        }
        GymError::Kernel(_)
        | GymError::NoTask { .. }
        | GymError::HeldOut { .. }
        | GymError::NoTerrain(_) => PyValueError::new_err(e.to_string()),
        GymError::State(_) => PyRuntimeError::new_err(e.to_string()),
        // As Python says of a keyword a function does not take.
        GymError::UnknownOption { .. } => PyTypeError::new_err(e.to_string()),
        _ => ProlegError::new_err(e.to_string()),
    }
}

/// A world's error.
pub fn sim_error(e: SimError) -> PyErr {
    match e {
        SimError::Config(c) => config_error(&c),
        SimError::Kernel(_) | SimError::NoSuchRobot { .. } | SimError::NoSuchLink { .. } => {
            PyValueError::new_err(e.to_string())
        }
        _ => ProlegError::new_err(e.to_string()),
    }
}

/// A replay's error: not one or two replays for a page is bad input.
pub fn playback_error(e: PlaybackError) -> PyErr {
    match e {
        PlaybackError::Streams(_) | PlaybackError::Fps(_) => PyValueError::new_err(e.to_string()),
        PlaybackError::Sim(s) => sim_error(s),
        _ => ProlegError::new_err(e.to_string()),
    }
}

/// Any other error of the library.
pub fn other(e: impl std::fmt::Display) -> PyErr {
    ProlegError::new_err(e.to_string())
}

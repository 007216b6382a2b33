//! The browser's 3D replay from Python: `Replay`, an episode's pose stream (an
//! environment's recording, `Env.replay`), and `write_html`, one self-contained page
//! playing one replay, or two on one timeline (the library's
//! `proleg::playback::page::write_standalone`, the page `proleg run --html` writes).

use std::path::PathBuf;

use proleg::playback::PoseStream;
use proleg::playback::page::write_standalone;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::{other, playback_error};

/// An episode as the 3D replay plays it: its scene and, per frame, every moving body's
/// pose, the joint angles, the pads' contacts and the score so far.
#[pyclass(module = "proleg._native", frozen)]
pub struct Replay {
    stream: PoseStream,
}

impl Replay {
    /// The stream.
    pub fn new(stream: PoseStream) -> Replay {
        Replay { stream }
    }
}

#[pymethods]
impl Replay {
    /// Frames recorded (the first at the reset).
    #[getter]
    fn frames(&self) -> usize {
        self.stream.frames
    }

    /// Simulated seconds between two frames.
    #[getter]
    fn frame_seconds(&self) -> f64 {
        self.stream.frame_seconds
    }

    /// The page's title for it.
    #[getter]
    fn label(&self) -> &str {
        &self.stream.label
    }

    /// The engine and its settings.
    #[getter]
    fn engine(&self) -> &str {
        &self.stream.engine
    }

    /// How the episode ended (or that it goes on).
    #[getter]
    fn end(&self) -> &str {
        &self.stream.end
    }

    /// Moving body `body`'s position (m) and rotation (x, y, z, w) at frame `frame`, as
    /// the page decodes them.
    fn pose(&self, frame: usize, body: usize) -> PyResult<([f64; 3], [f64; 4])> {
        self.stream.pose_at(frame, body).ok_or_else(|| {
            PyValueError::new_err(format!(
                "no body {body} at frame {frame}: the replay has {} frames",
                self.stream.frames
            ))
        })
    }

    /// The stream as the page reads it (JSON).
    fn to_json(&self) -> PyResult<String> {
        self.stream.to_json().map_err(other)
    }
}

/// Writes the self-contained page playing `replays` (one, or two side by side on one
/// timeline) to `path`; returns its size in bytes.
#[pyfunction]
pub fn write_html(py: Python<'_>, path: PathBuf, replays: Vec<Py<Replay>>) -> PyResult<u64> {
    let streams: Vec<&PoseStream> = replays.iter().map(|r| &r.get().stream).collect();
    py.detach(|| write_standalone(&path, &streams))
        .map_err(playback_error)
}

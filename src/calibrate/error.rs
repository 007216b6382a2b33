//! Why a calibration cannot be done: the calibration's errors, typed, turned into text
//! only where they are printed.

use std::path::PathBuf;

use crate::calibrate::recording::{self, MIN_SAMPLES};

/// Why a calibration cannot be done.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// The data file cannot be read.
    #[error("{0}")]
    Data(#[from] crate::data::read::DataError),
    /// The data file lacks the joint series.
    #[error("{}: {desired} desired and {real} real joint positions recorded; a calibration needs both for every joint ({} and {})", file.display(), recording::DESIRED, recording::REAL)]
    Series {
        /// The data file.
        file: PathBuf,
        /// Desired-position columns found.
        desired: usize,
        /// Real-position columns found.
        real: usize,
    },
    /// The recording is of another robot.
    #[error("{}: {found} joints recorded, but robot {robot} has {expected}: record this robot", file.display())]
    JointCount {
        /// The data file.
        file: PathBuf,
        /// Joints recorded.
        found: usize,
        /// The robot's name.
        robot: String,
        /// Its joints.
        expected: usize,
    },
    /// Too few samples to fit anything.
    #[error("{}: {samples} samples over {seconds:.2} s; a calibration needs at least {MIN_SAMPLES}", file.display())]
    TooShort {
        /// The data file.
        file: PathBuf,
        /// Samples.
        samples: usize,
        /// Seconds recorded.
        seconds: f64,
    },
    /// A joint to calibrate is declared in an included part, not in the robot file.
    #[error(
        "joint {joint} is declared in an included part file: the calibrated values are written on the robot file's own joints"
    )]
    JointElsewhere {
        /// The joint's name.
        joint: String,
    },
    /// The gait's simulation cannot be built or read.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// The picture cannot be drawn.
    #[error("{}: cannot draw: {message}", file.display())]
    Plot {
        /// The PNG.
        file: PathBuf,
        /// The drawing library's message.
        message: String,
    },
    /// A file cannot be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
}

//! Why a replay could not be recorded or its page written.

use std::path::PathBuf;

/// Why a replay could not be recorded or its page written.
#[derive(Debug, thiserror::Error)]
pub enum PlaybackError {
    /// The world: building, stepping or reading it.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// A frame rate that is not a positive number.
    #[error("{0} frames per second: give a number above 0")]
    Fps(f64),
    /// Not one or two streams for a page.
    #[error("{0} replays: the page plays one, or two on one timeline")]
    Streams(usize),
    /// The stream could not be turned into JSON.
    #[error("the replay could not be encoded: {0}")]
    Encode(#[source] serde_json::Error),
    /// The page could not be written.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
}

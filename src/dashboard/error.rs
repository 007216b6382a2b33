//! The dashboard's errors: where it could not listen, or why its store could not be read at
//! start. Turned into text only where they are printed.

use std::net::SocketAddr;

/// Why the dashboard could not serve.
#[derive(Debug, thiserror::Error)]
pub enum DashboardError {
    /// `--bind` is not an address and port.
    #[error("--bind {given}: not an address:port (e.g. 127.0.0.1:8080)")]
    BadBind {
        /// What was given.
        given: String,
    },
    /// The address could not be listened on (taken, not this host's).
    #[error("cannot listen on {addr}: {source}")]
    Listen {
        /// The address.
        addr: SocketAddr,
        /// The system's error.
        source: std::io::Error,
    },
    /// The async runtime could not start, or the server stopped with an I/O error.
    #[error("the web server failed: {0}")]
    Server(#[source] std::io::Error),
    /// The store could not be read at start.
    #[error("{0}")]
    Store(#[from] crate::optimize::store::StoreError),
    /// The stop signal could not be subscribed to.
    #[error("{0}")]
    Signal(#[from] crate::signal::SignalError),
}

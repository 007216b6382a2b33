//! The experiment store's errors: what failed and in which store, named as it may be shown
//! (a PostgreSQL URL without its password). Turned into text only where it is printed.

use std::path::PathBuf;

use crate::optimize::store::SCHEMA_VERSION;

/// A store operation that failed.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// An SQLite store that must exist does not (reading results).
    #[error("{}: no such store", path.display())]
    Missing {
        /// The file asked for.
        path: PathBuf,
    },
    /// The folder of a new SQLite store could not be made.
    #[error("{}: cannot make the store's folder: {source}", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The system's error.
        #[source]
        source: std::io::Error,
    },
    /// The SQLite driver failed.
    #[error("{}: {source}", path.display())]
    Sqlite {
        /// The store's file.
        path: PathBuf,
        /// The driver's error.
        #[source]
        source: rusqlite::Error,
    },
    /// The PostgreSQL server or its driver failed: the store and the server's message
    /// (or the connection's chain of causes).
    #[error("{store}: {message}")]
    Postgres {
        /// The store, without password.
        store: String,
        /// The cause.
        message: String,
    },
    /// No PostgreSQL server answered at the store's address (refused, unreachable, timed
    /// out): one that may yet come up, unlike a refused password.
    #[error("{store}: no server answers: {message}")]
    NoServer {
        /// The store, without password.
        store: String,
        /// The connection's chain of causes.
        message: String,
    },
    /// TLS could not be set up for a PostgreSQL connection.
    #[error("{store}: cannot set up TLS: {message}")]
    Tls {
        /// The store, without password.
        store: String,
        /// The TLS library's message.
        message: String,
    },
    /// A store of another schema version than this program's.
    #[error("{store}: the store has schema version {found}; this proleg reads version {SCHEMA_VERSION}{}", if *.found > SCHEMA_VERSION { " (a newer proleg wrote it)" } else { "" })]
    Schema {
        /// The store.
        store: String,
        /// Its version.
        found: i64,
    },
    /// A database opened for reading holds no proleg store.
    #[error(
        "{store}: no proleg store in this database (no table proleg_meta); `proleg optimize --store URL` creates it"
    )]
    NotAStore {
        /// The store, without password.
        store: String,
    },
    /// A database whose tables of the store's names belong to something else.
    #[error(
        "{store}: the database has tables named runs or evaluations that are not a proleg store; use another database"
    )]
    Foreign {
        /// The store, without password.
        store: String,
    },
    /// A run the store does not hold.
    #[error("{store}: no run {run}")]
    NoRun {
        /// The store.
        store: String,
        /// The run asked for.
        run: i64,
    },
    /// A store that holds no run yet.
    #[error("{store}: no runs stored")]
    NoRuns {
        /// The store.
        store: String,
    },
    /// A stored evaluation whose column cannot be read back.
    #[error("{store}: run {run}, {evaluation}: {column} `{text}` is not {expected}")]
    Corrupt {
        /// The store.
        store: String,
        /// The run.
        run: i64,
        /// Which evaluation (`evaluation 12`, `its best evaluation`).
        evaluation: String,
        /// The column.
        column: &'static str,
        /// What it holds.
        text: String,
        /// What it should hold.
        expected: &'static str,
    },
    /// A shared store that stayed unreachable.
    #[error("the store has been unreachable for {seconds:.0} s: {last}")]
    Unreachable {
        /// How long it was tried.
        seconds: f64,
        /// The last attempt's error.
        last: Box<StoreError>,
    },
}

//! The background writer: the simulation hands finished rounds to a thread that formats
//! and appends them to the data file and flushes after each, so a step never waits on
//! the disk and a killed process leaves every flushed round readable. Closing writes the
//! end tag (normal exit, Ctrl-C and SIGTERM all end through [`DataStore::finish`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use crate::data::handler::HandlerSpec;
use crate::data::write::{FOOTER, HandlerFrames, header, round};

/// Why a data file could not be written.
#[derive(Debug, thiserror::Error)]
pub enum DataStoreError {
    /// The file could not be created.
    #[error("{}: cannot create: {source}", path.display())]
    Create {
        /// The data file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// Writing or flushing the file failed (a full disk, a lost mount).
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The data file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The writer thread could not be started.
    #[error("cannot start the data writer: {0}")]
    Spawn(std::io::Error),
    /// The writer thread stopped (after a write error, which [`DataStore::finish`] returns).
    #[error("{}: the data writer stopped", path.display())]
    Stopped {
        /// The data file.
        path: PathBuf,
    },
    /// A round sent after the file was closed.
    #[error("the data file is closed")]
    Closed,
    /// The writer thread panicked.
    #[error("{}: the data writer panicked", path.display())]
    Panicked {
        /// The data file.
        path: PathBuf,
    },
}

/// A data file being written.
pub struct DataStore {
    path: PathBuf,
    sender: Option<Sender<Vec<HandlerFrames>>>,
    thread: Option<JoinHandle<Result<u64, DataStoreError>>>,
}

impl DataStore {
    /// Creates `path` and writes the header; rounds follow with [`DataStore::send`].
    pub fn create(path: &Path, handlers: Vec<HandlerSpec>) -> Result<DataStore, DataStoreError> {
        let file = File::create(path).map_err(|source| DataStoreError::Create {
            path: path.to_path_buf(),
            source,
        })?;
        let mut out = BufWriter::with_capacity(1 << 20, file);
        out.write_all(header(&handlers).as_bytes())
            .and_then(|_| out.flush())
            .map_err(|source| DataStoreError::Write {
                path: path.to_path_buf(),
                source,
            })?;
        let (sender, receiver) = channel();
        let name = path.to_path_buf();
        let thread = std::thread::Builder::new()
            .name("proleg-data-writer".into())
            .spawn(move || write_rounds(out, &handlers, receiver, name))
            .map_err(DataStoreError::Spawn)?;
        Ok(DataStore {
            path: path.to_path_buf(),
            sender: Some(sender),
            thread: Some(thread),
        })
    }

    /// The data file written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Queues one round (one `HandlerFrames` per handler, header order). Never blocks.
    pub fn send(&self, frames: Vec<HandlerFrames>) -> Result<(), DataStoreError> {
        match &self.sender {
            Some(s) => s.send(frames).map_err(|_| DataStoreError::Stopped {
                path: self.path.clone(),
            }),
            None => Err(DataStoreError::Closed),
        }
    }

    /// Writes what is queued, closes the document and the file; returns the rounds written.
    pub fn finish(mut self) -> Result<u64, DataStoreError> {
        self.close()
    }

    fn close(&mut self) -> Result<u64, DataStoreError> {
        drop(self.sender.take());
        match self.thread.take() {
            Some(t) => t.join().map_err(|_| DataStoreError::Panicked {
                path: self.path.clone(),
            })?,
            None => Ok(0),
        }
    }
}

impl Drop for DataStore {
    fn drop(&mut self) {
        if let Err(e) = self.close() {
            eprintln!("warning: {e}");
        }
    }
}

fn write_rounds(
    mut out: BufWriter<File>,
    handlers: &[HandlerSpec],
    rounds: Receiver<Vec<HandlerFrames>>,
    path: PathBuf,
) -> Result<u64, DataStoreError> {
    let mut text = String::new();
    let mut n = 0;
    let fail = |source| DataStoreError::Write {
        path: path.clone(),
        source,
    };
    for frames in rounds {
        text.clear();
        round(&mut text, n, handlers, &frames);
        out.write_all(text.as_bytes()).map_err(fail)?;
        out.flush().map_err(fail)?;
        n += 1;
    }
    out.write_all(FOOTER.as_bytes()).map_err(fail)?;
    out.flush().map_err(fail)?;
    out.get_ref().sync_all().map_err(fail)?;
    Ok(n)
}

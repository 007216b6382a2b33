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

/// A data file being written.
pub struct DataStore {
    path: PathBuf,
    sender: Option<Sender<Vec<HandlerFrames>>>,
    thread: Option<JoinHandle<Result<u64, String>>>,
}

impl DataStore {
    /// Creates `path` and writes the header; rounds follow with [`DataStore::send`].
    pub fn create(path: &Path, handlers: Vec<HandlerSpec>) -> Result<DataStore, String> {
        let file =
            File::create(path).map_err(|e| format!("{}: cannot create: {e}", path.display()))?;
        let mut out = BufWriter::with_capacity(1 << 20, file);
        out.write_all(header(&handlers).as_bytes())
            .and_then(|_| out.flush())
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
        let (sender, receiver) = channel();
        let name = path.display().to_string();
        let thread = std::thread::Builder::new()
            .name("proleg-data-writer".into())
            .spawn(move || write_rounds(out, &handlers, receiver, &name))
            .map_err(|e| format!("cannot start the data writer: {e}"))?;
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
    pub fn send(&self, frames: Vec<HandlerFrames>) -> Result<(), String> {
        match &self.sender {
            Some(s) => s
                .send(frames)
                .map_err(|_| format!("{}: the data writer stopped", self.path.display())),
            None => Err("the data file is closed".into()),
        }
    }

    /// Writes what is queued, closes the document and the file; returns the rounds written.
    pub fn finish(mut self) -> Result<u64, String> {
        self.close()
    }

    fn close(&mut self) -> Result<u64, String> {
        drop(self.sender.take());
        match self.thread.take() {
            Some(t) => t
                .join()
                .map_err(|_| format!("{}: the data writer panicked", self.path.display()))?,
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
    name: &str,
) -> Result<u64, String> {
    let mut text = String::new();
    let mut n = 0;
    let fail = |e: std::io::Error| format!("{name}: cannot write: {e}");
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

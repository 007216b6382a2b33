//! The journal of a suite run: one line per finished episode, appended and flushed as each
//! ends, so a run stopped halfway (Ctrl-C, a lost machine) resumes from what it had and
//! reaches the same table. Its first line names the run (the suite and a fingerprint of the
//! controller), so the journal of another run is refused rather than mixed in.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use crate::config::simulation::EngineKind;
use crate::config::suite::SuiteFile;
use crate::sim::episode::course::{Ended, EpisodeKey, EpisodeResult};
use crate::suite::error::{BadLine, COLUMNS, SuiteError};

/// An open journal: what it held when opened, and the file to append to.
pub struct Journal {
    path: PathBuf,
    file: File,
    /// The episodes finished before (by key).
    pub done: BTreeMap<EpisodeKey, EpisodeResult>,
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> SuiteError + '_ {
    move |source| SuiteError::Journal {
        path: path.to_path_buf(),
        source,
    }
}

impl Journal {
    /// Opens (or starts) the journal at `path` of a run named by `run_line`; lines of
    /// tasks the suite does not have are errors, a last line cut short is dropped.
    pub fn open(path: &Path, run_line: &str, suite: &SuiteFile) -> Result<Journal, SuiteError> {
        let mut done = BTreeMap::new();
        let text = match std::fs::read_to_string(path) {
            Ok(t) => Some(t),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(io(path)(e)),
        };
        let mut keep = 0;
        if let Some(text) = &text {
            let bad = |line: usize, why: BadLine| SuiteError::JournalLine {
                path: path.to_path_buf(),
                line,
                why,
            };
            let mut lines = text.split_inclusive('\n').enumerate();
            match lines.next() {
                Some((_, first)) if first.trim_end() == run_line => {}
                Some((_, first)) => {
                    return Err(bad(
                        1,
                        BadLine::AnotherRun {
                            found: first.trim_end().to_string(),
                            this: run_line.to_string(),
                        },
                    ));
                }
                None => {}
            }
            keep = text.len();
            for (i, line) in lines {
                if !line.ends_with('\n') {
                    // Cut short by a crash while it was written: that episode runs again.
                    keep = text.len() - line.len();
                    break;
                }
                let line = line.trim_end();
                if line == COLUMNS || line.is_empty() {
                    continue;
                }
                let r = parse_line(line, suite).map_err(|why| bad(i + 1, why))?;
                done.insert(r.key, r);
            }
        }
        let mut file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(io(path))?;
        if text.as_ref().is_some_and(|t| keep < t.len()) {
            file.set_len(keep as u64).map_err(io(path))?;
        }
        if text.as_ref().is_none_or(|t| t.is_empty()) {
            file.write_all(format!("{run_line}\n{COLUMNS}\n").as_bytes())
                .map_err(io(path))?;
        }
        Ok(Journal {
            path: path.to_path_buf(),
            file,
            done,
        })
    }

    /// Appends a finished episode (one write, flushed).
    pub fn append(&mut self, suite: &SuiteFile, r: &EpisodeResult) -> Result<(), SuiteError> {
        let line = format_line(suite, r);
        self.file
            .write_all(line.as_bytes())
            .map_err(io(&self.path))?;
        self.file.flush().map_err(io(&self.path))?;
        self.done.insert(r.key, *r);
        Ok(())
    }
}

/// One journal line (with its newline).
pub fn format_line(suite: &SuiteFile, r: &EpisodeResult) -> String {
    let task = suite.tasks.get(r.key.task).map_or("?", |t| t.name.as_str());
    // The shortest text that reads back to the same number: a resumed run's table is the
    // uninterrupted one's, to the last bit.
    format!(
        "{task},{},{},{},{},{}\n",
        r.key.seed,
        r.key.engine.name(),
        r.distance,
        u8::from(r.crossed),
        r.ended.name()
    )
}

fn parse_line(line: &str, suite: &SuiteFile) -> Result<EpisodeResult, BadLine> {
    let f: Vec<&str> = line.split(',').collect();
    let [task, seed, engine, distance, crossed, ended] = f.as_slice() else {
        return Err(BadLine::Columns(line.to_string()));
    };
    let bad = |column: &'static str, text: &str| BadLine::Value(column, text.to_string());
    let task = suite
        .tasks
        .iter()
        .position(|t| t.name == *task)
        .ok_or_else(|| BadLine::Task(task.to_string()))?;
    let seed = seed.parse::<u64>().map_err(|_| bad("seed", seed))?;
    let engine = EngineKind::parse(engine).ok_or_else(|| bad("engine", engine))?;
    let distance = f64::from_str(distance)
        .ok()
        .filter(|d| d.is_finite())
        .ok_or_else(|| bad("distance", distance))?;
    let crossed = match *crossed {
        "1" => true,
        "0" => false,
        other => return Err(bad("crossed (0 or 1)", other)),
    };
    let ended = Ended::parse(ended).ok_or_else(|| bad("ended", ended))?;
    Ok(EpisodeResult {
        key: EpisodeKey { task, seed, engine },
        distance,
        crossed,
        ended,
    })
}

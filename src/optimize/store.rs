//! The experiment store: every finished evaluation of every run in an embedded SQLite
//! database (WAL journal), written as its batch finishes, so a killed run loses nothing
//! finished and `--resume` replays it without re-running what is stored.

use std::path::{Path, PathBuf};

use rusqlite::{Connection, OptionalExtension, params};

use crate::optimize::space::Genome;

/// What identifies a run (a resumed run must match all of it).
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// The simulation file.
    pub config: String,
    /// The optimizer's name.
    pub algorithm: String,
    /// Seed of the run.
    pub seed: u64,
    /// Fitness name.
    pub fitness: String,
    /// Simulated seconds per episode.
    pub duration: f64,
    /// Gene labels, in genome order.
    pub genes: Vec<String>,
}

/// A stored run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// The run's id.
    pub id: i64,
    /// What was run.
    pub info: RunInfo,
    /// When it started (UTC).
    pub started: String,
    /// Whether it ran to its end.
    pub finished: bool,
    /// Evaluations stored.
    pub evaluations: u64,
    /// The best score stored.
    pub best_score: Option<f64>,
    /// The best candidate's values, as text.
    pub best_values: Option<String>,
}

/// One stored evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredEval {
    /// 0-based evaluation number.
    pub number: u64,
    /// Round it belonged to.
    pub round: u64,
    /// The candidate.
    pub genome: Genome,
    /// Its parameter values.
    pub values: Vec<f64>,
    /// Its score.
    pub score: f64,
    /// Wall seconds of its batch, shared by the batch's candidates.
    pub wall: f64,
}

/// An open store.
pub struct Store {
    conn: Connection,
    path: PathBuf,
    stored: u64,
    crash_after: Option<u64>,
}

fn join<T: ToString>(v: &[T]) -> String {
    v.iter().map(T::to_string).collect::<Vec<_>>().join(" ")
}

impl Store {
    /// Opens (creating if needed) the store at `path`.
    pub fn open(path: &Path) -> Result<Store, String> {
        let fail = |e: rusqlite::Error| format!("{}: {e}", path.display());
        let conn = Connection::open(path).map_err(fail)?;
        conn.pragma_update(None, "journal_mode", "WAL")
            .map_err(fail)?;
        conn.pragma_update(None, "synchronous", "NORMAL")
            .map_err(fail)?;
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS runs (
                id INTEGER PRIMARY KEY,
                config TEXT NOT NULL, algorithm TEXT NOT NULL, seed INTEGER NOT NULL,
                fitness TEXT NOT NULL, duration REAL NOT NULL, genes TEXT NOT NULL,
                started TEXT NOT NULL DEFAULT (datetime('now')),
                finished INTEGER NOT NULL DEFAULT 0);
             CREATE TABLE IF NOT EXISTS evaluations (
                run INTEGER NOT NULL REFERENCES runs(id), number INTEGER NOT NULL,
                round INTEGER NOT NULL, genome TEXT NOT NULL, vals TEXT NOT NULL,
                score REAL, seed INTEGER NOT NULL, wall REAL NOT NULL,
                PRIMARY KEY (run, number));",
        )
        .map_err(fail)?;
        Ok(Store {
            conn,
            path: path.to_path_buf(),
            stored: 0,
            crash_after: None,
        })
    }

    /// Testing aid for resumption: abort the process (no clean-up, like `kill -9`) right
    /// after the batch that brings this session's stored evaluations to `n` is committed.
    pub fn crash_after(&mut self, n: u64) {
        self.crash_after = Some(n);
    }

    /// The store's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn fail(&self, e: rusqlite::Error) -> String {
        format!("{}: {e}", self.path.display())
    }

    /// Registers a new run; returns its id.
    pub fn start_run(&self, info: &RunInfo) -> Result<i64, String> {
        self.conn
            .execute(
                "INSERT INTO runs (config, algorithm, seed, fitness, duration, genes) VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
                params![info.config, info.algorithm, info.seed as i64, info.fitness, info.duration, info.genes.join("\t")],
            )
            .map_err(|e| self.fail(e))?;
        Ok(self.conn.last_insert_rowid())
    }

    /// The latest unfinished run matching `info`.
    pub fn find_unfinished(&self, info: &RunInfo) -> Result<Option<i64>, String> {
        self.conn
            .query_row(
                "SELECT id FROM runs WHERE config = ?1 AND algorithm = ?2 AND seed = ?3 AND fitness = ?4
                 AND duration = ?5 AND genes = ?6 AND finished = 0 ORDER BY id DESC LIMIT 1",
                params![info.config, info.algorithm, info.seed as i64, info.fitness, info.duration, info.genes.join("\t")],
                |r| r.get(0),
            )
            .optional()
            .map_err(|e| self.fail(e))
    }

    /// Stores evaluations (one transaction).
    pub fn record(&mut self, run: i64, seed: u64, evals: &[StoredEval]) -> Result<(), String> {
        let tx = self
            .conn
            .transaction()
            .map_err(|e| format!("{}: {e}", self.path.display()))?;
        {
            let mut st = tx
                .prepare_cached(
                    "INSERT OR REPLACE INTO evaluations (run, number, round, genome, vals, score, seed, wall)
                     VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
                )
                .map_err(|e| format!("{}: {e}", self.path.display()))?;
            for e in evals {
                let score = if e.score.is_nan() {
                    None
                } else {
                    Some(e.score)
                };
                st.execute(params![
                    run,
                    e.number as i64,
                    e.round as i64,
                    join(&e.genome),
                    join(&e.values),
                    score,
                    seed as i64,
                    e.wall
                ])
                .map_err(|err| format!("{}: {err}", self.path.display()))?;
            }
        }
        tx.commit()
            .map_err(|e| format!("{}: {e}", self.path.display()))?;
        self.stored += evals.len() as u64;
        if self.crash_after.is_some_and(|n| self.stored >= n) {
            std::process::abort();
        }
        Ok(())
    }

    /// Every stored evaluation of `run`, by number.
    pub fn evaluations(&self, run: i64) -> Result<Vec<StoredEval>, String> {
        let mut st = self
            .conn
            .prepare("SELECT number, round, genome, vals, score, wall FROM evaluations WHERE run = ?1 ORDER BY number")
            .map_err(|e| self.fail(e))?;
        let rows = st
            .query_map(params![run], |r| {
                let genome: String = r.get(2)?;
                let vals: String = r.get(3)?;
                let score: Option<f64> = r.get(4)?;
                Ok(StoredEval {
                    number: r.get::<_, i64>(0)? as u64,
                    round: r.get::<_, i64>(1)? as u64,
                    genome: genome
                        .split_whitespace()
                        .filter_map(|t| t.parse().ok())
                        .collect(),
                    values: vals
                        .split_whitespace()
                        .filter_map(|t| t.parse().ok())
                        .collect(),
                    score: score.unwrap_or(f64::NAN),
                    wall: r.get(5)?,
                })
            })
            .map_err(|e| self.fail(e))?;
        rows.collect::<Result<Vec<_>, _>>()
            .map_err(|e| self.fail(e))
    }

    /// Marks `run` finished.
    pub fn finish_run(&self, run: i64) -> Result<(), String> {
        self.conn
            .execute("UPDATE runs SET finished = 1 WHERE id = ?1", params![run])
            .map(|_| ())
            .map_err(|e| self.fail(e))
    }

    /// Every run with its best evaluation.
    pub fn runs(&self) -> Result<Vec<RunRow>, String> {
        let mut st = self
            .conn
            .prepare(
                "SELECT r.id, r.config, r.algorithm, r.seed, r.fitness, r.duration, r.genes, r.started, r.finished,
                        (SELECT COUNT(*) FROM evaluations e WHERE e.run = r.id),
                        (SELECT MAX(score) FROM evaluations e WHERE e.run = r.id),
                        (SELECT vals FROM evaluations e WHERE e.run = r.id ORDER BY score DESC, number LIMIT 1)
                 FROM runs r ORDER BY r.id",
            )
            .map_err(|e| self.fail(e))?;
        let rows = st
            .query_map([], |r| {
                let genes: String = r.get(6)?;
                Ok(RunRow {
                    id: r.get(0)?,
                    info: RunInfo {
                        config: r.get(1)?,
                        algorithm: r.get(2)?,
                        seed: r.get::<_, i64>(3)? as u64,
                        fitness: r.get(4)?,
                        duration: r.get(5)?,
                        genes: genes.split('\t').map(str::to_string).collect(),
                    },
                    started: r.get(7)?,
                    finished: r.get::<_, i64>(8)? != 0,
                    evaluations: r.get::<_, i64>(9)? as u64,
                    best_score: r.get(10)?,
                    best_values: r.get(11)?,
                })
            })
            .map_err(|e| self.fail(e))?;
        rows.collect::<Result<Vec<_>, _>>()
            .map_err(|e| self.fail(e))
    }
}

//! The embedded SQLite experiment store (one machine): WAL journal, each batch of
//! evaluations one transaction. Its tables are the shared store's (see [`super`]); stores
//! written before the schema had a version (version 1) are brought to the current one.

use std::path::{Path, PathBuf};

use rusqlite::{Connection, OptionalExtension, params};

use crate::optimize::store::schema::{Dialect, create_tables};
use crate::optimize::store::{
    EVAL_COLUMNS, EpisodeRecord, EvalRow, ExperimentStore, RUNS_WITH_BEST, RunInfo, RunRow,
    RunSpec, SCHEMA_VERSION, StoreError, StoredEval, engine_scores_text, join, read_best, score_of,
};

/// An open SQLite store.
pub struct SqliteStore {
    conn: Connection,
    path: PathBuf,
}

/// Version 1 (no `proleg_meta`) to 2: the columns of shared evaluation and the run's files.
const FROM_V1: &str = "
ALTER TABLE runs ADD COLUMN program TEXT NOT NULL DEFAULT '';
ALTER TABLE evaluations ADD COLUMN state TEXT NOT NULL DEFAULT 'done';
ALTER TABLE evaluations ADD COLUMN worker TEXT;
ALTER TABLE evaluations ADD COLUMN attempt INTEGER NOT NULL DEFAULT 0;
ALTER TABLE evaluations ADD COLUMN lease_until REAL;";

/// Versions 1 to 3 to 4: each evaluation's scores on several engines.
const TO_V4: &str = "ALTER TABLE evaluations ADD COLUMN engine_scores TEXT NOT NULL DEFAULT '';";

/// Versions 1 to 4 to 5: why a co-design body was rejected, and measured descriptors.
const TO_V5: &str = "ALTER TABLE evaluations ADD COLUMN rejected TEXT;
ALTER TABLE evaluations ADD COLUMN measures TEXT NOT NULL DEFAULT '';";

impl SqliteStore {
    /// Opens (creating if needed, with its folder) the store at `path`.
    pub fn open(path: &Path) -> Result<SqliteStore, StoreError> {
        let fail = |source| StoreError::Sqlite {
            path: path.to_path_buf(),
            source,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
            && !dir.is_dir()
        {
            std::fs::create_dir_all(dir).map_err(|source| StoreError::Folder {
                path: dir.to_path_buf(),
                source,
            })?;
        }
        let conn = Connection::open(path).map_err(fail)?;
        conn.pragma_update(None, "journal_mode", "WAL")
            .map_err(fail)?;
        conn.pragma_update(None, "synchronous", "NORMAL")
            .map_err(fail)?;
        let store = SqliteStore {
            conn,
            path: path.to_path_buf(),
        };
        store.upgrade()?;
        Ok(store)
    }

    /// Creates the tables, or brings an older store to [`SCHEMA_VERSION`]; a newer store is
    /// refused.
    fn upgrade(&self) -> Result<(), StoreError> {
        let has = |table: &str| -> Result<bool, StoreError> {
            self.conn
                .query_row(
                    "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND name = ?1",
                    params![table],
                    |r| r.get::<_, i64>(0),
                )
                .map(|n| n > 0)
                .map_err(|e| self.fail(e))
        };
        let version: Option<i64> = if has("proleg_meta")? {
            self.conn
                .query_row("SELECT MAX(schema_version) FROM proleg_meta", [], |r| {
                    r.get(0)
                })
                .map_err(|e| self.fail(e))?
        } else if has("runs")? {
            Some(1)
        } else {
            None
        };
        match version {
            Some(v) if v == SCHEMA_VERSION => Ok(()),
            Some(v) if v > SCHEMA_VERSION => Err(StoreError::Schema {
                store: self.path.display().to_string(),
                found: v,
            }),
            old => {
                if old == Some(1) {
                    self.conn.execute_batch(FROM_V1).map_err(|e| self.fail(e))?;
                }
                if old.is_some_and(|v| v < 4) {
                    self.conn.execute_batch(TO_V4).map_err(|e| self.fail(e))?;
                }
                if old.is_some() {
                    self.conn.execute_batch(TO_V5).map_err(|e| self.fail(e))?;
                }
                self.conn
                    .execute_batch(&create_tables(Dialect::Sqlite))
                    .map_err(|e| self.fail(e))?;
                self.conn
                    .execute("DELETE FROM proleg_meta", [])
                    .and_then(|_| {
                        self.conn.execute(
                            "INSERT INTO proleg_meta (schema_version) VALUES (?1)",
                            params![SCHEMA_VERSION],
                        )
                    })
                    .map(|_| ())
                    .map_err(|e| self.fail(e))
            }
        }
    }

    /// The store's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn fail(&self, source: rusqlite::Error) -> StoreError {
        StoreError::Sqlite {
            path: self.path.clone(),
            source,
        }
    }
}

impl ExperimentStore for SqliteStore {
    fn describe(&self) -> String {
        self.path.display().to_string()
    }

    /// Registers a new run with its configuration files; returns its id.
    fn start_run(
        &mut self,
        info: &RunInfo,
        program: &str,
        files: &[(String, String)],
        episodes: &[EpisodeRecord],
    ) -> Result<i64, StoreError> {
        let path = self.path.clone();
        let fail = |source| StoreError::Sqlite {
            path: path.clone(),
            source,
        };
        let tx = self.conn.transaction().map_err(fail)?;
        tx.execute(
            "INSERT INTO runs (config, algorithm, seed, fitness, duration, genes, program) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
            params![info.config, info.algorithm, info.seed as i64, info.fitness, info.duration, info.genes.join("\t"), program],
        )
        .map_err(fail)?;
        let id = tx.last_insert_rowid();
        for (p, text) in files {
            tx.execute(
                "INSERT INTO run_files (run, path, content) VALUES (?1, ?2, ?3)",
                params![id, p, text],
            )
            .map_err(fail)?;
        }
        for e in episodes {
            tx.execute(
                "INSERT INTO run_episodes (run, episode, seed, draws) VALUES (?1, ?2, ?3, ?4)",
                params![id, e.episode, e.seed as i64, e.draws],
            )
            .map_err(fail)?;
        }
        tx.commit().map_err(fail)?;
        Ok(id)
    }

    /// The run, its program, configuration files and episodes.
    fn run_spec(&mut self, run: i64) -> Result<RunSpec, StoreError> {
        let fail = |e: rusqlite::Error| self.fail(e);
        let (info, program, finished) = self
            .conn
            .query_row(
                "SELECT config, algorithm, seed, fitness, duration, genes, program, finished
                 FROM runs WHERE id = ?1",
                params![run],
                |r| {
                    Ok((
                        run_info(r, 0)?,
                        r.get::<_, String>(6)?,
                        r.get::<_, i64>(7)? != 0,
                    ))
                },
            )
            .optional()
            .map_err(fail)?
            .ok_or_else(|| StoreError::NoRun {
                store: self.path.display().to_string(),
                run,
            })?;
        let mut q = self
            .conn
            .prepare("SELECT path, content FROM run_files WHERE run = ?1 ORDER BY path")
            .map_err(fail)?;
        let files = q
            .query_map(params![run], |r| Ok((r.get(0)?, r.get(1)?)))
            .and_then(|rows| rows.collect::<Result<Vec<(String, String)>, _>>())
            .map_err(fail)?;
        let mut q = self
            .conn
            .prepare(
                "SELECT episode, seed, draws FROM run_episodes WHERE run = ?1 ORDER BY episode",
            )
            .map_err(fail)?;
        let episodes = q
            .query_map(params![run], |r| {
                Ok(EpisodeRecord {
                    episode: r.get(0)?,
                    seed: r.get::<_, i64>(1)? as u64,
                    draws: r.get(2)?,
                })
            })
            .and_then(|rows| rows.collect::<Result<Vec<_>, _>>())
            .map_err(fail)?;
        Ok(RunSpec {
            id: run,
            info,
            program,
            finished,
            files,
            episodes,
        })
    }

    /// The latest unfinished run matching `info`.
    fn find_unfinished(&mut self, info: &RunInfo) -> Result<Option<i64>, StoreError> {
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
    fn record(&mut self, run: i64, seed: u64, evals: &[StoredEval]) -> Result<(), StoreError> {
        let path = self.path.clone();
        let fail = |source| StoreError::Sqlite {
            path: path.clone(),
            source,
        };
        let tx = self.conn.transaction().map_err(fail)?;
        {
            let mut st = tx
                .prepare_cached(
                    "INSERT OR REPLACE INTO evaluations (run, number, round, genome, vals, score, seed, wall, engine_scores, rejected, measures)
                     VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)",
                )
                .map_err(fail)?;
            for e in evals {
                st.execute(params![
                    run,
                    e.number as i64,
                    e.round as i64,
                    join(&e.genome),
                    join(&e.values),
                    score_of(e.score),
                    seed as i64,
                    e.wall,
                    engine_scores_text(&e.engines),
                    e.rejected,
                    join(&e.measures)
                ])
                .map_err(fail)?;
            }
        }
        tx.commit().map_err(fail)
    }

    /// Whether `run` has finished.
    fn run_finished(&mut self, run: i64) -> Result<bool, StoreError> {
        self.conn
            .query_row(
                "SELECT finished FROM runs WHERE id = ?1",
                params![run],
                |r| r.get::<_, i64>(0),
            )
            .map(|f| f != 0)
            .map_err(|e| self.fail(e))
    }

    /// The finished evaluations of `run` numbered `first` or more, by number.
    fn evaluations_from(&mut self, run: i64, first: u64) -> Result<Vec<StoredEval>, StoreError> {
        let mut st = self
            .conn
            .prepare(&format!(
                "SELECT {EVAL_COLUMNS} FROM evaluations
                 WHERE run = ?1 AND number >= ?2 AND state = 'done' ORDER BY number"
            ))
            .map_err(|e| self.fail(e))?;
        let rows = st
            .query_map(params![run, first as i64], |r| {
                Ok(EvalRow {
                    number: r.get(0)?,
                    round: r.get(1)?,
                    genome: r.get(2)?,
                    vals: r.get(3)?,
                    score: r.get(4)?,
                    wall: r.get(5)?,
                    engines: r.get(6)?,
                    rejected: r.get(7)?,
                    measures: r.get(8)?,
                })
            })
            .map_err(|e| self.fail(e))?;
        let store = self.describe();
        rows.map(|row| row.map_err(|e| self.fail(e))?.parse(&store, run))
            .collect()
    }

    /// Marks `run` finished.
    fn finish_run(&mut self, run: i64) -> Result<(), StoreError> {
        self.conn
            .execute("UPDATE runs SET finished = 1 WHERE id = ?1", params![run])
            .map(|_| ())
            .map_err(|e| self.fail(e))
    }

    /// Every run with its best evaluation.
    fn runs(&mut self) -> Result<Vec<RunRow>, StoreError> {
        let mut st = self
            .conn
            .prepare(RUNS_WITH_BEST)
            .map_err(|e| self.fail(e))?;
        let rows = st
            .query_map([], |r| {
                let row = RunRow {
                    id: r.get(0)?,
                    info: run_info(r, 1)?,
                    started: r.get(7)?,
                    finished: r.get::<_, i64>(8)? != 0,
                    evaluations: r.get::<_, i64>(9)? as u64,
                    best_score: r.get(10)?,
                    best_values: None,
                    best_engines: Vec::new(),
                    rejected: r.get::<_, i64>(13)? as u64,
                };
                let best: (Option<String>, Option<String>) = (r.get(11)?, r.get(12)?);
                Ok((row, best))
            })
            .map_err(|e| self.fail(e))?;
        let store = self.describe();
        rows.map(|row| {
            let (mut row, (values, engines)) = row.map_err(|e| self.fail(e))?;
            read_best(&mut row, &store, values, engines)?;
            Ok(row)
        })
        .collect()
    }
}

/// A run's settings from a row whose columns `first..first + 6` are config, algorithm,
/// seed, fitness, duration and the tab-separated genes.
fn run_info(r: &rusqlite::Row, first: usize) -> rusqlite::Result<RunInfo> {
    let genes: String = r.get(first + 5)?;
    Ok(RunInfo {
        config: r.get(first)?,
        algorithm: r.get(first + 1)?,
        seed: r.get::<_, i64>(first + 2)? as u64,
        fitness: r.get(first + 3)?,
        duration: r.get(first + 4)?,
        genes: genes.split('\t').map(str::to_string).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::simulation::EngineKind;

    #[test]
    fn a_store_of_version_1_is_brought_to_the_current_schema_with_its_runs() {
        let dir = std::env::temp_dir().join(format!("proleg-sqlite-v1-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("old.sqlite");
        {
            let c = Connection::open(&path).unwrap();
            c.execute_batch(
                "CREATE TABLE runs (id INTEGER PRIMARY KEY, config TEXT NOT NULL, algorithm TEXT NOT NULL,
                    seed INTEGER NOT NULL, fitness TEXT NOT NULL, duration REAL NOT NULL, genes TEXT NOT NULL,
                    started TEXT NOT NULL DEFAULT (datetime('now')), finished INTEGER NOT NULL DEFAULT 0);
                 CREATE TABLE evaluations (run INTEGER NOT NULL REFERENCES runs(id), number INTEGER NOT NULL,
                    round INTEGER NOT NULL, genome TEXT NOT NULL, vals TEXT NOT NULL, score REAL,
                    seed INTEGER NOT NULL, wall REAL NOT NULL, PRIMARY KEY (run, number));
                 INSERT INTO runs (config, algorithm, seed, fitness, duration, genes)
                    VALUES ('a.simulation.xml', 'great deluge', 3, 'displacement', 2.0, 'g');
                 INSERT INTO evaluations VALUES (1, 0, 0, '4', '40', 0.5, 3, 0.1);",
            )
            .unwrap();
        }
        let mut store = SqliteStore::open(&path).unwrap();
        let runs = store.runs().unwrap();
        assert_eq!(runs.len(), 1);
        assert_eq!(runs[0].best_score, Some(0.5));
        assert_eq!(store.evaluations(1).unwrap()[0].genome, vec![4]);
        // Version 3's run_episodes is there (empty for an old run), version 4's engine
        // scores and version 5's rejection reasons (none for an old run; new rows keep
        // theirs).
        assert!(store.run_spec(1).unwrap().episodes.is_empty());
        assert!(store.evaluations(1).unwrap()[0].engines.is_empty());
        let mut store = store;
        let both = vec![(EngineKind::Rapier, 0.75), (EngineKind::Mujoco, 0.25)];
        let e = StoredEval {
            number: 1,
            round: 1,
            genome: vec![5],
            values: vec![50.0],
            score: 0.25,
            engines: both.clone(),
            rejected: Some("a reason".into()),
            measures: vec![0.04, 12.5],
            wall: 0.1,
        };
        store.record(1, 3, &[e]).unwrap();
        assert_eq!(store.evaluations_from(1, 1).unwrap()[0].engines, both);
        assert_eq!(
            store.evaluations_from(1, 1).unwrap()[0].rejected.as_deref(),
            Some("a reason")
        );
        assert_eq!(store.evaluations(1).unwrap()[0].rejected, None);
        assert_eq!(store.runs().unwrap()[0].best_engines, Vec::new());
        drop(store);
        // A store of a newer schema is refused.
        let c = Connection::open(&path).unwrap();
        c.execute("UPDATE proleg_meta SET schema_version = 9", [])
            .unwrap();
        match SqliteStore::open(&path) {
            Err(e @ StoreError::Schema { found: 9, .. }) => assert!(
                e.to_string().ends_with(&format!(
                    "this proleg reads version {SCHEMA_VERSION} (a newer proleg wrote it)"
                )),
                "{e}"
            ),
            other => panic!("expected a schema error, got {:?}", other.err()),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

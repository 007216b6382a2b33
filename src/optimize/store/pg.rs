//! The PostgreSQL experiment store, shared by a driver and workers on many hosts: the same
//! tables as the SQLite store, created by the first driver under an advisory lock. Every
//! statement is parameterized; errors name the store by its URL without the password.
//! The queue of shared evaluations (claims, leases, results) is in [`super::pg_queue`].

use std::time::{Duration, Instant};

use postgres::{Client, Transaction};

use crate::optimize::store::location::PgTarget;
use crate::optimize::store::schema::{Dialect, create_tables};
use crate::optimize::store::{
    EVAL_COLUMNS, EpisodeRecord, EvalRow, ExperimentStore, RUNS_WITH_BEST, RunInfo, RunRow,
    RunSpec, SCHEMA_VERSION, StoreError, StoredEval, engine_scores_text, join, read_best, score_of,
};

/// An open connection to a PostgreSQL store.
pub struct PgStore {
    pub(super) client: Client,
    pub(super) target: PgTarget,
    /// The notification channels this connection listens to (again after a reconnect).
    pub(super) listening: Vec<&'static str>,
    /// The statements of the queue, prepared once per connection (by their text).
    pub(super) statements: std::collections::HashMap<&'static str, postgres::Statement>,
}

/// Advisory-lock key under which the first driver creates the tables.
const SCHEMA_LOCK: i64 = 0x7072_6f6c_6567;

/// Version 2 to 3: the episodes of robust fitness.
const FROM_V2: &str = "
CREATE TABLE run_episodes (
    run BIGINT NOT NULL REFERENCES runs(id), episode INTEGER NOT NULL, seed BIGINT NOT NULL,
    draws TEXT NOT NULL, PRIMARY KEY (run, episode));
UPDATE proleg_meta SET schema_version = 3;";

/// Version 3 to 4: each evaluation's scores on several engines.
const FROM_V3: &str = "
ALTER TABLE evaluations ADD COLUMN engine_scores TEXT NOT NULL DEFAULT '';
UPDATE proleg_meta SET schema_version = 4;";

/// Version 4 to 5: why a co-design body was rejected, and measured descriptors.
const FROM_V4: &str = "
ALTER TABLE evaluations ADD COLUMN rejected TEXT;
ALTER TABLE evaluations ADD COLUMN measures TEXT NOT NULL DEFAULT '';
UPDATE proleg_meta SET schema_version = 5;";

impl PgStore {
    /// Connects; with `create`, makes the tables when the database has none. A database
    /// holding another schema version (or foreign tables of the same names) is refused
    /// before anything is written.
    pub fn open(target: &PgTarget, create: bool) -> Result<PgStore, StoreError> {
        let client = connect(target)?;
        let mut store = PgStore {
            client,
            target: target.clone(),
            listening: Vec::new(),
            statements: std::collections::HashMap::new(),
        };
        let fail = store.failer();
        let mut tx = store.client.transaction().map_err(&fail)?;
        if create {
            tx.execute("SELECT pg_advisory_xact_lock($1)", &[&SCHEMA_LOCK])
                .map_err(&fail)?;
        }
        match schema_version(&mut tx).map_err(&fail)? {
            Some(v) if v == SCHEMA_VERSION => {}
            Some(2) if create => {
                tx.batch_execute(FROM_V2).map_err(&fail)?;
                tx.batch_execute(FROM_V3).map_err(&fail)?;
                tx.batch_execute(FROM_V4).map_err(&fail)?;
            }
            Some(3) if create => {
                tx.batch_execute(FROM_V3).map_err(&fail)?;
                tx.batch_execute(FROM_V4).map_err(&fail)?;
            }
            Some(4) if create => {
                tx.batch_execute(FROM_V4).map_err(&fail)?;
            }
            Some(v) => {
                return Err(StoreError::Schema {
                    store: target.to_string(),
                    found: v,
                });
            }
            None if !create => {
                return Err(StoreError::NotAStore {
                    store: target.to_string(),
                });
            }
            None => {
                let foreign: bool = tx
                    .query_one(
                        "SELECT to_regclass('runs') IS NOT NULL OR to_regclass('evaluations') IS NOT NULL",
                        &[],
                    )
                    .and_then(|r| r.try_get(0))
                    .map_err(&fail)?;
                if foreign {
                    return Err(StoreError::Foreign {
                        store: target.to_string(),
                    });
                }
                tx.batch_execute(&create_tables(Dialect::Postgres))
                    .map_err(&fail)?;
                tx.execute(
                    "INSERT INTO proleg_meta (schema_version) VALUES ($1)",
                    &[&(SCHEMA_VERSION as i32)],
                )
                .map_err(&fail)?;
            }
        }
        tx.commit().map_err(&fail)?;
        Ok(store)
    }

    /// Whether the connection is gone (the server restarted, the network was cut).
    pub fn is_closed(&self) -> bool {
        self.client.is_closed()
    }

    /// Connects again after the connection was lost, listening again to its channels;
    /// tries every 0.5 s, doubling up to 8 s, and gives up after `give_up` (or when
    /// `stopped` says so) with the last error.
    pub fn reconnect(
        &mut self,
        give_up: Duration,
        stopped: &dyn Fn() -> bool,
    ) -> Result<(), StoreError> {
        let started = Instant::now();
        let mut pause = Duration::from_millis(500);
        loop {
            let attempt = connect(&self.target).and_then(|client| {
                self.client = client;
                self.statements.clear();
                let channels = self.listening.clone();
                channels.iter().try_for_each(|c| self.listen(c))
            });
            match attempt {
                Ok(()) => return Ok(()),
                Err(e) if stopped() || started.elapsed() >= give_up => {
                    return Err(StoreError::Unreachable {
                        seconds: started.elapsed().as_secs_f64(),
                        last: Box::new(e),
                    });
                }
                Err(_) => {
                    std::thread::sleep(pause);
                    pause = (pause * 2).min(Duration::from_secs(8));
                }
            }
        }
    }

    /// Statement `sql`, prepared on this connection at its first use.
    pub(super) fn prepared(
        &mut self,
        sql: &'static str,
    ) -> Result<postgres::Statement, StoreError> {
        if let Some(st) = self.statements.get(sql) {
            return Ok(st.clone());
        }
        let st = self.client.prepare(sql).map_err(self.failer())?;
        self.statements.insert(sql, st.clone());
        Ok(st)
    }

    /// Whether this connection is encrypted (TLS).
    pub fn encrypted(&mut self) -> Result<bool, StoreError> {
        let fail = self.failer();
        self.client
            .query_one(
                "SELECT COALESCE((SELECT ssl FROM pg_stat_ssl WHERE pid = pg_backend_pid()), false)",
                &[],
            )
            .and_then(|r| r.try_get(0))
            .map_err(&fail)
    }

    /// The store's location (no password).
    pub fn target(&self) -> &PgTarget {
        &self.target
    }

    /// Maps a driver error to a message naming the store.
    pub(super) fn failer(&self) -> impl Fn(postgres::Error) -> StoreError + use<> {
        let shown = self.target.to_string();
        move |e| describe_error(&shown, &e)
    }
}

impl ExperimentStore for PgStore {
    fn describe(&self) -> String {
        self.target.to_string()
    }

    /// Registers a new run with its configuration files; returns its id.
    fn start_run(
        &mut self,
        info: &RunInfo,
        program: &str,
        files: &[(String, String)],
        episodes: &[EpisodeRecord],
    ) -> Result<i64, StoreError> {
        let fail = self.failer();
        let mut tx = self.client.transaction().map_err(&fail)?;
        let id: i64 = tx
            .query_one(
                "INSERT INTO runs (config, algorithm, seed, fitness, duration, genes, program)
                 VALUES ($1, $2, $3, $4, $5, $6, $7) RETURNING id",
                &[
                    &info.config,
                    &info.algorithm,
                    &(info.seed as i64),
                    &info.fitness,
                    &info.duration,
                    &info.genes.join("\t"),
                    &program,
                ],
            )
            .and_then(|r| r.try_get(0))
            .map_err(&fail)?;
        for (p, text) in files {
            tx.execute(
                "INSERT INTO run_files (run, path, content) VALUES ($1, $2, $3)",
                &[&id, p, text],
            )
            .map_err(&fail)?;
        }
        for e in episodes {
            tx.execute(
                "INSERT INTO run_episodes (run, episode, seed, draws) VALUES ($1, $2, $3, $4)",
                &[&id, &(e.episode as i32), &(e.seed as i64), &e.draws],
            )
            .map_err(&fail)?;
        }
        tx.commit().map_err(&fail)?;
        Ok(id)
    }

    /// The latest unfinished run matching `info`.
    fn find_unfinished(&mut self, info: &RunInfo) -> Result<Option<i64>, StoreError> {
        let fail = self.failer();
        let row = self
            .client
            .query_opt(
                "SELECT id FROM runs WHERE config = $1 AND algorithm = $2 AND seed = $3 AND fitness = $4
                 AND duration = $5 AND genes = $6 AND finished = 0 ORDER BY id DESC LIMIT 1",
                &[
                    &info.config,
                    &info.algorithm,
                    &(info.seed as i64),
                    &info.fitness,
                    &info.duration,
                    &info.genes.join("\t"),
                ],
            )
            .map_err(&fail)?;
        row.map(|r| r.try_get(0)).transpose().map_err(&fail)
    }

    /// Stores finished evaluations (one transaction), replacing what their numbers held.
    fn record(&mut self, run: i64, seed: u64, evals: &[StoredEval]) -> Result<(), StoreError> {
        let fail = self.failer();
        let mut tx = self.client.transaction().map_err(&fail)?;
        let st = tx
            .prepare(
                "INSERT INTO evaluations (run, number, round, genome, vals, score, seed, wall, engine_scores, rejected, measures)
                 VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11)
                 ON CONFLICT (run, number) DO UPDATE SET round = EXCLUDED.round,
                   genome = EXCLUDED.genome, vals = EXCLUDED.vals, score = EXCLUDED.score,
                   engine_scores = EXCLUDED.engine_scores, rejected = EXCLUDED.rejected,
                   measures = EXCLUDED.measures,
                   seed = EXCLUDED.seed, wall = EXCLUDED.wall, state = 'done', lease_until = NULL",
            )
            .map_err(&fail)?;
        for e in evals {
            tx.execute(
                &st,
                &[
                    &run,
                    &(e.number as i64),
                    &(e.round as i64),
                    &join(&e.genome),
                    &join(&e.values),
                    &score_of(e.score),
                    &(seed as i64),
                    &e.wall,
                    &engine_scores_text(&e.engines),
                    &e.rejected,
                    &join(&e.measures),
                ],
            )
            .map_err(&fail)?;
        }
        tx.commit().map_err(&fail)
    }

    /// The finished evaluations of `run` numbered `first` or more, by number.
    fn evaluations_from(&mut self, run: i64, first: u64) -> Result<Vec<StoredEval>, StoreError> {
        let fail = self.failer();
        let rows = self
            .client
            .query(
                &format!(
                    "SELECT {EVAL_COLUMNS} FROM evaluations
                     WHERE run = $1 AND number >= $2 AND state = 'done' ORDER BY number"
                ),
                &[&run, &(first as i64)],
            )
            .map_err(&fail)?;
        let store = self.target.to_string();
        rows.iter()
            .map(|r| {
                let row = EvalRow {
                    number: r.try_get(0)?,
                    round: r.try_get(1)?,
                    genome: r.try_get(2)?,
                    vals: r.try_get(3)?,
                    score: r.try_get(4)?,
                    wall: r.try_get(5)?,
                    engines: r.try_get(6)?,
                    rejected: r.try_get(7)?,
                    measures: r.try_get(8)?,
                };
                Ok::<_, postgres::Error>(row)
            })
            .map(|row| row.map_err(&fail)?.parse(&store, run))
            .collect()
    }

    /// Whether `run` has finished.
    fn run_finished(&mut self, run: i64) -> Result<bool, StoreError> {
        let fail = self.failer();
        let row = self
            .client
            .query_one("SELECT finished FROM runs WHERE id = $1", &[&run])
            .map_err(&fail)?;
        row.try_get::<_, i32>(0).map(|f| f != 0).map_err(&fail)
    }

    /// Marks `run` finished.
    fn finish_run(&mut self, run: i64) -> Result<(), StoreError> {
        let fail = self.failer();
        self.client
            .execute("UPDATE runs SET finished = 1 WHERE id = $1", &[&run])
            .map(|_| ())
            .map_err(&fail)
    }

    /// Every run with its best evaluation.
    fn runs(&mut self) -> Result<Vec<RunRow>, StoreError> {
        let fail = self.failer();
        let rows = self.client.query(RUNS_WITH_BEST, &[]).map_err(&fail)?;
        let store = self.target.to_string();
        rows.iter()
            .map(|r| {
                let row = RunRow {
                    id: r.try_get(0)?,
                    info: run_info(r)?,
                    started: r.try_get(7)?,
                    finished: r.try_get::<_, i32>(8)? != 0,
                    evaluations: r.try_get::<_, i64>(9)? as u64,
                    best_score: r.try_get(10)?,
                    best_values: None,
                    best_engines: Vec::new(),
                    rejected: r.try_get::<_, i64>(13)? as u64,
                };
                let best: (Option<String>, Option<String>) = (r.try_get(11)?, r.try_get(12)?);
                Ok::<_, postgres::Error>((row, best))
            })
            .map(|row| {
                let (mut row, (values, engines)) = row.map_err(&fail)?;
                read_best(&mut row, &store, values, engines)?;
                Ok(row)
            })
            .collect()
    }

    /// What a worker needs to evaluate `run`'s candidates: the run, the program that
    /// started it and its configuration files.
    fn run_spec(&mut self, run: i64) -> Result<RunSpec, StoreError> {
        let fail = self.failer();
        let row = self
            .client
            .query_opt(
                "SELECT id, config, algorithm, seed, fitness, duration, genes, program, finished
                 FROM runs WHERE id = $1",
                &[&run],
            )
            .map_err(&fail)?
            .ok_or_else(|| StoreError::NoRun {
                store: self.target.to_string(),
                run,
            })?;
        let files = self
            .client
            .query(
                "SELECT path, content FROM run_files WHERE run = $1 ORDER BY path",
                &[&run],
            )
            .map_err(&fail)?;
        let files = files
            .iter()
            .map(|f| Ok((f.try_get(0)?, f.try_get(1)?)))
            .collect::<Result<Vec<(String, String)>, postgres::Error>>()
            .map_err(&fail)?;
        let episodes = self
            .client
            .query(
                "SELECT episode, seed, draws FROM run_episodes WHERE run = $1 ORDER BY episode",
                &[&run],
            )
            .map_err(&fail)?
            .iter()
            .map(|e| {
                Ok(EpisodeRecord {
                    episode: e.try_get::<_, i32>(0)? as u32,
                    seed: e.try_get::<_, i64>(1)? as u64,
                    draws: e.try_get(2)?,
                })
            })
            .collect::<Result<Vec<_>, postgres::Error>>()
            .map_err(&fail)?;
        Ok(RunSpec {
            id: run,
            info: run_info(&row).map_err(&fail)?,
            program: row.try_get(7).map_err(&fail)?,
            finished: row.try_get::<_, i32>(8).map_err(&fail)? != 0,
            files,
            episodes,
        })
    }
}

/// The run description in columns 1..=6 of `r`.
fn run_info(r: &postgres::Row) -> Result<RunInfo, postgres::Error> {
    let genes: String = r.try_get(6)?;
    Ok(RunInfo {
        config: r.try_get(1)?,
        algorithm: r.try_get(2)?,
        seed: r.try_get::<_, i64>(3)? as u64,
        fitness: r.try_get(4)?,
        duration: r.try_get(5)?,
        genes: genes.split('\t').map(str::to_string).collect(),
    })
}

/// The schema version of the store in this database, if it has one.
fn schema_version(tx: &mut Transaction<'_>) -> Result<Option<i64>, postgres::Error> {
    let exists: bool = tx
        .query_one("SELECT to_regclass('proleg_meta') IS NOT NULL", &[])?
        .try_get(0)?;
    if !exists {
        return Ok(None);
    }
    let v: Option<i32> = tx
        .query_one("SELECT MAX(schema_version) FROM proleg_meta", &[])?
        .try_get(0)?;
    Ok(v.map(i64::from))
}

/// A connection to `target`: TLS when the URL's `sslmode` asks for it (`require`
/// encrypts without checking the server's certificate, as libpq does).
pub fn connect(target: &PgTarget) -> Result<Client, StoreError> {
    let tls = native_tls::TlsConnector::builder()
        .danger_accept_invalid_certs(true)
        .danger_accept_invalid_hostnames(true)
        .build()
        .map_err(|e| StoreError::Tls {
            store: target.to_string(),
            message: e.to_string(),
        })?;
    target
        .config
        .connect(postgres_native_tls::MakeTlsConnector::new(tls))
        .map_err(|e| match describe_error(&target.to_string(), &e) {
            StoreError::Postgres { store, message } if no_server(&e) => {
                StoreError::NoServer { store, message }
            }
            other => other,
        })
}

/// Whether a connection failed because no server answered (a socket error or a timeout
/// before any message of the server's), not because the server refused it.
fn no_server(e: &postgres::Error) -> bool {
    if e.as_db_error().is_some() {
        return false;
    }
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        if s.is::<std::io::Error>() {
            return true;
        }
        source = s.source();
    }
    // The driver reports a connect timeout with no source.
    e.to_string().contains("timed out")
}

/// The store and the cause (the server's message when it sent one, else the driver's
/// chain of causes).
pub fn describe_error(shown: &str, e: &postgres::Error) -> StoreError {
    let message = match e.as_db_error() {
        Some(db) => db.message().to_string(),
        None => {
            let mut text = e.to_string();
            let mut source = std::error::Error::source(e);
            while let Some(s) = source {
                let more = s.to_string();
                if !text.contains(&more) {
                    text = format!("{text}: {more}");
                }
                source = s.source();
            }
            text
        }
    };
    StoreError::Postgres {
        store: shown.to_string(),
        message,
    }
}

//! The experiment store: every evaluation of every run, written as it finishes, so a killed
//! run loses nothing finished and `--resume` replays it without re-running what is stored.
//!
//! One schema, two engines ([`StoreLocation`] says which):
//!
//! | table | holds |
//! |---|---|
//! | `proleg_meta` | the schema version ([`SCHEMA_VERSION`]) |
//! | `runs` | what identifies a run ([`RunInfo`]), when it started, whether it finished, the program that started it |
//! | `run_files` | the run's resolved configuration: every file it read (simulation, robot, parts, actuation, environment, meshes, optimizer) |
//! | `run_episodes` | robust fitness: each randomized episode's seed and what it drew |
//! | `evaluations` | one row per candidate: number, round, genome, values, score, its score on each engine (`engine_scores`, runs with `<engines>`), why it was rejected (`rejected`: a co-design body unrun or a module failed during its episode; NULL otherwise), the quantities measured in its episode (`measures`, MAP-Elites' measured descriptors), seed, wall seconds; and for shared evaluation its `state` (`pending`, `running`, `done`), the claiming `worker`, the claim's `attempt` and `lease_until` |
//!
//! [`sqlite`] is the embedded store of one machine (evaluations run in the optimizing
//! process); [`pg`] a PostgreSQL database shared by a driver and `proleg worker`s on many
//! hosts, with the queue of shared evaluations in [`pg_queue`]. [`location`] reads
//! `--store` (a path or a URL), [`schema`] describes the tables once for both, [`table`]
//! is every evaluation as one table, and [`error`] says what failed in which store.

pub mod error;
pub mod location;
pub mod pg;
pub mod pg_queue;
pub mod schema;
pub mod sqlite;
pub mod table;

use crate::config::simulation::EngineKind;

pub use error::StoreError;
pub use location::{PgTarget, StoreLocation};
pub use pg::PgStore;
pub use sqlite::SqliteStore;

/// The layout this program reads and writes (1: before shared evaluation; 2: before
/// `run_episodes`; 3: before `evaluations.engine_scores`; 4: before `evaluations.rejected` and `evaluations.measures`).
pub const SCHEMA_VERSION: i64 = 5;

/// The program that starts a run, stored with it: a worker of another version refuses the
/// run (its physics may differ, so its scores would not be the driver's).
pub fn program_version() -> String {
    format!("proleg {}", env!("CARGO_PKG_VERSION"))
}

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
    /// The best candidate's values, in gene order (`None` while the run has no scored
    /// evaluation).
    pub best_values: Option<Vec<f64>>,
    /// The best candidate's score on each engine (runs with `<engines>`; else empty).
    pub best_engines: Vec<(EngineKind, f64)>,
    /// Candidates rejected: co-design bodies unrun, modules failed during the episode.
    pub rejected: u64,
}

/// Everything a worker needs to evaluate a run's candidates.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// The run's id.
    pub id: i64,
    /// What is run.
    pub info: RunInfo,
    /// The program that started it ([`program_version`]).
    pub program: String,
    /// Whether it ran to its end.
    pub finished: bool,
    /// Its configuration files: (path as the driver read it, text).
    pub files: Vec<(String, String)>,
    /// Its randomized episodes (robust fitness; empty without).
    pub episodes: Vec<EpisodeRecord>,
}

/// One randomized episode of a run with robust fitness, as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct EpisodeRecord {
    /// 0-based episode number.
    pub episode: u32,
    /// Its seed.
    pub seed: u64,
    /// What it drew (friction, masses, start pose), for people.
    pub draws: String,
}

pub use crate::optimize::scores::StoredEval;

/// What both stores do, with the same semantics (`tests/store_conformance.rs` runs one
/// suite against each). A run's identity is [`RunInfo`]; evaluations are stored once, by number.
pub trait ExperimentStore {
    /// Where the store is, as it may be shown (a URL without its password).
    fn describe(&self) -> String;

    /// Registers a new run started by `program`, with the files of its configuration and
    /// its randomized episodes; returns its id.
    fn start_run(
        &mut self,
        info: &RunInfo,
        program: &str,
        files: &[(String, String)],
        episodes: &[EpisodeRecord],
    ) -> Result<i64, StoreError>;

    /// Everything needed to evaluate `run`'s candidates again: the run, the program that
    /// started it, its configuration files and its episodes.
    fn run_spec(&mut self, run: i64) -> Result<RunSpec, StoreError>;

    /// The latest unfinished run matching `info`.
    fn find_unfinished(&mut self, info: &RunInfo) -> Result<Option<i64>, StoreError>;

    /// Stores finished evaluations (one transaction).
    fn record(&mut self, run: i64, seed: u64, evals: &[StoredEval]) -> Result<(), StoreError>;

    /// The finished evaluations of `run` numbered `first` or more, by number.
    fn evaluations_from(&mut self, run: i64, first: u64) -> Result<Vec<StoredEval>, StoreError>;

    /// Every finished evaluation of `run`, by number.
    fn evaluations(&mut self, run: i64) -> Result<Vec<StoredEval>, StoreError> {
        self.evaluations_from(run, 0)
    }

    /// Whether `run` has finished.
    fn run_finished(&mut self, run: i64) -> Result<bool, StoreError>;

    /// Marks `run` finished.
    fn finish_run(&mut self, run: i64) -> Result<(), StoreError>;

    /// Every run with its best evaluation.
    fn runs(&mut self) -> Result<Vec<RunRow>, StoreError>;

    /// The last run matching `info`, finished or not.
    fn latest_run(&mut self, info: &RunInfo) -> Result<Option<i64>, StoreError> {
        Ok(self
            .runs()?
            .into_iter()
            .filter(|r| r.info == *info)
            .map(|r| r.id)
            .max())
    }
}

/// An open store of either kind: reached through [`ExperimentStore`]'s methods; a
/// run's scorer ([`crate::optimize::scorer`]) tells them apart to use the shared store's
/// queue.
pub enum Store {
    /// A results file of one host.
    Sqlite(SqliteStore),
    /// A shared PostgreSQL store with its queue (boxed: a client and its statements).
    Postgres(Box<PgStore>),
}

impl Store {
    /// Opens the store at `location`, creating its tables when there are none.
    pub fn open(location: &StoreLocation) -> Result<Store, StoreError> {
        Ok(match location {
            StoreLocation::Sqlite(p) => Store::Sqlite(SqliteStore::open(p)?),
            StoreLocation::Postgres(t) => Store::Postgres(Box::new(PgStore::open(t, true)?)),
        })
    }

    /// Opens a store that must exist already (reading results, workers).
    pub fn open_existing(location: &StoreLocation) -> Result<Store, StoreError> {
        match location {
            StoreLocation::Sqlite(p) if !p.is_file() => {
                Err(StoreError::Missing { path: p.clone() })
            }
            StoreLocation::Sqlite(p) => Ok(Store::Sqlite(SqliteStore::open(p)?)),
            StoreLocation::Postgres(t) => Ok(Store::Postgres(Box::new(PgStore::open(t, false)?))),
        }
    }

    /// A shared run's queue and workers (`None` for a SQLite store, which has no queue).
    pub fn queue_state(&mut self, run: i64) -> Result<Option<pg_queue::QueueState>, StoreError> {
        match self {
            Store::Sqlite(_) => Ok(None),
            Store::Postgres(pg) => pg.queue_state(run).map(Some),
        }
    }

    /// Registers a new run started by this program ([`program_version`]); returns its id.
    pub fn start_run(
        &mut self,
        info: &RunInfo,
        files: &[(String, String)],
        episodes: &[EpisodeRecord],
    ) -> Result<i64, StoreError> {
        (**self).start_run(info, &program_version(), files, episodes)
    }
}

impl std::ops::Deref for Store {
    type Target = dyn ExperimentStore;
    fn deref(&self) -> &Self::Target {
        match self {
            Store::Sqlite(s) => s,
            Store::Postgres(s) => s.as_ref(),
        }
    }
}

impl std::ops::DerefMut for Store {
    fn deref_mut(&mut self) -> &mut Self::Target {
        match self {
            Store::Sqlite(s) => s,
            Store::Postgres(s) => s.as_mut(),
        }
    }
}

/// One row of `evaluations` as both drivers read it (number, round, genome, vals, score,
/// wall, engine_scores, rejected, measures), before its text columns are parsed by [`EvalRow::parse`].
pub(crate) struct EvalRow {
    pub number: i64,
    pub round: i64,
    pub genome: String,
    pub vals: String,
    pub score: Option<f64>,
    pub wall: f64,
    pub engines: String,
    pub rejected: Option<String>,
    pub measures: String,
}

/// The columns both drivers select for an [`EvalRow`], in its order.
pub(crate) const EVAL_COLUMNS: &str =
    "number, round, genome, vals, score, wall, engine_scores, rejected, measures";

impl EvalRow {
    /// The stored evaluation, each text column parsed; a column that does not parse is a
    /// [`StoreError::Corrupt`] naming the store, run and evaluation (never skipped).
    pub(crate) fn parse(self, store: &str, run: i64) -> Result<StoredEval, StoreError> {
        let number = self.number as u64;
        let place = Place {
            store,
            run,
            evaluation: Some(number),
        };
        Ok(StoredEval {
            number,
            round: self.round as u64,
            genome: place.list("genome", &self.genome)?,
            values: place.list("vals", &self.vals)?,
            score: self.score.unwrap_or(f64::NAN),
            engines: place.engines(&self.engines)?,
            rejected: self.rejected,
            measures: place.list("measures", &self.measures)?,
            wall: self.wall,
        })
    }
}

/// Where a text column was read: its store, run and evaluation, for a
/// [`StoreError::Corrupt`].
pub(crate) struct Place<'a> {
    pub store: &'a str,
    pub run: i64,
    /// The evaluation read (none: the run's best); its name is written only on error.
    pub evaluation: Option<u64>,
}

impl Place<'_> {
    fn corrupt(&self, column: &'static str, text: &str, expected: &'static str) -> StoreError {
        StoreError::Corrupt {
            store: self.store.to_string(),
            run: self.run,
            evaluation: match self.evaluation {
                Some(n) => format!("evaluation {n}"),
                None => "its best evaluation".into(),
            },
            column,
            text: text.to_string(),
            expected,
        }
    }

    /// A [`join`]ed column of numbers.
    pub(crate) fn list<T: std::str::FromStr>(
        &self,
        column: &'static str,
        text: &str,
    ) -> Result<Vec<T>, StoreError> {
        parse_list(text).ok_or_else(|| self.corrupt(column, text, "a list of numbers"))
    }

    /// An [`engine_scores_text`] column.
    pub(crate) fn engines(&self, text: &str) -> Result<Vec<(EngineKind, f64)>, StoreError> {
        parse_engine_scores(text)
            .ok_or_else(|| self.corrupt("engine_scores", text, "engine=score pairs"))
    }
}

/// The best evaluation's values and engine scores of run `run`, read from their columns'
/// text (values NULL while it has no scored evaluation; engine scores NULL when it has
/// none): both stores read a run's best through here.
pub(crate) fn read_best(
    row: &mut RunRow,
    store: &str,
    values: Option<String>,
    engines: Option<String>,
) -> Result<(), StoreError> {
    let place = Place {
        store,
        run: row.id,
        evaluation: None,
    };
    row.best_values = values.map(|v| place.list("vals", &v)).transpose()?;
    row.best_engines = place.engines(engines.as_deref().unwrap_or_default())?;
    Ok(())
}

/// Every run with its count of finished evaluations, best score and best values, by id:
/// the same statement on both engines (it takes no parameters).
pub(crate) const RUNS_WITH_BEST: &str = "SELECT r.id, r.config, r.algorithm, r.seed, r.fitness, r.duration, r.genes, r.started, r.finished,
        (SELECT COUNT(*) FROM evaluations e WHERE e.run = r.id AND e.state = 'done'),
        (SELECT MAX(score) FROM evaluations e WHERE e.run = r.id AND e.state = 'done'),
        (SELECT vals FROM evaluations e WHERE e.run = r.id AND e.state = 'done' AND e.score IS NOT NULL
         ORDER BY score DESC, number LIMIT 1),
        (SELECT engine_scores FROM evaluations e WHERE e.run = r.id AND e.state = 'done' AND e.score IS NOT NULL
         ORDER BY score DESC, number LIMIT 1),
        (SELECT COUNT(*) FROM evaluations e WHERE e.run = r.id AND e.state = 'done' AND e.rejected IS NOT NULL)
     FROM runs r ORDER BY r.id";

/// Numbers as one space-separated text column.
pub(crate) fn join<T: ToString>(v: &[T]) -> String {
    v.iter().map(T::to_string).collect::<Vec<_>>().join(" ")
}

/// The numbers of a [`join`]ed column; `None` when one is not a number.
pub(crate) fn parse_list<T: std::str::FromStr>(text: &str) -> Option<Vec<T>> {
    text.split_whitespace().map(|t| t.parse().ok()).collect()
}

/// Engine scores as one text column: `rapier=0.51 mujoco=0.41` (empty on one engine).
pub fn engine_scores_text(scores: &[(EngineKind, f64)]) -> String {
    let parts: Vec<String> = scores.iter().map(|(k, s)| format!("{k}={s}")).collect();
    parts.join(" ")
}

/// The engine scores of an [`engine_scores_text`] column; `None` when a part is not
/// `engine=score`.
pub fn parse_engine_scores(text: &str) -> Option<Vec<(EngineKind, f64)>> {
    text.split_whitespace()
        .map(|part| {
            let (name, score) = part.split_once('=')?;
            Some((EngineKind::parse(name)?, score.parse().ok()?))
        })
        .collect()
}

/// A score as stored: NaN (a failed episode) as NULL.
pub(crate) fn score_of(score: f64) -> Option<f64> {
    (!score.is_nan()).then_some(score)
}

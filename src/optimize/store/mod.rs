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
//! | `evaluations` | one row per candidate: number, round, genome, values, score, its score on each engine (`engine_scores`, runs with `<engines>`), seed, wall seconds; and for shared evaluation its `state` (`pending`, `running`, `done`), the claiming `worker`, the claim's `attempt` and `lease_until` |
//!
//! [`sqlite`] is the embedded store of one machine (evaluations run in the optimizing
//! process); [`pg`] a PostgreSQL database shared by a driver and `proleg worker`s on many
//! hosts, with the queue of shared evaluations in [`pg_queue`].

pub mod location;
pub mod pg;
pub mod pg_queue;
pub mod sqlite;

use crate::config::simulation::EngineKind;
use crate::optimize::space::Genome;

pub use location::{PgTarget, StoreLocation};
pub use pg::PgStore;
pub use sqlite::SqliteStore;

/// The layout this program reads and writes (1: before shared evaluation; 2: before
/// `run_episodes`; 3: before `evaluations.engine_scores`).
pub const SCHEMA_VERSION: i64 = 4;

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
    /// The best candidate's values, as text.
    pub best_values: Option<String>,
    /// The best candidate's score on each engine (runs with `<engines>`; else empty).
    pub best_engines: Vec<(EngineKind, f64)>,
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
    /// Its score on each engine, when the run scores on several (`<engines>`).
    pub engines: Vec<(EngineKind, f64)>,
    /// Wall seconds of its evaluation (a batch's shared by its candidates).
    pub wall: f64,
}

/// An open store.
pub enum Store {
    /// The embedded SQLite store.
    Sqlite(SqliteStore),
    /// A shared PostgreSQL store.
    Postgres(Box<PgStore>),
}

impl Store {
    /// Opens the store at `location`, creating its tables when there are none.
    pub fn open(location: &StoreLocation) -> Result<Store, String> {
        match location {
            StoreLocation::Sqlite(p) => SqliteStore::open(p).map(Store::Sqlite),
            StoreLocation::Postgres(t) => {
                PgStore::open(t, true).map(|s| Store::Postgres(Box::new(s)))
            }
        }
    }

    /// Opens a store that must exist already (reading results, workers).
    pub fn open_existing(location: &StoreLocation) -> Result<Store, String> {
        match location {
            StoreLocation::Sqlite(p) if !p.is_file() => {
                Err(format!("{}: no such store", p.display()))
            }
            StoreLocation::Sqlite(p) => SqliteStore::open(p).map(Store::Sqlite),
            StoreLocation::Postgres(t) => {
                PgStore::open(t, false).map(|s| Store::Postgres(Box::new(s)))
            }
        }
    }

    /// Where the store is, as it may be shown (a URL without its password).
    pub fn describe(&self) -> String {
        match self {
            Store::Sqlite(s) => s.path().display().to_string(),
            Store::Postgres(p) => p.target().to_string(),
        }
    }

    /// The shared store, when this is one.
    pub fn shared(&mut self) -> Option<&mut PgStore> {
        match self {
            Store::Sqlite(_) => None,
            Store::Postgres(p) => Some(p.as_mut()),
        }
    }

    /// Registers a new run, with the files of its configuration and its randomized
    /// episodes; returns its id.
    pub fn start_run(
        &mut self,
        info: &RunInfo,
        files: &[(String, String)],
        episodes: &[EpisodeRecord],
    ) -> Result<i64, String> {
        let program = program_version();
        match self {
            Store::Sqlite(s) => s.start_run(info, &program, files, episodes),
            Store::Postgres(p) => p.start_run(info, &program, files, episodes),
        }
    }

    /// Everything needed to evaluate `run`'s candidates again: the run, the program that
    /// started it, its configuration files and its episodes.
    pub fn run_spec(&mut self, run: i64) -> Result<RunSpec, String> {
        match self {
            Store::Sqlite(s) => s.run_spec(run),
            Store::Postgres(p) => p.run_spec(run),
        }
    }

    /// The latest unfinished run matching `info`.
    pub fn find_unfinished(&mut self, info: &RunInfo) -> Result<Option<i64>, String> {
        match self {
            Store::Sqlite(s) => s.find_unfinished(info),
            Store::Postgres(p) => p.find_unfinished(info),
        }
    }

    /// Stores finished evaluations (one transaction).
    pub fn record(&mut self, run: i64, seed: u64, evals: &[StoredEval]) -> Result<(), String> {
        match self {
            Store::Sqlite(s) => s.record(run, seed, evals),
            Store::Postgres(p) => p.record(run, seed, evals),
        }
    }

    /// Every finished evaluation of `run`, by number.
    pub fn evaluations(&mut self, run: i64) -> Result<Vec<StoredEval>, String> {
        match self {
            Store::Sqlite(s) => s.evaluations(run),
            Store::Postgres(p) => p.evaluations(run),
        }
    }

    /// The finished evaluations of `run` numbered `first` or more, by number.
    pub fn evaluations_from(&mut self, run: i64, first: u64) -> Result<Vec<StoredEval>, String> {
        match self {
            Store::Sqlite(s) => s.evaluations_from(run, first),
            Store::Postgres(p) => p.evaluations_from(run, first),
        }
    }

    /// Whether `run` has finished.
    pub fn run_finished(&mut self, run: i64) -> Result<bool, String> {
        match self {
            Store::Sqlite(s) => s.run_finished(run),
            Store::Postgres(p) => p.run_finished(run),
        }
    }

    /// Marks `run` finished.
    pub fn finish_run(&mut self, run: i64) -> Result<(), String> {
        match self {
            Store::Sqlite(s) => s.finish_run(run),
            Store::Postgres(p) => p.finish_run(run),
        }
    }

    /// Every run with its best evaluation.
    pub fn runs(&mut self) -> Result<Vec<RunRow>, String> {
        match self {
            Store::Sqlite(s) => s.runs(),
            Store::Postgres(p) => p.runs(),
        }
    }
}

/// Every run with its count of finished evaluations, best score and best values, by id:
/// the same statement on both engines (it takes no parameters).
pub(crate) const RUNS_WITH_BEST: &str = "SELECT r.id, r.config, r.algorithm, r.seed, r.fitness, r.duration, r.genes, r.started, r.finished,
        (SELECT COUNT(*) FROM evaluations e WHERE e.run = r.id AND e.state = 'done'),
        (SELECT MAX(score) FROM evaluations e WHERE e.run = r.id AND e.state = 'done'),
        (SELECT vals FROM evaluations e WHERE e.run = r.id AND e.state = 'done' AND e.score IS NOT NULL
         ORDER BY score DESC, number LIMIT 1),
        (SELECT engine_scores FROM evaluations e WHERE e.run = r.id AND e.state = 'done' AND e.score IS NOT NULL
         ORDER BY score DESC, number LIMIT 1)
     FROM runs r ORDER BY r.id";

/// Numbers as one space-separated text column.
pub(crate) fn join<T: ToString>(v: &[T]) -> String {
    v.iter().map(T::to_string).collect::<Vec<_>>().join(" ")
}

/// The numbers of a [`join`]ed column.
pub(crate) fn parse_list<T: std::str::FromStr>(text: &str) -> Vec<T> {
    text.split_whitespace()
        .filter_map(|t| t.parse().ok())
        .collect()
}

/// Engine scores as one text column: `rapier=0.51 mujoco=0.41` (empty on one engine).
pub fn engine_scores_text(scores: &[(EngineKind, f64)]) -> String {
    let parts: Vec<String> = scores.iter().map(|(k, s)| format!("{k}={s}")).collect();
    parts.join(" ")
}

/// The engine scores of an [`engine_scores_text`] column (unreadable parts are skipped).
pub fn parse_engine_scores(text: &str) -> Vec<(EngineKind, f64)> {
    text.split_whitespace()
        .filter_map(|part| {
            let (name, score) = part.split_once('=')?;
            Some((EngineKind::parse(name)?, score.parse().ok()?))
        })
        .collect()
}

/// A score as stored: NaN (a failed episode) as NULL.
pub(crate) fn score_of(score: f64) -> Option<f64> {
    (!score.is_nan()).then_some(score)
}

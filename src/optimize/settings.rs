//! How an optimization run goes: seed, workers, batching, budget, episode length and
//! fitness, built in one place from a simulation's files and the user's choices (the
//! command line's flags, the control window's optimization view), and the stop flag ([`StopFlag`], the signal module's).

use std::time::Duration;

use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::optimize::error::BadChoice;
use crate::signal::StopFlag;

/// Neighbours the great deluge hands out per round (fixed, so its candidates do not depend
/// on the worker count).
pub const DELUGE_BATCH: usize = 8;

/// Seconds a shared store's claim stays valid without a heartbeat, unless chosen.
pub const DEFAULT_LEASE_S: f64 = 60.0;

/// How to run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSettings {
    /// Seed of the optimizer and of every episode.
    pub seed: u64,
    /// Worker threads evaluating batches (0 only with a shared store: remote workers).
    pub workers: usize,
    /// Robots per world (0: split each round evenly over the workers).
    pub batch: usize,
    /// Great deluge: neighbours handed out per round.
    pub deluge_batch: usize,
    /// Evaluation budget.
    pub max_evaluations: u64,
    /// Simulated seconds per episode.
    pub duration: f64,
    /// How episodes are scored.
    pub fitness: Fitness,
    /// With a shared store: how long a claim stays valid without a heartbeat (a killed
    /// worker's evaluations are claimed again this long after its last one).
    pub lease: Duration,
    /// Ends the run early when set (between rounds).
    pub stop: StopFlag,
    /// Ends the run, finished, at the end of the first round whose best score reaches this
    /// (a curriculum's stage, [`crate::optimize::curriculum`]); none: the budget ends it.
    pub until: Option<f64>,
}

/// Robots per world unless the user asks for more: each evaluation in a world of its own,
/// so scores do not depend on the number of workers. Sharing worlds (`--batch N`) is faster
/// on small robots, but on scenarios with many contacts (experiment 2) the scores move
/// slightly with N (docs/MEASUREMENTS.md).
pub const DEFAULT_BATCH: usize = 1;

/// What the user chose; `None` takes the simulation's files (the optimizer file's budget
/// and fitness, the simulation's seed and duration) or, for workers, every core.
#[derive(Debug, Clone, PartialEq)]
pub struct RunChoices {
    /// Seed of the run (default: the simulation's).
    pub seed: Option<u64>,
    /// Worker threads (default: the cores available).
    pub workers: Option<usize>,
    /// Robots per world (0: split each round evenly over the workers; default
    /// [`DEFAULT_BATCH`]).
    pub batch: usize,
    /// Evaluation budget (default: the optimizer file's, else unlimited).
    pub max_evaluations: Option<u64>,
    /// Simulated seconds per episode (default: the simulation's duration).
    pub duration: Option<f64>,
    /// Fitness (default: the optimizer file's, else displacement).
    pub fitness: Option<Fitness>,
    /// Lease of a shared store's claims, seconds (default [`DEFAULT_LEASE_S`]).
    pub lease: Option<f64>,
}

impl Default for RunChoices {
    fn default() -> Self {
        RunChoices {
            seed: None,
            workers: None,
            batch: DEFAULT_BATCH,
            max_evaluations: None,
            duration: None,
            fitness: None,
            lease: None,
        }
    }
}

impl RunSettings {
    /// The settings of a run of `sim` with the user's `choices`; the error names the bad
    /// choice.
    pub fn of(sim: &Simulation, choices: &RunChoices) -> Result<RunSettings, BadChoice> {
        let props = &sim.files.simulation.properties;
        let spec = sim.optimizer.as_ref().map(|m| &m.spec);
        let duration = choices.duration.unwrap_or(props.duration);
        if !duration.is_finite() || duration <= 0.0 {
            return Err(BadChoice::Duration(duration));
        }
        let lease = choices.lease.unwrap_or(DEFAULT_LEASE_S);
        if !lease.is_finite() || lease <= 0.0 {
            return Err(BadChoice::Lease(lease));
        }
        let workers = choices.workers.unwrap_or_else(|| {
            std::thread::available_parallelism()
                .map(|n| n.get())
                .unwrap_or(1)
        });
        Ok(RunSettings {
            seed: choices.seed.unwrap_or(props.seed),
            workers,
            batch: choices.batch,
            deluge_batch: DELUGE_BATCH,
            max_evaluations: choices
                .max_evaluations
                .or(spec.and_then(|s| s.max_evaluations))
                .unwrap_or(u64::MAX),
            duration,
            fitness: choices
                .fitness
                .or(spec.map(|s| s.fitness))
                .unwrap_or(Fitness::Displacement),
            lease: Duration::from_secs_f64(lease),
            stop: StopFlag::default(),
            until: None,
        })
    }
}

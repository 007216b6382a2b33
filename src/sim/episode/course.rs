//! One episode of a suite: a controller on one test course of one task, on one engine, run
//! by the one episode runner and measured along the course: how far its centre of mass
//! got ahead of the start, and whether it crossed the goal line.

use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::config::simulation::EngineKind;
use crate::config::suite::Task;
use crate::control::ModuleRegistry;
use crate::signal::StopFlag;
use crate::sim::{
    BuildOptions, Episode, EpisodeEnd, EpisodeSettings, SimError, Simulator, WorldExit,
};

/// Which episode: a task, a test seed, an engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EpisodeKey {
    /// The task's index in the suite.
    pub task: usize,
    /// The terrain's seed (one of the task's test seeds).
    pub seed: u64,
    /// The engine.
    pub engine: EngineKind,
}

/// How an episode ended, for the journal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    /// It ran the task's duration.
    Duration,
    /// The robot left the course's world (fell off its side): measured where it left.
    Left,
    /// The physics diverged: scored as no progress.
    Diverged,
}

impl Ended {
    /// The name the journal uses.
    pub fn name(self) -> &'static str {
        match self {
            Ended::Duration => "duration",
            Ended::Left => "left",
            Ended::Diverged => "diverged",
        }
    }

    /// Its number in a store's measures.
    pub fn code(self) -> u8 {
        match self {
            Ended::Duration => 0,
            Ended::Left => 1,
            Ended::Diverged => 2,
        }
    }

    /// The end a store's measure names.
    pub fn of_code(code: f64) -> Option<Ended> {
        [Ended::Duration, Ended::Left, Ended::Diverged]
            .into_iter()
            .find(|e| f64::from(e.code()) == code)
    }

    /// Reads a journal name.
    pub fn parse(s: &str) -> Option<Ended> {
        [Ended::Duration, Ended::Left, Ended::Diverged]
            .into_iter()
            .find(|e| e.name() == s)
    }
}

/// What one episode measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpisodeResult {
    /// Which episode.
    pub key: EpisodeKey,
    /// Metres its centre of mass ended ahead of the start along the course (0 diverged).
    pub distance: f64,
    /// Whether it crossed the goal line at some point.
    pub crossed: bool,
    /// How it ended.
    pub ended: Ended,
}

/// Runs `sim` (a task's world, [`Simulation::on_course`](crate::config::Simulation::on_course)) on `engine` for the
/// task's duration; `None` when `stop` was raised before it ended, an error when a module
/// failed during it (its distance is not the file's control's).
pub fn run_episode(
    sim: &Simulation,
    task: &Task,
    key: EpisodeKey,
    registry: &ModuleRegistry,
    stop: Option<&StopFlag>,
) -> Result<Option<EpisodeResult>, SimError> {
    let opts = BuildOptions {
        robots: 1,
        seed: sim.files.simulation.properties.seed,
        record: false,
        engine: key.engine.into(),
        ..BuildOptions::default()
    };
    let mut s = Simulator::with_registry(sim, &opts, registry)?;
    let settings = EpisodeSettings::new(&s, task.duration, Fitness::Distance);
    let mut episode = Episode::begin(&s, settings)?;
    let start = episode.start(0).com;
    let dir = task.direction();
    let along = |c: [f64; 3]| (0..3).map(|i| (c[i] - start[i]) * dir[i]).sum::<f64>();
    let (mut last, mut furthest) = (0.0_f64, 0.0_f64);
    let end = episode.run(&mut s, stop, |s| {
        let c = s.com(0)?;
        if c.iter().all(|v| v.is_finite()) {
            last = along(c);
            furthest = furthest.max(last);
        }
        Ok::<(), SimError>(())
    })?;
    let ended = match end {
        EpisodeEnd::Stopped => return Ok(None),
        EpisodeEnd::Duration => Ended::Duration,
        EpisodeEnd::Left(WorldExit::Left(_)) => Ended::Left,
        EpisodeEnd::Left(WorldExit::Diverged) => Ended::Diverged,
    };
    if let Some((module, cause)) = s.kernel(0)?.failures().next() {
        return Err(SimError::ModuleFailed {
            module: module.to_string(),
            cause: cause.to_string(),
        });
    }
    let diverged = ended == Ended::Diverged;
    Ok(Some(EpisodeResult {
        key,
        distance: if diverged { 0.0 } else { last },
        crossed: !diverged && furthest >= task.goal,
        ended,
    }))
}

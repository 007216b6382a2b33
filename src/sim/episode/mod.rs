//! The one episode runner. It builds nothing: it runs a prepared [`Simulator`] to the end
//! of an episode — its duration, every robot leaving the world, the physics diverging
//! ([`exit`], the one exit rule), or a raised [`StopFlag`] — in chunks a caller may observe
//! between (progress, plots, recording, a behaviour probe), and scores each robot through
//! the one [`robot_score`] ([`score`]): a robot that left is scored as it was when it left.
//! `proleg run`, the evaluator, the Gymnasium environment and the control window each run
//! their episodes through an [`Episode`].
//!
//! - [`exit`]: the exit rule ([`WorldExit`], the [`Scenery`] box and its margins)
//! - [`score`]: the fitness of an episode and a robot's score in a running world
//! - [`course`]: one episode on a suite task's course, measured along it (distance, the goal
//!   line crossed): what `proleg suite` and its workers run

pub mod course;
pub mod exit;
pub mod score;

use crate::config::fitness::Fitness;
use crate::signal::StopFlag;
use crate::sim::Simulator;
use crate::sim::error::SimError;

pub use exit::{BLOW_UP_DISTANCE, Scenery, WORLD_MARGIN, WorldExit, WorldMargin};
pub use score::{Measured, RobotStart, robot_score};

/// Simulated seconds between two checks of the exit rule (and of the stop flag), unless
/// an episode asks for another cadence: `proleg run` and an optimizer's episode share it,
/// so both stop at the same step.
pub const EXIT_CHECK_SECONDS: f64 = 0.05;

/// How an episode runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpisodeSettings {
    /// Steps until the episode ends by its duration (`None`: open-ended, a window's run
    /// continued past its duration).
    pub steps: Option<u64>,
    /// Steps between two checks of the exit rule, the stop flag and the observer.
    pub check_every: u64,
    /// How a robot is scored.
    pub fitness: Fitness,
    /// Whether leaving the scenery ends a robot's episode (a window may watch on after
    /// it); a diverged world always does.
    pub watch_world: bool,
}

impl EpisodeSettings {
    /// An episode of `duration` simulated seconds of `sim`'s steps, checked every
    /// [`EXIT_CHECK_SECONDS`], scored by `fitness`.
    pub fn new(sim: &Simulator, duration: f64, fitness: Fitness) -> EpisodeSettings {
        let dt = sim.clock().dt;
        EpisodeSettings {
            steps: Some((duration / dt).round().max(0.0) as u64),
            check_every: (EXIT_CHECK_SECONDS / dt).round().max(1.0) as u64,
            fitness,
            watch_world: true,
        }
    }
}

/// How an episode ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EpisodeEnd {
    /// It ran its duration.
    Duration,
    /// Every robot left the world: the last one's exit (robot 0's, for one robot).
    Left(WorldExit),
    /// Its stop flag was raised (Ctrl-C, SIGTERM, a window's Stop): the episode was
    /// abandoned between two chunks and scores nothing.
    Stopped,
}

/// A robot's end before the episode's.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RobotEnd {
    exit: WorldExit,
    /// Its score when it left (`-inf` for a diverged world).
    score: f64,
}

/// One running episode's bookkeeping over a [`Simulator`] it does not own.
#[derive(Debug, Clone, PartialEq)]
pub struct Episode {
    settings: EpisodeSettings,
    starts: Vec<RobotStart>,
    scenery: Option<Scenery>,
    /// The world's step counter when the episode began.
    first_step: u64,
    ends: Vec<Option<RobotEnd>>,
    end: Option<EpisodeEnd>,
}

impl Episode {
    /// Begins an episode of every robot of `sim`, where they are now.
    pub fn begin(sim: &Simulator, settings: EpisodeSettings) -> Result<Episode, SimError> {
        let starts = (0..sim.robots().len())
            .map(|i| RobotStart::of(sim, i))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Episode {
            settings,
            ends: vec![None; starts.len()],
            starts,
            scenery: Scenery::of(sim),
            first_step: sim.clock().step,
            end: None,
        })
    }

    /// The settings it runs with.
    pub fn settings(&self) -> &EpisodeSettings {
        &self.settings
    }

    /// Steps run since it began.
    pub fn steps(&self, sim: &Simulator) -> u64 {
        sim.clock().step - self.first_step
    }

    /// Simulated seconds since it began.
    pub fn time(&self, sim: &Simulator) -> f64 {
        self.steps(sim) as f64 * sim.clock().dt
    }

    /// Where robot `robot` started (the default for a robot the world does not have).
    pub fn start(&self, robot: usize) -> RobotStart {
        self.starts.get(robot).copied().unwrap_or_default()
    }

    /// The static scenery's box, if the world has any.
    pub fn scenery(&self) -> Option<Scenery> {
        self.scenery
    }

    /// How it ended, once it did.
    pub fn end(&self) -> Option<EpisodeEnd> {
        self.end
    }

    /// How robot `robot` left the world, if it did.
    pub fn exit(&self, robot: usize) -> Option<WorldExit> {
        self.ends.get(robot).copied().flatten().map(|e| e.exit)
    }

    /// Robot `robot`'s score: as it was when it left the world, else as it is now.
    pub fn score(&self, sim: &Simulator, robot: usize) -> Result<f64, SimError> {
        match self.ends.get(robot).copied().flatten() {
            Some(e) => Ok(e.score),
            None => robot_score(
                sim,
                robot,
                self.start(robot),
                self.time(sim),
                self.settings.fitness,
            ),
        }
    }

    /// Runs on past the way it ended (a window's Continue): past its duration, or on with
    /// the robots outside the world (leaving is no longer watched). A diverged or stopped
    /// episode stays ended.
    pub fn continue_past(&mut self) {
        match self.end {
            Some(EpisodeEnd::Duration) => self.settings.steps = None,
            Some(EpisodeEnd::Left(WorldExit::Left(_))) => {
                self.settings.watch_world = false;
                for e in &mut self.ends {
                    if e.is_some_and(|e| matches!(e.exit, WorldExit::Left(_))) {
                        *e = None;
                    }
                }
            }
            _ => return,
        }
        self.end = None;
    }

    /// Runs at most `max` steps, checking the exit rule at every multiple of the cadence
    /// and at the duration, and the stop flag before every chunk (so where a robot is
    /// found to have left does not depend on how a caller splits the steps).
    /// Returns how the episode ended, once it has.
    pub fn advance(
        &mut self,
        sim: &mut Simulator,
        max: u64,
        stop: Option<&StopFlag>,
    ) -> Result<Option<EpisodeEnd>, SimError> {
        let mut left = max;
        while self.end.is_none() && left > 0 {
            if stop.is_some_and(StopFlag::is_set) {
                self.end = Some(EpisodeEnd::Stopped);
                break;
            }
            let done = self.steps(sim);
            let cadence = self.settings.check_every.max(1);
            let mut piece = left.min(cadence - done % cadence);
            if let Some(total) = self.settings.steps {
                piece = piece.min(total.saturating_sub(done));
            }
            if piece == 0 {
                // At the duration already: only the check below remains.
                self.check(sim)?;
                break;
            }
            sim.run_steps(piece);
            left -= piece;
            let after = done + piece;
            let at_end = self.settings.steps.is_some_and(|t| after >= t);
            if after.is_multiple_of(cadence) || at_end {
                self.check(sim)?;
            }
        }
        Ok(self.end)
    }

    /// Runs to its end, calling `observe` after every chunk of the cadence (before the
    /// exit rule reads the world, so it sees every chunk a robot ran); returns how it
    /// ended. An open-ended episode runs until a robot leaves or `stop` is raised.
    pub fn run<E: From<SimError>>(
        &mut self,
        sim: &mut Simulator,
        stop: Option<&StopFlag>,
        mut observe: impl FnMut(&Simulator) -> Result<(), E>,
    ) -> Result<EpisodeEnd, E> {
        loop {
            if let Some(end) = self.end {
                return Ok(end);
            }
            let cadence = self.settings.check_every.max(1);
            let next = cadence - self.steps(sim) % cadence;
            let before = self.steps(sim);
            self.advance(sim, next, stop)?;
            if self.steps(sim) > before {
                observe(sim)?;
            }
        }
    }

    /// Applies the exit rule to every robot still in the world, then the duration.
    fn check(&mut self, sim: &Simulator) -> Result<(), SimError> {
        let mut last = None;
        for robot in 0..self.ends.len() {
            if self.ends[robot].is_some() {
                continue;
            }
            let start = self.start(robot).com;
            let exit = exit::world_exit(sim, robot, self.scenery.as_ref(), start)?;
            let exit = match exit {
                Some(WorldExit::Left(_)) if !self.settings.watch_world => None,
                e => e,
            };
            if let Some(exit) = exit {
                let score = match exit {
                    WorldExit::Diverged => f64::NEG_INFINITY,
                    WorldExit::Left(_) => self.score(sim, robot)?,
                };
                self.ends[robot] = Some(RobotEnd { exit, score });
                last = Some(exit);
            }
        }
        if let Some(exit) = last
            && self.ends.iter().all(Option::is_some)
        {
            self.end = Some(EpisodeEnd::Left(exit));
        } else if self
            .settings
            .steps
            .is_some_and(|total| self.steps(sim) >= total)
        {
            self.end = Some(EpisodeEnd::Duration);
        }
        Ok(())
    }
}

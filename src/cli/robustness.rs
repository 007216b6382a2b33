//! `proleg robustness`: a stored candidate (a run's best, or any evaluation) re-evaluated on
//! fresh randomized episodes — how much of its displacement a gait keeps on a floor, robot
//! and start it was not tuned on, before it goes to the real robot.

use std::fmt;

use crate::config::robustness::Robustness;
use crate::control::ModuleRegistry;
use crate::optimize::replay::{FreshEpisodes, OnCourse, RandomizedCheck, Which, randomized_check};

/// Command-line options of `proleg robustness`.
#[derive(clap::Args)]
pub struct RobustnessArgs {
    /// The store holding the run (a results .sqlite file or a postgres:// URL).
    pub store: String,
    /// The run's id (`proleg results STORE` lists them).
    #[arg(long)]
    pub run: i64,
    /// The evaluation's number, or "best".
    #[arg(long, default_value = "best")]
    pub eval: String,
    /// Randomized episodes.
    #[arg(long, default_value_t = 20)]
    pub episodes: u32,
    /// Seed of the episodes (choose one no run used, for fresh episodes).
    #[arg(long, default_value_t = 1000)]
    pub seed: u64,
    /// The physics engines instead of the run's (rapier, mujoco; comma-separated: each is
    /// checked in turn): how the gait fares on the other engine.
    #[arg(long = "engines", visible_alias = "engine", value_delimiter = ',')]
    pub engines: Vec<crate::config::simulation::EngineKind>,
    /// A suite task's course instead of the run's own world, as TASK:SEED (a test seed for
    /// a held-out world, e.g. steps-medium:101); with --suite.
    #[arg(long, requires = "suite")]
    pub course: Option<CourseArg>,
    /// The suite file --course names a task of.
    #[arg(long, requires = "course")]
    pub suite: Option<std::path::PathBuf>,
}

/// `--course TASK:SEED`.
#[derive(Debug, Clone, PartialEq)]
pub struct CourseArg {
    /// The task's name.
    pub task: String,
    /// The course's terrain seed.
    pub seed: u64,
}

/// A `--course` that is not `TASK:SEED`.
#[derive(Debug, thiserror::Error)]
#[error("{0:?}: give TASK:SEED, e.g. steps-medium:101")]
pub struct BadCourse(String);

impl std::str::FromStr for CourseArg {
    type Err = BadCourse;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || BadCourse(s.to_string());
        let (task, seed) = s.rsplit_once(':').ok_or_else(bad)?;
        let seed = seed.trim().parse().map_err(|_| bad())?;
        if task.trim().is_empty() {
            return Err(bad());
        }
        Ok(CourseArg {
            task: task.trim().to_string(),
            seed,
        })
    }
}

/// The checks of one candidate, one per engine asked for (the run's engine when none).
#[derive(Debug, Clone, PartialEq)]
pub struct RobustnessReport {
    /// One check per engine, in the order asked for.
    pub checks: Vec<RandomizedCheck>,
}

/// Runs the checks the options ask for, with [`Robustness::typical`] ranges.
pub fn run(
    a: &RobustnessArgs,
    registry: &ModuleRegistry,
) -> Result<RobustnessReport, crate::optimize::replay::ReplayError> {
    let which = Which::parse(&a.eval)?;
    let course = match (&a.course, &a.suite) {
        (Some(c), Some(suite)) => Some(OnCourse {
            suite: suite.clone(),
            task: c.task.clone(),
            seed: c.seed,
        }),
        _ => None,
    };
    let engines: Vec<Option<_>> = match a.engines.as_slice() {
        [] => vec![None],
        list => list.iter().copied().map(Some).collect(),
    };
    let mut checks = Vec::with_capacity(engines.len());
    for engine in engines {
        checks.push(randomized_check(
            &a.store,
            a.run,
            which,
            &Robustness::typical(),
            FreshEpisodes {
                count: a.episodes,
                seed: a.seed,
                course: course.clone(),
            },
            engine,
            registry,
        )?);
    }
    Ok(RobustnessReport { checks })
}

impl fmt::Display for RobustnessReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, c) in self.checks.iter().enumerate() {
            if i > 0 {
                writeln!(out)?;
            }
            write!(out, "{c}")?;
        }
        Ok(())
    }
}

impl fmt::Display for RandomizedCheck {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(out, "{}", self.label)?;
        writeln!(out, "randomized: {}", self.ranges.describe())?;
        let scores: Vec<String> = self.scores.iter().map(|s| format!("{s:.3}")).collect();
        writeln!(out, "episodes    {}", scores.join(" "))?;
        writeln!(out, "nominal     {:.4}", self.nominal)?;
        writeln!(
            out,
            "randomized  mean {:.4}, lower quartile {:.4}, min {:.4}",
            self.mean(),
            self.lower_quartile(),
            self.scores.iter().copied().fold(f64::INFINITY, f64::min)
        )?;
        writeln!(
            out,
            "kept        {:.1}% of the nominal score",
            self.kept() * 100.0
        )
    }
}

//! A suite task's courses under an environment: with `terrain="pegs"` (and `difficulty`,
//! `suite`) each reset builds the robot on one of the task's courses — a train seed drawn
//! from the episode's seed (`split="train"`, the default), one of the task's test seeds
//! (`split="test"`), or `terrain_seed` when given. A generated course is kept for the next
//! reset on the same seed (a task has a few dozen), so only a seed's first reset pays for
//! its generation; the environments of a vector environment share what they keep
//! ([`CourseCache`]), so a course is held once, not once per lane.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use crate::config::Simulation;
use crate::config::source::FsSource;
use crate::config::suite::{Task, load_suite};
use crate::config::terrain::Family;
use crate::gym::error::GymError;
use crate::rng::SimRng;

/// Which of a task's seed lists resets draw from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// The train seeds (what a policy may learn on).
    Train,
    /// The held-out test seeds (what a policy is scored on).
    Test,
}

impl Split {
    /// Reads `"train"` or `"test"`.
    pub fn parse(s: &str) -> Result<Split, GymError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "train" => Ok(Split::Train),
            "test" => Ok(Split::Test),
            _ => Err(GymError::Option {
                option: "split",
                value: s.to_string(),
                want: "give \"train\" or \"test\"",
            }),
        }
    }

    /// The name [`Split::parse`] reads.
    pub fn name(self) -> &'static str {
        match self {
            Split::Train => "train",
            Split::Test => "test",
        }
    }
}

/// What the options ask for: a family at a difficulty of a suite's tasks.
#[derive(Debug, Clone, PartialEq)]
pub struct CourseOptions {
    /// The family.
    pub family: Family,
    /// Its difficulty in [0, 1].
    pub difficulty: f64,
    /// The suite file holding the task.
    pub suite: PathBuf,
    /// Which seed list.
    pub split: Split,
    /// One course for every reset, instead of a drawn one.
    pub terrain_seed: Option<u64>,
}

/// The simulation on each course generated so far, by terrain seed: one environment's,
/// or shared by the lanes of a vector environment (all on the same file and task).
#[derive(Debug, Clone, Default)]
pub struct CourseCache(Arc<Mutex<BTreeMap<u64, Arc<Simulation>>>>);

impl CourseCache {
    /// Courses kept.
    pub fn len(&self) -> usize {
        self.map().len()
    }

    /// Whether none is kept yet.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The map; a lane that panicked while holding it left it whole (an insert is the
    /// only change), so a poisoned lock is taken as it is.
    fn map(&self) -> std::sync::MutexGuard<'_, BTreeMap<u64, Arc<Simulation>>> {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// A task's courses, generated as resets need them.
#[derive(Debug)]
pub struct Courses {
    task: Task,
    suite: PathBuf,
    seeds: Vec<u64>,
    fixed: Option<u64>,
    made: CourseCache,
}

impl Courses {
    /// The task of `o` in its suite, or why there is none; its courses are kept in
    /// `cache`.
    pub fn new(o: &CourseOptions, cache: CourseCache) -> Result<Courses, GymError> {
        let suite = load_suite(&FsSource, &o.suite)?;
        let family = o.family.name();
        let same = |t: &&Task| t.terrain.family == o.family;
        let Some(task) = suite
            .tasks
            .iter()
            .filter(same)
            .find(|t| (t.terrain.difficulty - o.difficulty).abs() < 1e-9)
        else {
            let known: Vec<String> = suite
                .tasks
                .iter()
                .filter(same)
                .map(|t| format!("{} ({})", t.name, t.terrain.difficulty))
                .collect();
            return Err(GymError::NoTask {
                suite: o.suite.display().to_string(),
                family: family.to_string(),
                difficulty: o.difficulty,
                known: if known.is_empty() {
                    "none of that family".into()
                } else {
                    known.join(", ")
                },
            });
        };
        let seeds = match o.split {
            Split::Train => task.train.clone(),
            Split::Test => task.test.clone(),
        };
        if seeds.is_empty() && o.terrain_seed.is_none() {
            return Err(GymError::HeldOut {
                task: task.name.clone(),
            });
        }
        Ok(Courses {
            task: task.clone(),
            suite: o.suite.clone(),
            seeds,
            fixed: o.terrain_seed,
            made: cache,
        })
    }

    /// The task.
    pub fn task(&self) -> &Task {
        &self.task
    }

    /// The terrain seed of the episode of seed `episode_seed`.
    pub fn pick(&self, episode_seed: u64) -> u64 {
        self.fixed.unwrap_or_else(|| {
            let k = SimRng::new(episode_seed ^ 0x636f_7572_7365).next_u64();
            self.seeds[(k % self.seeds.len().max(1) as u64) as usize]
        })
    }

    /// `base` on the course of terrain seed `seed` (generated at its first use by any
    /// environment sharing the cache; the others wait for it rather than make it twice).
    pub fn world(&self, base: &Simulation, seed: u64) -> Result<Arc<Simulation>, GymError> {
        let mut made = self.made.map();
        if let Some(sim) = made.get(&seed) {
            return Ok(Arc::clone(sim));
        }
        let sim = Arc::new(base.on_course(&self.task, seed, &self.suite)?);
        made.insert(seed, Arc::clone(&sim));
        Ok(sim)
    }

    /// The courses kept.
    pub fn cache(&self) -> &CourseCache {
        &self.made
    }
}

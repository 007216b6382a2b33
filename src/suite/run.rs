//! A suite run: every selected task's test courses on every chosen engine, in parallel on
//! the local cores, each finished episode written to the journal at once; episodes the
//! journal already holds are not run again, so a stopped run resumes to the same table.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use rayon::prelude::*;

use crate::config::Simulation;
use crate::config::simulation::EngineKind;
use crate::config::suite::SuiteFile;
use crate::control::ModuleRegistry;
use crate::signal::StopFlag;
use crate::sim::episode::course::{EpisodeKey, EpisodeResult, run_episode};
use crate::suite::error::SuiteError;
use crate::suite::journal::Journal;
use crate::suite::report::{SuiteReport, report};
use crate::suite::shared::{SharedSuite, run_on_store};

/// What to run.
pub struct SuiteRun<'a> {
    /// The suite file (what errors name).
    pub path: PathBuf,
    /// The suite.
    pub suite: &'a SuiteFile,
    /// The controller: its robot, control and physics properties.
    pub controller: &'a Simulation,
    /// How the report names the controller.
    pub label: String,
    /// The engines every course runs on.
    pub engines: Vec<EngineKind>,
    /// The tasks (indices into the suite), in the order they are reported.
    pub tasks: Vec<usize>,
    /// Worker threads (each runs one episode at a time).
    pub threads: usize,
    /// The journal file.
    pub journal: PathBuf,
    /// Run on a shared store's workers instead of the local cores alone (`threads` of
    /// them then among the workers).
    pub shared: Option<SharedSuite>,
}

/// Called after every finished episode: it, and how many of how many are done.
pub type Progress<'p> = &'p (dyn Fn(&EpisodeResult, usize, usize) + Sync);

impl SuiteRun<'_> {
    /// The tasks named (all when none), or the first unknown name.
    pub fn select(suite: &SuiteFile, names: &[String]) -> Result<Vec<usize>, SuiteError> {
        if names.is_empty() {
            return Ok((0..suite.tasks.len()).collect());
        }
        names
            .iter()
            .map(|n| {
                suite
                    .tasks
                    .iter()
                    .position(|t| crate::config::xml::read::same_name(&t.name, n))
                    .ok_or_else(|| SuiteError::UnknownTask {
                        name: n.clone(),
                        known: suite
                            .tasks
                            .iter()
                            .map(|t| t.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", "),
                    })
            })
            .collect()
    }

    /// Every episode of the run, in a fixed order.
    pub fn episodes(&self) -> Vec<EpisodeKey> {
        let mut keys = Vec::new();
        for &task in &self.tasks {
            for &seed in &self.suite.tasks[task].test {
                for &engine in &self.engines {
                    keys.push(EpisodeKey { task, seed, engine });
                }
            }
        }
        keys
    }

    /// How the episode `key` is named in messages.
    pub fn describe(&self, key: EpisodeKey) -> String {
        format!(
            "{} seed {} on {}",
            self.suite.tasks[key.task].name,
            key.seed,
            key.engine.name()
        )
    }

    /// The journal's first line: the suite and the run's [`fingerprint`](Self::fingerprint).
    pub fn run_line(&self) -> String {
        format!(
            "# proleg suite {} run {:016x}",
            self.suite.name,
            self.fingerprint()
        )
    }

    /// A fingerprint of the suite, of what the controller is and of the ground (each
    /// task's first test course as generated, so a journal or a stored run made by another
    /// version of a terrain family is not taken for this run's).
    pub fn fingerprint(&self) -> u64 {
        let c = self.controller;
        let props = &c.files.simulation.properties;
        let mut what = format!(
            "{:?}{:?}{:?}{:?}{:?}{}",
            c.robot,
            c.actuation,
            c.environment.physics,
            c.environment.robot_pose,
            (props.step_width, props.seed),
            crate::config::suite::write_suite_file(self.suite)
        );
        for task in &self.suite.tasks {
            if let Some(&seed) = task.test.first() {
                let g = crate::config::terrain::generate(&task.course(seed));
                what += &format!("{:?}", g.kinbody.bodies);
                for (_, mesh) in &g.meshes {
                    what += &format!("{:?}", mesh.vertices);
                }
            }
        }
        what.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
    }

    /// Runs what the journal does not hold yet; returns the report of all of it.
    pub fn run(
        &self,
        registry: &ModuleRegistry,
        stop: Option<&StopFlag>,
        progress: Progress<'_>,
    ) -> Result<SuiteReport, SuiteError> {
        for &e in &self.engines {
            crate::sim::engine::ready(e).map_err(SuiteError::Engine)?;
        }
        let journal = Mutex::new(Journal::open(&self.journal, &self.run_line(), self.suite)?);
        let all = self.episodes();
        let total = all.len();
        match &self.shared {
            Some(shared) => run_on_store(self, shared, registry, &journal, &all, stop, progress)?,
            None => self.run_here(&journal, &all, registry, stop, progress)?,
        }
        let j = lock(&journal);
        let done = all.iter().filter(|k| j.done.contains_key(k)).count();
        if done < total {
            return Err(SuiteError::Stopped { done, total });
        }
        Ok(report(
            self.suite,
            &self.tasks,
            &self.engines,
            &self.label,
            &j.done,
        ))
    }

    /// Runs the episodes of `all` the journal lacks on the local cores, each result into
    /// the journal as it ends.
    fn run_here(
        &self,
        journal: &Mutex<Journal>,
        all: &[EpisodeKey],
        registry: &ModuleRegistry,
        stop: Option<&StopFlag>,
        progress: Progress<'_>,
    ) -> Result<(), SuiteError> {
        let todo: Vec<EpisodeKey> = {
            let j = lock(journal);
            all.iter()
                .copied()
                .filter(|k| !j.done.contains_key(k))
                .collect()
        };
        let total = all.len();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.max(1))
            .build()
            .map_err(|e| SuiteError::Journal {
                path: self.journal.clone(),
                source: std::io::Error::other(e),
            })?;
        let outcome: Result<(), SuiteError> = pool.install(|| {
            todo.par_iter().try_for_each(|&key| {
                let task = &self.suite.tasks[key.task];
                let world = self.controller.on_course(task, key.seed, &self.path)?;
                let Some(r) = run_episode(&world, task, key, registry, stop)? else {
                    return Ok(());
                };
                let mut j = lock(journal);
                j.append(self.suite, &r)?;
                let done = all.iter().filter(|k| j.done.contains_key(k)).count();
                progress(&r, done, total);
                Ok(())
            })
        });
        outcome
    }
}

/// The journal, locked.
pub(crate) fn lock(j: &Mutex<Journal>) -> std::sync::MutexGuard<'_, Journal> {
    // The journal's state is its file and the map, both whole after every append.
    j.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The journal file in an output folder.
pub fn journal_path(out: &Path) -> PathBuf {
    out.join("episodes.csv")
}

//! A suite run on a shared store (`proleg suite ... --store URL`): a stored run whose
//! evaluations are episodes, not candidates. [`SuiteJob`] is how its [`RunInfo`] tells it
//! from an optimization run (and names the suite file among its stored files); each
//! evaluation's genome names one episode, a task, one of its test seeds and an engine
//! ([`episode_entry`], [`episode_key`]); its score is the episode's distance along the
//! course and its measures whether it crossed the goal line and how it ended
//! ([`episode_score`], [`episode_result`]). A worker runs one with [`CourseEpisodes`].

use std::path::PathBuf;

use crate::config::simulation::EngineKind;
use crate::config::suite::{SuiteFile, load_suite};
use crate::config::{MemSource, Simulation};
use crate::control::ModuleRegistry;
use crate::optimize::error::UnevaluableRun;
use crate::optimize::evaluate::EvalError;
use crate::optimize::scores::{CandidateScore, StoredEval};
use crate::optimize::shared::stored_simulation;
use crate::optimize::space::Genome;
use crate::optimize::store::{RunInfo, RunSpec, program_version};
use crate::signal::StopFlag;
use crate::sim::episode::course::{Ended, EpisodeKey, EpisodeResult, run_episode};

/// The fitness name that marks a suite run.
pub const SUITE_FITNESS: &str = "suite episode: distance along the course (m)";

/// The gene names of a suite run's evaluations.
const GENES: [&str; 3] = ["task", "test seed", "engine"];

/// What makes a stored run a suite run: the suite file (its path among the run's stored
/// files), a fingerprint of the suite, controller and ground (a journal's
/// [`SuiteRun::run_line`](crate::suite::SuiteRun::run_line)), and the engines.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteJob {
    /// The suite file's path as stored.
    pub suite: String,
    /// The fingerprint.
    pub fingerprint: u64,
    /// The engines its courses run on.
    pub engines: Vec<EngineKind>,
}

impl SuiteJob {
    /// The run's identity: the controller's simulation file and seed, the job in the
    /// algorithm's place (`suite FINGERPRINT ENGINES PATH`).
    pub fn info(&self, controller: &str, seed: u64) -> RunInfo {
        let engines: Vec<&str> = self.engines.iter().map(|e| e.name()).collect();
        RunInfo {
            config: controller.to_string(),
            algorithm: format!(
                "suite {:016x} {} {}",
                self.fingerprint,
                engines.join("+"),
                self.suite
            ),
            seed,
            fitness: SUITE_FITNESS.to_string(),
            duration: 0.0,
            genes: GENES.map(String::from).to_vec(),
        }
    }

    /// The job of a suite run's identity; `None` for an optimization run.
    pub fn of(info: &RunInfo) -> Option<SuiteJob> {
        if info.fitness != SUITE_FITNESS {
            return None;
        }
        let rest = info.algorithm.strip_prefix("suite ")?;
        let (fingerprint, rest) = rest.split_once(' ')?;
        let (engines, suite) = rest.split_once(' ')?;
        Some(SuiteJob {
            suite: suite.to_string(),
            fingerprint: u64::from_str_radix(fingerprint, 16).ok()?,
            engines: engines
                .split('+')
                .map(|e| e.parse().ok())
                .collect::<Option<Vec<EngineKind>>>()?,
        })
    }
}

/// Most test seeds of one of the suite's tasks (the stride of evaluation numbers).
fn seed_stride(suite: &SuiteFile) -> u64 {
    suite.tasks.iter().map(|t| t.test.len()).max().unwrap_or(1) as u64
}

/// Episode `key`'s evaluation number in a suite run (the same whichever tasks and
/// engines a call selects) and its genome: task, test seed's place, engine's place in
/// [`EngineKind::ALL`]. `None` when the suite has no such episode.
pub fn episode_entry(suite: &SuiteFile, key: EpisodeKey) -> Option<(u64, Genome)> {
    let task = suite.tasks.get(key.task)?;
    let seed = task.test.iter().position(|&s| s == key.seed)?;
    let engine = EngineKind::ALL.iter().position(|&e| e == key.engine)?;
    let slots = EngineKind::ALL.len() as u64;
    let number = (key.task as u64 * seed_stride(suite) + seed as u64) * slots + engine as u64;
    Some((number, vec![key.task as u32, seed as u32, engine as u32]))
}

/// The episode a suite run's genome names; `None` when the suite has none such.
pub fn episode_key(suite: &SuiteFile, genome: &Genome) -> Option<EpisodeKey> {
    let [task, seed, engine] = genome.as_slice() else {
        return None;
    };
    let t = suite.tasks.get(*task as usize)?;
    Some(EpisodeKey {
        task: *task as usize,
        seed: *t.test.get(*seed as usize)?,
        engine: *EngineKind::ALL.get(*engine as usize)?,
    })
}

/// An episode's result as a stored score: the distance, and as measures whether it
/// crossed the goal line (1 or 0) and how it ended ([`Ended::code`]).
pub fn episode_score(r: &EpisodeResult) -> CandidateScore {
    CandidateScore {
        score: r.distance,
        engines: Vec::new(),
        rejected: None,
        measures: vec![f64::from(u8::from(r.crossed)), f64::from(r.ended.code())],
    }
}

/// A stored evaluation of a suite run as the episode result it holds; `None` when it holds
/// none (the episode failed on its worker, or the row is not one of a suite run's).
pub fn episode_result(suite: &SuiteFile, eval: &StoredEval) -> Option<EpisodeResult> {
    let key = episode_key(suite, &eval.genome)?;
    let [crossed, ended] = eval.measures.as_slice() else {
        return None;
    };
    if !eval.score.is_finite() {
        return None;
    }
    Some(EpisodeResult {
        key,
        distance: eval.score,
        crossed: *crossed == 1.0,
        ended: Ended::of_code(*ended)?,
    })
}

/// A worker's view of a suite run: the suite and the controller, loaded from the run's
/// stored files with this host's module types.
pub struct CourseEpisodes {
    suite: SuiteFile,
    path: PathBuf,
    controller: Simulation,
    registry: ModuleRegistry,
    stop: StopFlag,
}

impl CourseEpisodes {
    /// The episodes of stored run `spec`, a suite run `job`; an error says why this host
    /// cannot run them (another program version, MuJoCo missing, a file that does not
    /// load).
    pub fn of(
        spec: &RunSpec,
        job: &SuiteJob,
        registry: &ModuleRegistry,
    ) -> Result<CourseEpisodes, UnevaluableRun> {
        let here = program_version();
        if spec.program != here {
            return Err(UnevaluableRun::Version {
                started: spec.program.clone(),
                here,
            });
        }
        for &engine in &job.engines {
            if let Err(e) = crate::sim::engine::ready(engine) {
                return Err(UnevaluableRun::NoMujoco(e.to_string()));
            }
        }
        let mut src = MemSource::new();
        for (path, text) in &spec.files {
            src.insert(path, text.as_str());
        }
        let path = PathBuf::from(&job.suite);
        Ok(CourseEpisodes {
            suite: load_suite(&src, &path)?,
            path,
            controller: stored_simulation(spec, registry)?,
            registry: registry.clone(),
            stop: StopFlag::default(),
        })
    }

    /// The same episodes, abandoned in flight when `stop` is raised.
    pub fn with_stop(self, stop: StopFlag) -> CourseEpisodes {
        CourseEpisodes { stop, ..self }
    }

    /// Runs the episode `genome` names; its stored score.
    pub fn run(&self, genome: &Genome) -> Result<CandidateScore, EvalError> {
        let key = episode_key(&self.suite, genome)
            .ok_or_else(|| EvalError::NoSuchEpisode(genome.clone()))?;
        let task = &self.suite.tasks[key.task];
        let world = self
            .controller
            .on_course(task, key.seed, &self.path)
            .map_err(|e| EvalError::Course(Box::new(e)))?;
        match run_episode(&world, task, key, &self.registry, Some(&self.stop))? {
            Some(r) => Ok(episode_score(&r)),
            None => Err(EvalError::Stopped),
        }
    }
}

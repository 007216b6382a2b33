//! Replaying a stored evaluation: the run's stored configuration, the candidate's genome,
//! the world's seed (the run's, or a randomized episode's seed and physics), so the
//! trajectory is the one the optimization scored, step for step — headless
//! ([`Replay::score`]) or in the control window (`proleg gui --replay`).

use crate::config::Simulation;
use crate::config::fitness::Fitness;
use crate::config::robustness::Robustness;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::optimize::error::UnevaluableRun;
use crate::optimize::evaluate::{EpisodeWorld, EvalError, Evaluator};
use crate::optimize::robust::{RobustEpisodes, combine};
use crate::optimize::run::prepare;
use crate::optimize::shared::{stored_evaluator, stored_simulation};
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::{RunSpec, Store, StoreError, program_version};
use crate::sim::randomize::SensorNoise;
use crate::sim::{BuildOptions, Episode, EpisodeSettings, SimError, Simulator};

/// Why a stored evaluation cannot be replayed or checked.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The store: unreachable, refused, or without the run.
    #[error("{0}")]
    Store(#[from] StoreError),
    /// A store location that is neither a file nor a `postgres://` URL.
    #[error("{0}")]
    Location(#[from] crate::optimize::error::BadChoice),
    /// The run's stored configuration does not load or set up here.
    #[error("{0}")]
    Unevaluable(#[from] UnevaluableRun),
    /// Its search space cannot be set up.
    #[error("{0}")]
    Setup(#[source] Box<crate::optimize::error::OptimizeError>),
    /// The run has no such finished evaluation (or none at all).
    #[error("{store}: run {run} has no {}", match number { Some(n) => format!("finished evaluation {n}"), None => "evaluation".into() })]
    NoEvaluation {
        /// The store, as it may be shown.
        store: String,
        /// The run.
        run: i64,
        /// The evaluation asked for (none: the best).
        number: Option<u64>,
    },
    /// A stored genome of another length than its configuration's search space.
    #[error("evaluation {number} has {stored} genes, its configuration {configured}")]
    Genes {
        /// The evaluation.
        number: u64,
        /// Genes stored.
        stored: usize,
        /// Genes the configuration has.
        configured: usize,
    },
    /// The suite a robustness check's course comes from does not load, or the candidate
    /// cannot be put on its course.
    #[error("{0}")]
    Course(#[source] Box<crate::config::ConfigError>),
    /// A course of a task the suite does not have.
    #[error("{suite}: no task {task} (its tasks: {known})")]
    UnknownTask {
        /// The suite file.
        suite: String,
        /// The task asked for.
        task: String,
        /// The suite's tasks.
        known: String,
    },
    /// An episode asked of a run without randomized episodes.
    #[error("run {run} has no randomized episodes (no <robustness>), so no episode {episode}")]
    NoEpisodes {
        /// The run.
        run: i64,
        /// The episode asked for.
        episode: u32,
    },
    /// An episode beyond the run's.
    #[error("episode {episode}: the run has episodes 0 to {}", count.saturating_sub(1))]
    Episode {
        /// The episode asked for.
        episode: u32,
        /// The run's episodes.
        count: usize,
    },
    /// An evaluation that is neither a number nor `best`.
    #[error("evaluation {0:?}: give a number or \"best\"")]
    Which(String),
    /// The replayed episode could not be run or scored.
    #[error("{0}")]
    Run(#[from] EvalError),
    /// The replay scored nothing.
    #[error("the replay scored nothing")]
    NothingScored,
    /// The replayed world could not be built or read.
    #[error("{0}")]
    Sim(#[from] SimError),
    /// Its data file could not be opened.
    #[error("{0}")]
    Record(#[from] crate::sim::runner::RecordError),
    /// Its data file could not be completed.
    #[error("{0}")]
    Data(#[from] crate::data::store::DataStoreError),
    /// Its pose stream could not be recorded.
    #[error("{0}")]
    Playback(#[from] crate::playback::PlaybackError),
}

/// A stored evaluation, ready to run again.
#[derive(Clone)]
pub struct Replay {
    /// The world to build: the stored configuration, or a randomized episode of it.
    pub sim: Simulation,
    /// How the genome maps to module parameters.
    pub space: SearchSpace,
    /// The candidate.
    pub genome: Genome,
    /// The world's seed.
    pub seed: u64,
    /// The world's sensor noise (randomized episodes).
    pub noise: SensorNoise,
    /// Simulated seconds of the episode.
    pub duration: f64,
    /// The stored score (with robust fitness: of all the run's episodes together).
    pub stored_score: f64,
    /// What is replayed, for titles and messages.
    pub label: String,
    /// The run's simulation file, as the optimizing host named it.
    pub config: String,
    /// The stored configuration (without an episode's randomization).
    pub nominal: Simulation,
    /// The evaluation's stored score on each engine (a run with `<engines>`).
    pub stored_engines: Vec<(EngineKind, f64)>,
    /// The engine the replay runs on.
    pub engine: EngineKind,
    evaluator: Evaluator,
}

/// Evaluation `number` of run `run` in `store`; for a run with robust fitness, its episode
/// `episode` (default 0).
pub fn load_replay(
    store: &mut Store,
    run: i64,
    number: u64,
    episode: Option<u32>,
    registry: &ModuleRegistry,
) -> Result<Replay, ReplayError> {
    let spec = store.run_spec(run)?;
    crate::optimize::shared::candidate_run(&spec)?;
    let eval = store
        .evaluations_from(run, number)?
        .into_iter()
        .find(|e| e.number == number)
        .ok_or_else(|| ReplayError::NoEvaluation {
            store: store.describe(),
            run,
            number: Some(number),
        })?;
    let sim = stored_simulation(&spec, registry)?;
    let (space, _) = prepare(&sim, registry).map_err(|e| ReplayError::Setup(Box::new(e)))?;
    if eval.genome.len() != space.genes.len() {
        return Err(ReplayError::Genes {
            number,
            stored: eval.genome.len(),
            configured: space.genes.len(),
        });
    }
    let evaluator = stored_evaluator(&spec, &sim, &space, registry)?;
    let mut label = format!(
        "{} run {run}, evaluation {number} (stored score {:.4})",
        store.describe(),
        eval.score
    );
    if spec.program != program_version() {
        label.push_str(&format!(
            "; started by {}, this is {}: the trajectory may differ",
            spec.program,
            program_version()
        ));
    }
    let engine = match &evaluator.cross {
        Some(c) => {
            let scores: Vec<String> = eval
                .engines
                .iter()
                .map(|(k, s)| format!("{k} {s:.4}"))
                .collect();
            label.push_str(&format!(
                "; scored on {}: {}",
                c.describe(),
                scores.join(", ")
            ));
            c.engines.first().copied().unwrap_or_else(|| sim.engine())
        }
        None => sim.engine(),
    };
    let (world, seed, noise, which) = replay_world(
        &evaluator,
        &sim,
        &spec,
        &eval.genome,
        run,
        episode,
        registry,
    )?;
    label.push_str(&which);
    Ok(Replay {
        sim: world,
        space,
        genome: eval.genome,
        seed,
        noise,
        duration: spec.info.duration,
        stored_score: eval.score,
        label,
        config: spec.info.config.clone(),
        nominal: sim,
        stored_engines: eval.engines,
        engine,
        evaluator,
    })
}

/// The world a replay runs, its seed and noise: the stored configuration, a co-design
/// candidate's own body, or with robust fitness the randomized episode asked for (then
/// named in the text returned, for the replay's label).
fn replay_world(
    evaluator: &Evaluator,
    sim: &Simulation,
    spec: &RunSpec,
    genome: &Genome,
    run: i64,
    episode: Option<u32>,
    registry: &ModuleRegistry,
) -> Result<(Simulation, u64, SensorNoise, String), ReplayError> {
    Ok(match (&evaluator.robust, episode) {
        (None, Some(k)) => {
            return Err(ReplayError::NoEpisodes { run, episode: k });
        }
        // A co-design candidate's world is its own body, built from the stored files.
        (None, None) => match &evaluator.design {
            Some(d) => (
                d.simulation(genome, registry)
                    .map_err(UnevaluableRun::Config)?,
                spec.info.seed,
                SensorNoise::default(),
                String::new(),
            ),
            None => (
                sim.clone(),
                spec.info.seed,
                SensorNoise::default(),
                String::new(),
            ),
        },
        (Some(r), k) => {
            let (mut world, seed, noise) = episode_of(r, k.unwrap_or(0))?;
            // A co-design body draws the episode with its own links and joints.
            if let Some(d) = &evaluator.design {
                let body = d
                    .simulation(genome, registry)
                    .map_err(UnevaluableRun::Config)?;
                if let Some(e) = r.of_body(k.unwrap_or(0) as usize, &body) {
                    world = e.sim;
                }
            }
            let which = format!(", episode {} of {}", k.unwrap_or(0), r.episodes.len());
            (world, seed, noise, which)
        }
    })
}

/// Episode `k`'s world, seed and noise.
fn episode_of(r: &RobustEpisodes, k: u32) -> Result<(Simulation, u64, SensorNoise), ReplayError> {
    let e = r.episodes.get(k as usize).ok_or(ReplayError::Episode {
        episode: k,
        count: r.episodes.len(),
    })?;
    Ok((e.sim.clone(), e.seed, e.noise))
}

impl Replay {
    /// The same evaluation replayed on `engine`: its stored score becomes the one stored
    /// for that engine (a run with `<engines>`), and the label says which engine runs.
    pub fn on_engine(mut self, engine: EngineKind) -> Replay {
        if let Some((_, s)) = self.stored_engines.iter().find(|(k, _)| *k == engine) {
            self.stored_score = *s;
        }
        self.engine = engine;
        self.label.push_str(&format!(", replayed on {engine}"));
        self
    }

    /// How the replayed world is built (`record`: with trajectories, for the viewer).
    pub fn build_options(&self, record: bool) -> BuildOptions {
        BuildOptions {
            robots: 1,
            seed: self.seed,
            record,
            noise: self.noise,
            engine: self.engine.into(),
        }
    }

    /// Puts the candidate's values into robot 0's kernel of a world built with
    /// [`Replay::build_options`].
    pub fn apply(&self, simulator: &mut Simulator) -> Result<(), SimError> {
        // A co-design candidate's values are in its own actuation file.
        if self.evaluator.design.is_some() {
            return Ok(());
        }
        let kernel = simulator.kernel_mut(0)?;
        self.space
            .apply(&self.genome, kernel)
            .map_err(SimError::from)
    }

    /// How the replayed episode is scored.
    pub fn fitness(&self) -> Fitness {
        self.evaluator.fitness
    }

    /// The replayed episode's score, run headless by the optimizers' own evaluator.
    pub fn score(&self) -> Result<f64, ReplayError> {
        let scores = self.evaluator.run_world(
            &self.sim,
            EpisodeWorld {
                seed: self.seed,
                noise: self.noise,
                engine: Some(self.engine),
            },
            std::slice::from_ref(&self.genome),
        )?;
        scores.first().copied().ok_or(ReplayError::NothingScored)
    }

    /// Replays the episode headless in the world [`Replay::build_options`] builds (the one
    /// the windows and videos show), recording every data handler into the B.8 data file
    /// `file` every `accuracy` steps of the simulation file; returns the rounds written.
    pub fn record_data(
        &self,
        file: &std::path::Path,
        registry: &ModuleRegistry,
    ) -> Result<u64, ReplayError> {
        let mut simulator =
            Simulator::with_registry(&self.sim, &self.build_options(false), registry)?;
        self.apply(&mut simulator)?;
        let every = self.sim.files.simulation.properties.accuracy.max(1);
        simulator.record_to(
            file,
            crate::sim::datalog::DataSettings {
                every,
                ..Default::default()
            },
        )?;
        simulator.run_for(self.duration);
        Ok(simulator.finish_data()?)
    }

    /// Replays the episode headless in the world [`Replay::build_options`] builds, as the
    /// optimization ran it (one episode: a robot that leaves the world ends it), recorded
    /// as a pose stream for the 3D viewer at `fps` frames per simulated second.
    pub fn pose_stream(
        &self,
        registry: &ModuleRegistry,
        fps: f64,
    ) -> Result<crate::playback::PoseStream, ReplayError> {
        let mut simulator =
            Simulator::with_registry(&self.sim, &self.build_options(false), registry)?;
        self.apply(&mut simulator)?;
        let settings = EpisodeSettings::new(&simulator, self.duration, self.fitness());
        let mut episode = Episode::begin(&simulator, settings)?;
        let recording = crate::playback::Recording {
            fps,
            label: self.label.clone(),
        };
        let recorded = crate::playback::record_episode(
            &self.sim,
            &mut simulator,
            &mut episode,
            &recording,
            None,
        )?;
        Ok(recorded.stream)
    }
}

/// Which evaluation of a run to replay.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// The run's best (the first of equal scores).
    Best,
    /// Evaluation number N.
    Number(u64),
}

impl Which {
    /// `best` or a number.
    pub fn parse(text: &str) -> Result<Which, ReplayError> {
        match text.trim() {
            "best" => Ok(Which::Best),
            t => t
                .parse()
                .map(Which::Number)
                .map_err(|_| ReplayError::Which(t.to_string())),
        }
    }

    /// The evaluation's number in `run`.
    pub fn number(self, store: &mut Store, run: i64) -> Result<u64, ReplayError> {
        match self {
            Which::Number(n) => Ok(n),
            Which::Best => store
                .evaluations(run)?
                .into_iter()
                .filter(|e| !e.score.is_nan())
                .fold(None, |best: Option<(u64, f64)>, e| match best {
                    Some((_, s)) if s >= e.score => best,
                    _ => Some((e.number, e.score)),
                })
                .map(|(n, _)| n)
                .ok_or_else(|| ReplayError::NoEvaluation {
                    store: store.describe(),
                    run,
                    number: None,
                }),
        }
    }
}

/// Opens the store at `location` and loads `which` evaluation of `run` (episode `episode`
/// of a robust run) for replay.
pub fn replay_from(
    location: &str,
    run: i64,
    which: Which,
    episode: Option<u32>,
    registry: &ModuleRegistry,
) -> Result<Replay, ReplayError> {
    let location =
        crate::optimize::store::StoreLocation::parse(location).map_err(ReplayError::Location)?;
    let mut store = Store::open_existing(&location)?;
    let number = which.number(&mut store, run)?;
    load_replay(&mut store, run, number, episode, registry)
}

/// A stored candidate re-evaluated on fresh randomized episodes.
#[derive(Debug, Clone, PartialEq)]
pub struct RandomizedCheck {
    /// What was checked.
    pub label: String,
    /// Its score in the nominal world (the stored configuration, the run's seed).
    pub nominal: f64,
    /// Its score in each randomized episode.
    pub scores: Vec<f64>,
    /// The ranges the episodes were drawn from.
    pub ranges: Robustness,
}

impl RandomizedCheck {
    /// The mean of the episodes' scores.
    pub fn mean(&self) -> f64 {
        combine(&self.scores, None)
    }

    /// The lower quartile of the episodes' scores.
    pub fn lower_quartile(&self) -> f64 {
        combine(&self.scores, Some(0.25))
    }

    /// The share of the nominal score the randomized mean keeps (1: nothing lost).
    pub fn kept(&self) -> f64 {
        self.mean() / self.nominal
    }
}

/// Episodes drawn afresh for a robustness check: how many, the seed they are drawn from
/// (not the run's own), and where (the run's own world, or a suite task's course).
#[derive(Debug, Clone, PartialEq)]
pub struct FreshEpisodes {
    /// How many.
    pub count: u32,
    /// Their seed.
    pub seed: u64,
    /// A suite task's course instead of the world of the run's simulation file.
    pub course: Option<OnCourse>,
}

/// One course of a suite task, by the task's name and the course's terrain seed.
#[derive(Debug, Clone, PartialEq)]
pub struct OnCourse {
    /// The suite file.
    pub suite: std::path::PathBuf,
    /// The task's name (`steps-medium`).
    pub task: String,
    /// The course's terrain seed (a test seed, for a held-out world).
    pub seed: u64,
}

impl OnCourse {
    /// `sim` on this course ([`Simulation::on_course`]: the task's world and duration).
    pub fn place(&self, sim: &Simulation) -> Result<Simulation, ReplayError> {
        let boxed = |e| ReplayError::Course(Box::new(e));
        let suite = crate::config::suite::load_suite(&crate::config::FsSource, &self.suite)
            .map_err(boxed)?;
        let Some(task) = suite.task(&self.task) else {
            let known: Vec<&str> = suite.tasks.iter().map(|t| t.name.as_str()).collect();
            return Err(ReplayError::UnknownTask {
                suite: self.suite.display().to_string(),
                task: self.task.clone(),
                known: known.join(", "),
            });
        };
        sim.on_course(task, self.seed, &self.suite).map_err(boxed)
    }
}

/// Re-evaluates `which` evaluation of `run` in the store at `location` on `fresh`
/// episodes drawn from `ranges` (fresh seeds, not the run's own episodes):
/// how much of its score a gait keeps when the world is not the one it was tuned in.
pub fn randomized_check(
    location: &str,
    run: i64,
    which: Which,
    ranges: &Robustness,
    fresh: FreshEpisodes,
    engine: Option<EngineKind>,
    registry: &ModuleRegistry,
) -> Result<RandomizedCheck, ReplayError> {
    let location =
        crate::optimize::store::StoreLocation::parse(location).map_err(ReplayError::Location)?;
    let mut store = Store::open_existing(&location)?;
    let number = which.number(&mut store, run)?;
    let replay = load_replay(&mut store, run, number, None, registry)?;
    let engine = engine.unwrap_or(replay.engine);
    let mut nominal_sim = replay.nominal.clone().with_engine(Some(engine));
    if let Some(course) = &fresh.course {
        nominal_sim = course.place(&nominal_sim)?;
    }
    let nominal_sim = &nominal_sim;
    let e = &replay.evaluator;
    let genome = std::slice::from_ref(&replay.genome);
    let world = EpisodeWorld::nominal(e.seed, None);
    let episode = |sim, world| e.run_world(sim, world, genome);
    let nominal = episode(nominal_sim, world)?[0];
    let mut ranges = *ranges;
    ranges.episodes = fresh.count.max(1);
    let drawn = RobustEpisodes::new(nominal_sim, &ranges, fresh.seed);
    let mut scores = Vec::with_capacity(drawn.episodes.len());
    for ep in &drawn.episodes {
        let world = EpisodeWorld {
            seed: ep.seed,
            noise: ep.noise,
            engine: None,
        };
        scores.extend(episode(&ep.sim, world)?);
    }
    Ok(RandomizedCheck {
        label: format!(
            "{} run {run}, evaluation {number}, on {}",
            store.describe(),
            nominal_sim.engine()
        ),
        nominal,
        scores,
        ranges,
    })
}

//! Evaluating candidates: each is a fresh, seeded headless episode of the simulation.
//! Candidates are batched, up to `batch` robots sharing one world (they do not touch each
//! other), and the batches are spread over `workers` threads. A physics blow-up (a
//! non-finite or far-flung centre of mass) scores the candidate `-inf` and the run goes on.
//! Each episode is one of the episode runner's ([`crate::sim::episode`]): a robot that
//! leaves the world (falls off the floor's end) is scored as it was when it left, as the
//! Python environment ends its episode there, and a raised [`Evaluator::stop`] abandons the
//! episodes in flight ([`EvalError::Stopped`]).
//! With robust fitness ([`RobustEpisodes`]) a candidate is scored over its K randomized
//! episodes, each a world of its own, one candidate per job. With cross-engine scores
//! (`<engines>` in the optimizer file) every candidate runs on each engine, and its score
//! combines theirs ([`CandidateScore`]).

use std::sync::Mutex;
use std::sync::mpsc::channel;
use std::time::Instant;

use crate::config::Simulation;
use crate::config::cross_engine::CrossEngine;
use crate::config::fitness::Fitness;
use crate::config::optimizer::Quantity;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::optimize::behaviour::{Probe, measured_quantities};
use crate::optimize::design::{Candidate, Design, Rejection};
use crate::optimize::robust::RobustEpisodes;
pub use crate::optimize::scores::CandidateScore;
use crate::optimize::space::{Genome, SearchSpace};
use crate::signal::StopFlag;
use crate::sim::randomize::SensorNoise;
use crate::sim::{BuildOptions, Episode, EpisodeEnd, EpisodeSettings, Simulator};

/// Why an episode could not be run or scored.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    /// The world does not build, or a robot of it cannot be read.
    #[error("{0}")]
    Sim(#[from] crate::sim::SimError),
    /// The candidate's values do not fit the kernel.
    #[error("{0}")]
    Kernel(#[from] crate::control::kernel::KernelError),
    /// A co-design candidate's generated robot or actuation does not load.
    #[error("the candidate's body does not load: {0}")]
    Design(Box<crate::config::ConfigError>),
    /// A world built for one robot gave no outcome.
    #[error("the episode gave no outcome")]
    Empty,
    /// A suite run's course does not build from its stored files.
    #[error("the course does not build: {0}")]
    Course(Box<crate::config::ConfigError>),
    /// A suite run's evaluation names no episode of its suite.
    #[error("the evaluation names no episode of the suite (genome {0:?})")]
    NoSuchEpisode(crate::optimize::space::Genome),
    /// The run was asked to stop (Ctrl-C, SIGTERM, a window's Stop) and the episode was
    /// abandoned; it is deterministic, so a resumed run runs it again to the same score.
    #[error("stopped before the episode ended")]
    Stopped,
}

/// How an episode's world is drawn: its seed, the noise on what its modules read, and the
/// engine (`None`: the simulation's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EpisodeWorld {
    /// The world's seed.
    pub seed: u64,
    /// Noise on what modules read (randomized episodes; none in the nominal world).
    pub noise: SensorNoise,
    /// The engine, when not the simulation's.
    pub engine: Option<EngineKind>,
}

impl EpisodeWorld {
    /// The nominal world of `seed` (no noise) on `engine`.
    pub fn nominal(seed: u64, engine: Option<EngineKind>) -> EpisodeWorld {
        EpisodeWorld {
            seed,
            noise: SensorNoise::default(),
            engine,
        }
    }
}

/// Runs candidates.
#[derive(Clone)]
pub struct Evaluator {
    /// The simulation every episode runs.
    pub sim: Simulation,
    /// The module types episodes may create (standard library, loaded plugins).
    pub registry: ModuleRegistry,
    /// How genomes map to module parameters.
    pub space: SearchSpace,
    /// How episodes are scored.
    pub fitness: Fitness,
    /// Simulated seconds per episode.
    pub duration: f64,
    /// Seed of every episode.
    pub seed: u64,
    /// Robots per world.
    pub batch: usize,
    /// Worker threads.
    pub workers: usize,
    /// The randomized episodes of robust fitness, if the optimizer file asks for them.
    pub robust: Option<RobustEpisodes>,
    /// The engines every candidate runs on, if the optimizer file asks for several.
    pub cross: Option<CrossEngine>,
    /// A co-design run's bodies: each candidate builds its own robot and actuation.
    pub design: Option<std::sync::Arc<crate::optimize::design::Design>>,
    /// The quantities measured in each episode (MAP-Elites' measured descriptors).
    pub measures: Vec<Quantity>,
    /// Raised to abandon the episodes in flight ([`EvalError::Stopped`]).
    pub stop: StopFlag,
}

impl CandidateScore {
    /// An outcome on the simulation's one engine.
    fn of(outcome: Outcome) -> CandidateScore {
        CandidateScore {
            score: outcome.score,
            engines: Vec::new(),
            rejected: outcome.failed,
            measures: outcome.measures,
        }
    }

    /// Outcomes on several engines: their scores combined, the first engine's quantities.
    fn combined(cross: &CrossEngine, row: Vec<(EngineKind, Outcome)>) -> CandidateScore {
        let scores: Vec<f64> = row.iter().map(|(_, o)| o.score).collect();
        let failed = row.iter().find_map(|(_, o)| o.failed.clone());
        CandidateScore {
            score: if failed.is_some() {
                f64::NEG_INFINITY
            } else {
                cross.combine.apply(&scores)
            },
            measures: row
                .first()
                .map(|(_, o)| o.measures.clone())
                .unwrap_or_default(),
            engines: row.into_iter().map(|(k, o)| (k, o.score)).collect(),
            rejected: failed,
        }
    }
}

/// The engines `sim`'s candidates are scored on: the optimizer file's `<engines>`, else the
/// simulation's own.
pub fn scoring_engines(sim: &Simulation) -> Vec<EngineKind> {
    match cross_engine(sim) {
        Some(c) => c.engines,
        None => vec![sim.engine()],
    }
}

/// The optimizer file's `<engines>`/`<combine>`, if it has them.
fn cross_engine(sim: &Simulation) -> Option<CrossEngine> {
    sim.optimizer
        .as_ref()
        .and_then(|m| m.spec.cross_engine.clone())
}

impl Evaluator {
    /// An evaluator of `sim`'s candidates (one robot per world, one thread), with the
    /// randomized episodes its optimizer file asks for, drawn from `seed`.
    pub fn new(
        sim: &Simulation,
        registry: &ModuleRegistry,
        space: &SearchSpace,
        fitness: Fitness,
        duration: f64,
        seed: u64,
    ) -> Evaluator {
        Evaluator {
            robust: RobustEpisodes::of(sim, seed),
            cross: cross_engine(sim),
            sim: sim.clone(),
            registry: registry.clone(),
            space: space.clone(),
            fitness,
            duration,
            seed,
            batch: 1,
            workers: 1,
            measures: measured_quantities(sim),
            stop: StopFlag::default(),
            design: crate::optimize::design::Design::of(
                sim,
                std::sync::Arc::new(crate::config::source::FsSource),
            )
            .map(std::sync::Arc::new),
        }
    }

    /// This evaluator with its co-design bodies built over `files` (a stored run's files)
    /// instead of the files on disk.
    pub fn with_files(
        mut self,
        files: std::sync::Arc<dyn crate::config::source::FileSource + Send + Sync>,
    ) -> Evaluator {
        self.design =
            crate::optimize::design::Design::of(&self.sim, files).map(std::sync::Arc::new);
        self
    }

    /// Robots per world this evaluator uses (1 with robust fitness: each episode's physics
    /// is its own; at most what every engine scored on holds).
    pub fn robots_per_world(&self) -> usize {
        if self.robust.is_some() || self.design.is_some() {
            return 1;
        }
        let most = scoring_engines(&self.sim)
            .into_iter()
            .map(crate::sim::engine::max_robots)
            .min()
            .unwrap_or(1);
        self.batch.clamp(1, most.max(1))
    }

    /// Scores of `genomes`, in order.
    pub fn evaluate(&self, genomes: &[Genome]) -> Result<Vec<f64>, EvalError> {
        self.evaluate_with(genomes, |_, _, _| {})
            .map(|v| v.into_iter().map(|c| c.score).collect())
    }

    /// Scores of `genomes`, in order; `on_batch(first, scores, wall_seconds)` is called on
    /// this thread as each batch finishes (to store results before the round ends).
    pub fn evaluate_with(
        &self,
        genomes: &[Genome],
        mut on_batch: impl FnMut(usize, &[CandidateScore], f64),
    ) -> Result<Vec<CandidateScore>, EvalError> {
        let batch = self.robots_per_world();
        let chunks: Vec<(usize, &[Genome])> = genomes
            .chunks(batch)
            .enumerate()
            .map(|(i, c)| (i * batch, c))
            .collect();
        let next = Mutex::new(0usize);
        let mut results = vec![CandidateScore::single(f64::NAN); genomes.len()];
        let mut error = None;
        let (tx, rx) = channel::<(usize, Result<Vec<CandidateScore>, EvalError>, f64)>();
        std::thread::scope(|s| {
            for _ in 0..self.workers.clamp(1, chunks.len().max(1)) {
                let tx = tx.clone();
                let (next, chunks) = (&next, &chunks);
                s.spawn(move || {
                    loop {
                        let i = {
                            let Ok(mut n) = next.lock() else { return };
                            let i = *n;
                            *n += 1;
                            i
                        };
                        let Some((start, chunk)) = chunks.get(i) else {
                            return;
                        };
                        let t = Instant::now();
                        let r = self.run_batch_scored(chunk);
                        let failed = r.is_err();
                        if tx.send((*start, r, t.elapsed().as_secs_f64())).is_err() || failed {
                            return;
                        }
                    }
                });
            }
            drop(tx);
            for (start, r, wall) in rx {
                match r {
                    Ok(scores) => {
                        results[start..start + scores.len()].clone_from_slice(&scores);
                        on_batch(start, &scores, wall);
                    }
                    Err(e) => {
                        error.get_or_insert(e);
                    }
                }
            }
        });
        match error {
            Some(e) => Err(e),
            None => Ok(results),
        }
    }

    /// The scores of `genomes` (combined over the engines with cross-engine scores).
    pub fn run_batch(&self, genomes: &[Genome]) -> Result<Vec<f64>, EvalError> {
        self.run_batch_scored(genomes)
            .map(|v| v.into_iter().map(|c| c.score).collect())
    }

    /// The scores of `genomes`, each with its engines' scores when it runs on several.
    pub fn run_batch_scored(&self, genomes: &[Genome]) -> Result<Vec<CandidateScore>, EvalError> {
        if let Some(design) = &self.design {
            return genomes.iter().map(|g| self.run_design(design, g)).collect();
        }
        let Some(cross) = &self.cross else {
            let outcomes = self.run_batch_on(None, genomes)?;
            return Ok(outcomes.into_iter().map(CandidateScore::of).collect());
        };
        let mut per_engine = Vec::with_capacity(cross.engines.len());
        for &kind in &cross.engines {
            per_engine.push((kind, self.run_batch_on(Some(kind), genomes)?));
        }
        let mut scores = Vec::with_capacity(genomes.len());
        for i in 0..genomes.len() {
            let row: Vec<(EngineKind, Outcome)> =
                per_engine.iter().map(|(k, o)| (*k, o[i].clone())).collect();
            scores.push(CandidateScore::combined(cross, row));
        }
        Ok(scores)
    }

    /// A co-design candidate's score: its body built and run in a world of its own (on
    /// each engine with cross-engine scores), or rejected unrun.
    fn run_design(&self, design: &Design, genome: &Genome) -> Result<CandidateScore, EvalError> {
        let sim = match design.candidate(genome, &self.registry) {
            Ok(Candidate::Run(sim)) => sim,
            Ok(Candidate::Rejected(why)) => return Ok(CandidateScore::rejected(why)),
            Err(e) => return Err(EvalError::Design(Box::new(e))),
        };
        let Some(cross) = &self.cross else {
            return Ok(CandidateScore::of(self.design_on(&sim, genome, None)?));
        };
        let mut row = Vec::with_capacity(cross.engines.len());
        for &kind in &cross.engines {
            row.push((kind, self.design_on(&sim, genome, Some(kind))?));
        }
        Ok(CandidateScore::combined(cross, row))
    }

    /// A co-design body's outcome on `engine` (`None`: the simulation's): its episode, or
    /// with robust fitness its randomized episodes combined.
    fn design_on(
        &self,
        body: &Simulation,
        genome: &Genome,
        engine: Option<EngineKind>,
    ) -> Result<Outcome, EvalError> {
        let one = std::slice::from_ref(genome);
        let Some(robust) = &self.robust else {
            let world = EpisodeWorld::nominal(self.seed, engine);
            return first(self.run_world_measured(body, world, one)?);
        };
        let mut episodes = Vec::with_capacity(robust.episodes.len());
        for k in 0..robust.episodes.len() {
            if let Some(e) = robust.of_body(k, body) {
                let world = EpisodeWorld {
                    seed: e.seed,
                    noise: e.noise,
                    engine,
                };
                episodes.extend(self.run_world_measured(&e.sim, world, one)?);
            }
        }
        Ok(Outcome::over_episodes(robust, &episodes))
    }

    /// The outcomes of `genomes` on `engine` (`None`: the simulation's): one world with a
    /// robot per genome, or with robust fitness each genome's randomized episodes,
    /// combined.
    fn run_batch_on(
        &self,
        engine: Option<EngineKind>,
        genomes: &[Genome],
    ) -> Result<Vec<Outcome>, EvalError> {
        let Some(robust) = &self.robust else {
            let world = EpisodeWorld::nominal(self.seed, engine);
            return self.run_world_measured(&self.sim, world, genomes);
        };
        let mut outcomes = Vec::with_capacity(genomes.len());
        let mut episodes = Vec::with_capacity(robust.episodes.len());
        for g in genomes {
            episodes.clear();
            for e in &robust.episodes {
                let world = EpisodeWorld {
                    seed: e.seed,
                    noise: e.noise,
                    engine,
                };
                episodes.extend(self.run_world_measured(&e.sim, world, std::slice::from_ref(g))?);
            }
            outcomes.push(Outcome::over_episodes(robust, &episodes));
        }
        Ok(outcomes)
    }

    /// The scores of `genomes` as robots of one world of `sim`, built with `seed` and
    /// `noise` on `engine` (`None`: the simulation's).
    pub fn run_world(
        &self,
        sim: &Simulation,
        world: EpisodeWorld,
        genomes: &[Genome],
    ) -> Result<Vec<f64>, EvalError> {
        let outcomes = self.run_world_measured(sim, world, genomes)?;
        Ok(outcomes.into_iter().map(|o| o.score).collect())
    }

    /// [`Evaluator::run_world`], each robot's measured quantities ([`Evaluator::measures`])
    /// with its score.
    pub fn run_world_measured(
        &self,
        sim: &Simulation,
        world: EpisodeWorld,
        genomes: &[Genome],
    ) -> Result<Vec<Outcome>, EvalError> {
        let opts = BuildOptions {
            robots: genomes.len(),
            seed: world.seed,
            record: false,
            engine: world.engine.into(),
            noise: world.noise,
        };
        let mut s = Simulator::with_registry(sim, &opts, &self.registry)?;
        // A co-design candidate's values are in its generated actuation file.
        if self.design.is_none() {
            for (i, g) in genomes.iter().enumerate() {
                let kernel = s.kernel_mut(i)?;
                self.space.apply(g, kernel)?;
            }
        }
        let settings = EpisodeSettings::new(&s, self.duration, self.fitness);
        let mut episode = Episode::begin(&s, settings)?;
        let mut probes = Vec::new();
        if !self.measures.is_empty() {
            let samples = settings
                .steps
                .unwrap_or(0)
                .div_ceil(settings.check_every.max(1)) as usize;
            for i in 0..genomes.len() {
                probes.push(Probe::start(&s, i, samples)?);
            }
        }
        // A robot that leaves the world is scored as it was then: one falling off the
        // floor's end does not go on scoring as it falls.
        let end = episode.run(&mut s, Some(&self.stop), |s| {
            probes.iter_mut().try_for_each(|p| p.sample(s))
        })?;
        if end == EpisodeEnd::Stopped {
            return Err(EvalError::Stopped);
        }
        let mut outcomes = Vec::with_capacity(genomes.len());
        for i in 0..genomes.len() {
            let failed =
                s.kernel(i)?
                    .failures()
                    .next()
                    .map(|(module, cause)| Rejection::ModuleFailed {
                        module: module.to_string(),
                        cause: cause.to_string(),
                    });
            outcomes.push(Outcome {
                score: if failed.is_some() {
                    f64::NEG_INFINITY
                } else {
                    episode.score(&s, i)?
                },
                failed,
                measures: probes
                    .get(i)
                    .map(|p| p.finish(&self.measures))
                    .unwrap_or_default(),
            });
        }
        Ok(outcomes)
    }
}

/// One robot's episode: its score and the quantities measured (empty unless the
/// evaluator measures any).
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The score.
    pub score: f64,
    /// The measured quantities, in [`Evaluator::measures`]' order.
    pub measures: Vec<f64>,
    /// A module that stopped during the episode: the score is then `-inf`.
    pub failed: Option<Rejection>,
}

impl Outcome {
    /// A candidate's outcome over its randomized episodes: their scores combined, their
    /// quantities averaged.
    fn over_episodes(robust: &RobustEpisodes, episodes: &[Outcome]) -> Outcome {
        let scores: Vec<f64> = episodes.iter().map(|o| o.score).collect();
        let n = episodes.first().map_or(0, |o| o.measures.len());
        let measures = (0..n)
            .map(|k| episodes.iter().map(|o| o.measures[k]).sum::<f64>() / episodes.len() as f64)
            .collect();
        let failed = episodes.iter().find_map(|o| o.failed.clone());
        Outcome {
            score: if failed.is_some() {
                f64::NEG_INFINITY
            } else {
                robust.combine(&scores)
            },
            measures,
            failed,
        }
    }
}

/// The one outcome of a one-robot world.
fn first(outcomes: Vec<Outcome>) -> Result<Outcome, EvalError> {
    outcomes.into_iter().next().ok_or(EvalError::Empty)
}

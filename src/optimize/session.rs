//! One optimization, prepared once: [`Session::prepare`] reads the search space and the
//! start candidate from the simulation and checks the run's choices before anything is
//! stored; [`Session::run`] drives the optimizer named by the optimizer file, its rounds
//! scored by the run's [`crate::optimize::scorer::Scorer`], every evaluation reported to a
//! callback (progress, tables) as it comes. The command line and the control window both
//! drive a session.

use crate::config::Simulation;
use crate::config::optimizer::Algorithm;
use crate::config::resolve::OptimizerModel;
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::optimize::Optimizer;
use crate::optimize::cmaes::CmaOptimizer;
use crate::optimize::deluge::GreatDeluge;
use crate::optimize::design::DesignSpace;
use crate::optimize::error::{BadChoice, OptimizeError};
use crate::optimize::es::EsOptimizer;
use crate::optimize::evaluate::{EvalError, Evaluator};
use crate::optimize::ga::GeneticAlgorithm;
use crate::optimize::local::LocalScorer;
use crate::optimize::map_elites::{MapElites, map_axes};
use crate::optimize::prepare::prepare;
use crate::optimize::scorer::{Recording, Round, Scorer};
use crate::optimize::settings::RunSettings;
use crate::optimize::shared::queue::QueueScorer;
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::Store;
use crate::rng::SimRng;

/// Salt of the stream a random start (`<randomStart>`) is drawn from.
const RANDOM_START_STREAM: u64 = 0x7374_6172_7420_7074;

/// One finished evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// 0-based evaluation number.
    pub number: u64,
    /// Round (GA generation / great-deluge batch) it belonged to.
    pub round: u64,
    /// The candidate.
    pub genome: Genome,
    /// Its parameter values (the genome decoded).
    pub values: Vec<f64>,
    /// Its score.
    pub score: f64,
    /// Best score so far, this one included.
    pub best: f64,
}

/// What a run found.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome {
    /// The best candidate found.
    pub best: Genome,
    /// Its score.
    pub best_score: f64,
    /// The start candidate: the configured one, or with `<randomStart>` one drawn from the
    /// seed.
    pub start: Genome,
    /// Whether the start was drawn from the seed (`<randomStart>`).
    pub start_drawn: bool,
    /// The start candidate's score (when it was evaluated first).
    pub start_score: Option<f64>,
    /// Evaluations done (simulated or from the store).
    pub evaluations: u64,
    /// Evaluations simulated in this call (the rest came from the store).
    pub simulated: u64,
    /// How candidates were spread over worlds, and why.
    pub batching: crate::optimize::scorer::Batching,
    /// Rounds (GA generations, great-deluge batches).
    pub rounds: u64,
    /// The best candidate's score on each engine (runs with `<engines>`; else empty).
    pub best_engines: Vec<(EngineKind, f64)>,
    /// The run was stopped before its optimizer finished (a signal, the window's Stop):
    /// it stays unfinished in its store, and `--resume` continues it.
    pub stopped: bool,
    /// The run ended because its best score reached the settings' `until`.
    pub reached: bool,
}

/// An optimization of a simulation, prepared and checked.
pub struct Session {
    sim: Simulation,
    model: OptimizerModel,
    settings: RunSettings,
    space: SearchSpace,
    start: Genome,
    start_drawn: bool,
}

impl Session {
    /// Prepares the optimization of `sim` with `settings` (its search space from the
    /// optimizer file and the modules `registry` makes, the start candidate) and checks
    /// the choices for a run recorded into a `shared` store or not.
    pub fn prepare(
        sim: &Simulation,
        settings: &RunSettings,
        registry: &ModuleRegistry,
        shared: bool,
    ) -> Result<Session, OptimizeError> {
        let (space, configured) = prepare(sim, registry)?;
        let Some(model) = sim.optimizer.clone() else {
            return Err(OptimizeError::NoOptimizer {
                file: sim.file.clone(),
                mode: sim.files.simulation.properties.mode.name().to_string(),
            });
        };
        check_workers(settings, shared)?;
        let start = start_candidate(model.spec.random_start, &space, configured, settings.seed);
        Ok(Session {
            sim: sim.clone(),
            start_drawn: model.spec.random_start,
            model,
            settings: settings.clone(),
            space,
            start,
        })
    }

    /// The same session starting from `start` (a candidate of its search space: a
    /// curriculum's previous stage's best) instead of the configured or drawn one.
    pub fn starting_from(self, start: Genome) -> Result<Session, OptimizeError> {
        if !self.space.contains(&start) {
            return Err(OptimizeError::StartOutsideSpace);
        }
        Ok(Session {
            start,
            start_drawn: false,
            ..self
        })
    }

    /// The search space.
    pub fn space(&self) -> &SearchSpace {
        &self.space
    }

    /// The run's settings.
    pub fn settings(&self) -> &RunSettings {
        &self.settings
    }

    /// The evaluator of the run's episodes, stopped by the run's stop flag.
    fn evaluator(&self, registry: &ModuleRegistry) -> Evaluator {
        let settings = &self.settings;
        Evaluator {
            batch: settings.batch,
            stop: settings.stop.clone(),
            ..Evaluator::new(
                &self.sim,
                registry,
                &self.space,
                settings.fitness,
                settings.duration,
                settings.seed,
            )
        }
    }

    /// Runs the optimization, calling `on_eval` for every evaluation in order. With a
    /// recording, every evaluation is stored as it is scored, and stored ones (same number
    /// and genome) are reused instead of simulated again. A raised stop flag abandons the
    /// round in flight (its finished batches are stored) and ends the run unfinished.
    pub fn run(
        &self,
        registry: &ModuleRegistry,
        recording: Option<Recording<'_>>,
        mut on_eval: impl FnMut(&Evaluation),
    ) -> Result<RunOutcome, OptimizeError> {
        let settings = &self.settings;
        let design = DesignSpace::from_model(&self.model);
        let mut optimizer = build_optimizer(
            &self.model.spec.algorithm,
            &self.space,
            design,
            &self.start,
            settings,
        )?;
        let mut scorer = scorer_for(recording, self.evaluator(registry), settings, registry)?;
        let (mut n, mut round, mut best) = (0u64, 0u64, f64::NEG_INFINITY);
        let (mut start_score, mut best_engines, mut reached) = (None, Vec::new(), false);
        while !optimizer.finished() && !settings.stop.is_set() && !reached {
            let candidates = optimizer.ask();
            if candidates.is_empty() {
                break;
            }
            let scored = match scorer.score(&Round {
                first: n,
                number: round,
                candidates: &candidates,
            }) {
                // Stopped mid-round: the episodes in flight were abandoned (the batches
                // that finished are stored); the round is not told, `--resume` runs it.
                Err(OptimizeError::Eval(EvalError::Stopped)) => break,
                scored => scored?,
            };
            for (g, s) in candidates.iter().zip(&scored) {
                start_score = start_score.or(Some(s.score));
                if s.score > best {
                    best_engines.clone_from(&s.engines);
                }
                best = best.max(s.score);
                on_eval(&Evaluation {
                    number: n,
                    round,
                    genome: g.clone(),
                    values: self.space.decode(g),
                    score: s.score,
                    best,
                });
                n += 1;
            }
            let scores: Vec<f64> = scored.iter().map(|s| s.score).collect();
            let measures: Vec<Vec<f64>> = scored.into_iter().map(|s| s.measures).collect();
            optimizer.tell_measured(&scores, &measures);
            round += 1;
            reached = settings.until.is_some_and(|until| best >= until);
        }
        let stopped = settings.stop.is_set() && !optimizer.finished() && !reached;
        let summary = scorer.finish(!stopped)?;
        let (g, s) = optimizer
            .best()
            .map(|(g, s)| (g.clone(), s))
            .ok_or(if stopped {
                OptimizeError::StoppedEarly
            } else {
                OptimizeError::NothingEvaluated
            })?;
        Ok(RunOutcome {
            best: g,
            best_score: s,
            start: self.start.clone(),
            start_drawn: self.start_drawn,
            start_score,
            evaluations: n,
            simulated: summary.simulated,
            batching: summary.batching,
            rounds: round,
            best_engines,
            stopped,
            reached,
        })
    }
}

/// The search's start: the configured candidate, or with `random` one drawn from `seed`.
fn start_candidate(random: bool, space: &SearchSpace, configured: Genome, seed: u64) -> Genome {
    if random {
        space.random(&mut SimRng::new(seed ^ RANDOM_START_STREAM))
    } else {
        configured
    }
}

/// Local worker threads: at least one, unless a shared store's workers evaluate; one robot
/// per world with a shared store (scores must not depend on who claims what).
pub fn check_workers(settings: &RunSettings, shared: bool) -> Result<(), BadChoice> {
    if settings.workers == 0 && !shared {
        return Err(BadChoice::NoWorkers);
    }
    if shared && settings.batch != 1 {
        return Err(BadChoice::SharedBatch(settings.batch));
    }
    Ok(())
}

/// The optimizer an optimizer file names, starting from `start`.
fn build_optimizer(
    algorithm: &Algorithm,
    space: &SearchSpace,
    design: Option<DesignSpace>,
    start: &Genome,
    settings: &RunSettings,
) -> Result<Box<dyn Optimizer>, OptimizeError> {
    Ok(match algorithm {
        Algorithm::Genetic(ga) => Box::new(GeneticAlgorithm::new(
            space.clone(),
            ga.clone(),
            start.clone(),
            settings.seed,
            settings.max_evaluations,
        )),
        Algorithm::CmaEs(c) => Box::new(CmaOptimizer::with_restarts(
            space.clone(),
            start.clone(),
            c.sigma,
            c.popsize as usize,
            settings.seed,
            settings.max_evaluations,
            c.restarts,
        )),
        Algorithm::GreatDeluge(gd) => Box::new(GreatDeluge::new(
            space.clone(),
            gd.clone(),
            start.clone(),
            settings.seed,
            settings.deluge_batch,
            settings.max_evaluations,
        )),
        Algorithm::Es(e) => Box::new(EsOptimizer::new(
            space.clone(),
            start.clone(),
            e,
            settings.seed,
            settings.max_evaluations,
        )),
        Algorithm::MapElites(m) => Box::new(MapElites::new(
            space.clone(),
            m.clone(),
            map_axes(m, space, design)?,
            start.clone(),
            settings.seed,
            settings.max_evaluations,
        )),
    })
}

/// The scorer for a run: through the queue when it records into a shared store, else on
/// this host's threads (recording into its store, if any).
fn scorer_for<'a>(
    recording: Option<Recording<'a>>,
    evaluator: Evaluator,
    settings: &RunSettings,
    registry: &ModuleRegistry,
) -> Result<Box<dyn Scorer + 'a>, OptimizeError> {
    let Some(Recording {
        store,
        run,
        known,
        crash_after,
    }) = recording
    else {
        return Ok(Box::new(LocalScorer::new(evaluator, settings, None)));
    };
    Ok(match store {
        Store::Postgres(pg) => Box::new(QueueScorer::start(
            pg, run, known, evaluator, settings, registry,
        )?),
        store => Box::new(LocalScorer::new(
            evaluator,
            settings,
            Some(Recording {
                store,
                run,
                known,
                crash_after,
            }),
        )),
    })
}

//! One optimization run: the optimizer named by the simulation's optimizer file, fed by the
//! evaluator, every evaluation reported to a callback (progress, logs, the store) as its
//! batch finishes.

use std::ops::Range;

use crate::config::Simulation;
use crate::config::optimizer::Algorithm;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::optimize::Optimizer;
use crate::optimize::cmaes::CmaOptimizer;
use crate::optimize::deluge::GreatDeluge;
use crate::optimize::error::{BadChoice, OptimizeError};
use crate::optimize::es::EsOptimizer;
use crate::optimize::evaluate::Evaluator;
use crate::optimize::ga::GeneticAlgorithm;
use crate::optimize::map_elites::{Descriptor, MapElites};
use crate::optimize::shared::driver::{LocalWorkers, evaluate_round};
use crate::optimize::shared::worker::OUTAGE;
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::pg_queue::{DONE, Pending};
use crate::optimize::store::{PgStore, Store, StoredEval};
use crate::rng::SimRng;

pub use crate::optimize::settings::{RunChoices, RunSettings, StopFlag};

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
    pub batching: String,
    /// Rounds (GA generations, great-deluge batches).
    pub rounds: u64,
}

/// The configured start candidate and the search space of `sim`, whose modules
/// `registry` creates.
pub fn prepare(
    sim: &Simulation,
    registry: &ModuleRegistry,
) -> Result<(SearchSpace, Genome), OptimizeError> {
    let model = sim
        .optimizer
        .as_ref()
        .ok_or_else(|| OptimizeError::NoOptimizer {
            file: sim.file.clone(),
            mode: sim.files.simulation.properties.mode.name().to_string(),
        })?;
    if let Some(design) = crate::optimize::design::DesignSpace::from_model(model) {
        // Bodies and gaits start from the middle of every gene's range.
        let space = design.search_space();
        let start = space.genes.iter().map(|g| g.alleles.count() / 2).collect();
        return Ok((space, start));
    }
    let limits = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let kernel = ControlKernel::from_actuation(&sim.actuation, registry, limits)?;
    let space = SearchSpace::from_model(model, &kernel)?;
    if space.genes.is_empty() {
        return Err(OptimizeError::NothingRegistered {
            file: model.file.clone(),
        });
    }
    let start = space.encode_kernel(&kernel);
    Ok((space, start))
}

/// The search's start: the configured candidate, or with `random` one drawn from `seed`.
fn start_candidate(random: bool, space: &SearchSpace, configured: Genome, seed: u64) -> Genome {
    if random {
        space.random(&mut SimRng::new(seed ^ RANDOM_START_STREAM))
    } else {
        configured
    }
}

/// Where a run stores its evaluations, and what it already holds (for `--resume`).
pub struct Recording<'a> {
    /// The experiment store.
    pub store: &'a mut Store,
    /// The run's id in the store.
    pub run: i64,
    /// Evaluations stored by an earlier, interrupted attempt of this run, sorted by
    /// number (as [`Store::evaluations`] returns them).
    pub known: Vec<StoredEval>,
    /// Testing aid for resumption: abort the process (no clean-up, like `kill -9`) right
    /// after the batch that brings this call's stored evaluations to this many.
    pub crash_after: Option<u64>,
}

/// Runs the optimization of `sim`, calling `on_eval` for every evaluation in order. With a
/// recording, every evaluation is stored as its batch finishes, and stored ones (same
/// number and genome) are reused instead of simulated again.
pub fn optimize(
    sim: &Simulation,
    settings: &RunSettings,
    registry: &ModuleRegistry,
    mut recording: Option<Recording<'_>>,
    mut on_eval: impl FnMut(&Evaluation),
) -> Result<RunOutcome, OptimizeError> {
    let (space, configured) = prepare(sim, registry)?;
    let Some(model) = sim.optimizer.as_ref() else {
        return Err(OptimizeError::NoOptimizer {
            file: sim.file.clone(),
            mode: sim.files.simulation.properties.mode.name().to_string(),
        });
    };
    let start = start_candidate(model.spec.random_start, &space, configured, settings.seed);
    let design = crate::optimize::design::DesignSpace::from_model(model);
    let mut optimizer = build_optimizer(&model.spec.algorithm, (&space, design), &start, settings)?;
    let shared = recording.as_mut().and_then(|r| r.store.shared()).is_some();
    check_workers(settings, shared)?;
    let workers = settings.workers;
    let base = Evaluator {
        batch: settings.batch,
        ..Evaluator::new(
            sim,
            registry,
            &space,
            settings.fitness,
            settings.duration,
            settings.seed,
        )
    };
    let evaluator = |workers: usize| Evaluator {
        workers,
        ..base.clone()
    };
    let local = match recording.as_mut() {
        Some(r) if shared => start_local_workers(r, registry, evaluator(1), settings)?,
        _ => None,
    };
    let mut scoring = Scoring {
        evaluator: evaluator(workers.max(1)),
        batching: Batching::new(settings.batch, workers.max(1)),
        local,
        stored: 0,
        simulated: 0,
    };
    let (mut n, mut round, mut best) = (0u64, 0u64, f64::NEG_INFINITY);
    let mut start_score = None;
    while !optimizer.finished() && !settings.stop.is_set() {
        let candidates = optimizer.ask();
        if candidates.is_empty() {
            break;
        }
        let (scores, measures) =
            scoring.score(&mut recording, (n, round), &candidates, settings.seed)?;
        for (g, s) in candidates.iter().zip(&scores) {
            start_score = start_score.or(Some(*s));
            best = best.max(*s);
            on_eval(&Evaluation {
                number: n,
                round,
                genome: g.clone(),
                score: *s,
                best,
            });
            n += 1;
        }
        optimizer.tell_measured(&scores, &measures);
        round += 1;
    }
    let (batching, simulated) = scoring.finish(&mut recording, workers)?;
    if let Some(r) = recording.as_mut() {
        r.store.finish_run(r.run)?;
    }
    let (g, s) = optimizer
        .best()
        .map(|(g, s)| (g.clone(), s))
        .ok_or(OptimizeError::NothingEvaluated)?;
    Ok(RunOutcome {
        best: g,
        best_score: s,
        start,
        start_drawn: model.spec.random_start,
        start_score,
        evaluations: n,
        simulated,
        batching,
        rounds: round,
    })
}

/// A round's scores and the quantities measured in their episodes, in candidate order.
type Scores = (Vec<f64>, Vec<Vec<f64>>);

/// How a run's candidates get their scores: from the store (resuming), simulated here, or
/// through a shared store's queue with the driver's local workers.
struct Scoring {
    evaluator: Evaluator,
    batching: Batching,
    local: Option<LocalWorkers>,
    /// Evaluations stored by this call (for the crash aid).
    stored: u64,
    /// Evaluations simulated by this call (the rest came from the store).
    simulated: u64,
}

impl Scoring {
    /// The scores of a round's candidates, the first numbered `first`, and the quantities
    /// measured in their episodes.
    fn score(
        &mut self,
        recording: &mut Option<Recording<'_>>,
        (first, round): (u64, u64),
        candidates: &[Genome],
        seed: u64,
    ) -> Result<Scores, OptimizeError> {
        let (mut scores, missing) = reuse_stored(recording.as_ref(), first, candidates);
        self.simulated += missing.len() as u64;
        let round_of = RoundRef {
            first,
            round,
            candidates,
            missing: &missing,
        };
        match (self.local.as_mut(), recording.as_mut()) {
            (Some(local), Some(rec)) => {
                let run = rec.run;
                let Some(pg) = rec.store.shared() else {
                    return Err(OptimizeError::StoreGone);
                };
                let space = &self.evaluator.space;
                queue_missing(pg, run, seed, space, &round_of, &mut scores, local)?;
            }
            _ => simulate_missing(
                &mut self.evaluator,
                &mut self.batching,
                &round_of,
                &mut scores,
                recording,
                (seed, &mut self.stored),
            )?,
        }
        Ok(scores)
    }

    /// Stops the local workers; how candidates were spread, and how many were simulated.
    fn finish(
        self,
        recording: &mut Option<Recording<'_>>,
        workers: usize,
    ) -> Result<(String, u64), OptimizeError> {
        let mut description = self.batching.description;
        if let (Some(local), Some(pg)) = (
            self.local,
            recording.as_mut().and_then(|r| r.store.shared()),
        ) {
            local.finish(pg)?;
            description = format!(
                "one world per candidate, through the shared store ({workers} local worker thread(s))"
            );
        }
        Ok((description, self.simulated))
    }
}

/// The driver's own evaluating threads on a shared store (listening for results first).
fn start_local_workers(
    r: &mut Recording<'_>,
    registry: &ModuleRegistry,
    evaluator: Evaluator,
    settings: &RunSettings,
) -> Result<Option<LocalWorkers>, OptimizeError> {
    let run = r.run;
    let Some(pg) = r.store.shared() else {
        return Ok(None);
    };
    pg.listen(DONE)?;
    Ok(Some(LocalWorkers::start(
        pg,
        registry,
        evaluator,
        (run, settings.workers),
        settings.lease,
    )))
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

/// Puts the round's missing candidates in the shared store's queue and fills their scores
/// as the workers (local and remote) write them.
fn queue_missing(
    pg: &mut PgStore,
    run: i64,
    seed: u64,
    space: &crate::optimize::space::SearchSpace,
    r: &RoundRef<'_>,
    scores: &mut Scores,
    local: &mut LocalWorkers,
) -> Result<(), OptimizeError> {
    if r.missing.is_empty() {
        return Ok(());
    }
    let pending: Vec<Pending> = r
        .missing
        .iter()
        .map(|&i| Pending {
            number: r.first + i as u64,
            round: r.round,
            genome: r.candidates[i].clone(),
            values: space.decode(&r.candidates[i]),
        })
        .collect();
    // A lost connection (the server restarted) is made again; queueing the same
    // candidates again changes nothing, and the workers' results are in the store.
    let got = loop {
        match evaluate_round(pg, run, seed, &pending, local) {
            Ok(got) => break got,
            Err(_) if pg.is_closed() => pg.reconnect(OUTAGE, &|| false)?,
            Err(e) => return Err(e),
        }
    };
    for (k, (s, m)) in got.into_iter().enumerate() {
        let i = r.missing[k];
        scores.0[i] = if s.is_nan() { f64::NEG_INFINITY } else { s };
        scores.1[i] = m;
    }
    Ok(())
}

/// The optimizer an optimizer file names, starting from `start`.
/// The archive's two axes of a MAP-Elites file in `space`; a descriptor naming a gene the
/// space does not have is an error naming both.
pub fn map_axes(
    m: &crate::config::optimizer::MapElitesSettings,
    space: &SearchSpace,
    design: Option<crate::optimize::design::DesignSpace>,
) -> Result<[Descriptor; 2], OptimizeError> {
    let design = design.map(std::sync::Arc::new);
    let axis = |k: usize| {
        let spec = m.descriptors.get(k).ok_or(OptimizeError::Descriptor {
            gene: 0,
            genes: space.genes.len(),
        })?;
        // Measured descriptors read the evaluation's measures in descriptor order.
        let index = m.descriptors[..k]
            .iter()
            .filter(|d| d.measured.is_some())
            .count();
        Descriptor::of(spec, space, design.as_ref(), index).ok_or(OptimizeError::Descriptor {
            gene: spec.gene,
            genes: space.genes.len(),
        })
    };
    Ok([axis(0)?, axis(1)?])
}

fn build_optimizer(
    algorithm: &Algorithm,
    (space, design): (&SearchSpace, Option<crate::optimize::design::DesignSpace>),
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
            (c.sigma, c.popsize as usize),
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

/// The scores (and measures) an interrupted attempt stored for this round's candidates
/// (same number and genome), and the indices of the candidates still to simulate.
fn reuse_stored(
    recording: Option<&Recording<'_>>,
    first: u64,
    candidates: &[Genome],
) -> (Scores, Vec<usize>) {
    let mut scores = vec![f64::NAN; candidates.len()];
    let mut measures = vec![Vec::new(); candidates.len()];
    let mut missing = Vec::new();
    for (i, g) in candidates.iter().enumerate() {
        let number = first + i as u64;
        let known = recording.and_then(|r| {
            // Batches may finish out of order: look the number up, do not index.
            r.known
                .binary_search_by_key(&number, |k| k.number)
                .ok()
                .map(|at| &r.known[at])
                .filter(|k| k.genome == *g)
        });
        match known {
            Some(k) => {
                scores[i] = if k.score.is_nan() {
                    f64::NEG_INFINITY
                } else {
                    k.score
                };
                measures[i].clone_from(&k.measures);
            }
            None => missing.push(i),
        }
    }
    ((scores, measures), missing)
}

/// How candidates are spread over worlds: given, or measured on the first large round
/// (one world per candidate against robots sharing worlds) and then kept.
struct Batching {
    given: usize,
    workers: usize,
    shared_worlds: Option<bool>,
    description: String,
}

impl Batching {
    fn new(given: usize, workers: usize) -> Batching {
        let description = if given > 0 {
            format!("{given} robots per world (given)")
        } else {
            "one world per candidate (rounds too small to measure)".to_string()
        };
        Batching {
            given,
            workers,
            shared_worlds: None,
            description,
        }
    }

    /// Parts of a round of `len` candidates: (range, robots per world).
    fn plan(&self, len: usize) -> Vec<(Range<usize>, usize)> {
        let workers = self.workers;
        let shared = |k: usize| k.div_ceil(workers).max(1);
        match (self.given, self.shared_worlds) {
            (b, _) if b > 0 => vec![(0..len, b)],
            (_, Some(true)) => vec![(0..len, shared(len))],
            (_, Some(false)) => vec![(0..len, 1)],
            // Not measured yet: one world per candidate for the first `workers`
            // candidates, shared worlds for the rest, and keep the faster.
            (_, None) if len > 2 * workers => {
                vec![(0..workers, 1), (workers..len, shared(len - workers))]
            }
            (_, None) => vec![(0..len, 1)],
        }
    }

    /// Keeps the faster way once both were measured: `rates` holds (robots per world,
    /// candidates per second) of a round's parts.
    fn learn(&mut self, rates: &[(usize, f64)]) {
        if self.given > 0 || self.shared_worlds.is_some() || rates.len() != 2 {
            return;
        }
        let faster_shared = rates[1].1 > rates[0].1;
        self.shared_worlds = Some(faster_shared);
        self.description = format!(
            "{} (measured {:.2} candidates/s alone, {:.2} with {} robots per world)",
            if faster_shared {
                "robots share worlds"
            } else {
                "one world per candidate"
            },
            rates[0].1,
            rates[1].1,
            rates[1].0
        );
    }
}

/// A round's candidates: its first evaluation number, round number, the candidates and
/// the indices of those to simulate.
struct RoundRef<'a> {
    first: u64,
    round: u64,
    candidates: &'a [Genome],
    missing: &'a [usize],
}

/// Simulates the round's missing candidates part by part, storing every batch as it
/// finishes, and fills their scores.
fn simulate_missing(
    evaluator: &mut Evaluator,
    batching: &mut Batching,
    r: &RoundRef<'_>,
    scores: &mut Scores,
    recording: &mut Option<Recording<'_>>,
    (seed, stored): (u64, &mut u64),
) -> Result<(), OptimizeError> {
    if r.missing.is_empty() {
        return Ok(());
    }
    let todo: Vec<Genome> = r.missing.iter().map(|i| r.candidates[*i].clone()).collect();
    let mut rates = Vec::new();
    for (range, batch) in batching.plan(todo.len()) {
        evaluator.batch = batch;
        let t = std::time::Instant::now();
        let mut store_error = None;
        let offset = range.start;
        let space = &evaluator.space;
        let got = evaluator.evaluate_with(&todo[range.clone()], |first, batch_scores, wall| {
            let Some(rec) = recording.as_mut() else {
                return;
            };
            let evals: Vec<StoredEval> = batch_scores
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    let i = r.missing[offset + first + k];
                    StoredEval {
                        number: r.first + i as u64,
                        round: r.round,
                        genome: r.candidates[i].clone(),
                        values: space.decode(&r.candidates[i]),
                        score: s.score,
                        engines: s.engines.clone(),
                        rejected: s.rejected.as_ref().map(ToString::to_string),
                        measures: s.measures.clone(),
                        wall: wall / batch_scores.len().max(1) as f64,
                    }
                })
                .collect();
            if let Err(e) = rec.store.record(rec.run, seed, &evals) {
                store_error.get_or_insert(e);
            }
            *stored += evals.len() as u64;
            if rec.crash_after.is_some_and(|n| *stored >= n) {
                std::process::abort();
            }
        })?;
        if let Some(e) = store_error {
            return Err(e.into());
        }
        let rate = range.len() as f64 / t.elapsed().as_secs_f64().max(1e-9);
        rates.push((batch, rate));
        for (k, score) in got.into_iter().enumerate() {
            let i = r.missing[offset + k];
            scores.0[i] = score.score;
            scores.1[i] = score.measures;
        }
    }
    batching.learn(&rates);
    Ok(())
}

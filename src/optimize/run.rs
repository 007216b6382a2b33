//! One optimization run: the optimizer named by the simulation's optimizer file, fed by the
//! evaluator, every evaluation reported to a callback (progress, logs, the store) as its
//! batch finishes.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::config::Simulation;
use crate::config::optimizer::Algorithm;
use crate::optimize::Optimizer;
use crate::optimize::deluge::GreatDeluge;
use crate::optimize::evaluate::Evaluator;
use crate::optimize::fitness::Fitness;
use crate::optimize::ga::GeneticAlgorithm;
use crate::optimize::space::{Genome, SearchSpace};
use crate::optimize::store::{Store, StoredEval};
use crate::sim::{BuildOptions, Simulator};

/// Set from another thread to end a run after its current round (the GUI's Stop).
#[derive(Debug, Clone, Default)]
pub struct StopFlag(pub Arc<AtomicBool>);

impl StopFlag {
    pub fn stop(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    pub fn is_set(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}

impl PartialEq for StopFlag {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// How to run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSettings {
    pub seed: u64,
    pub workers: usize,
    /// Robots per world (0: split each round evenly over the workers).
    pub batch: usize,
    /// Great deluge: neighbours handed out per round.
    pub deluge_batch: usize,
    pub max_evaluations: u64,
    /// Simulated seconds per episode.
    pub duration: f64,
    pub fitness: Fitness,
    /// Ends the run early when set (between rounds).
    pub stop: StopFlag,
}

/// One finished evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// 0-based evaluation number.
    pub number: u64,
    /// Round (GA generation / great-deluge batch) it belonged to.
    pub round: u64,
    pub genome: Genome,
    pub score: f64,
    /// Best score so far, this one included.
    pub best: f64,
}

/// What a run found.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub best: Genome,
    pub best_score: f64,
    pub start: Genome,
    pub start_score: Option<f64>,
    pub evaluations: u64,
    /// Evaluations simulated in this call (the rest came from the store).
    pub simulated: u64,
    /// How candidates were spread over worlds, and why.
    pub batching: String,
    pub rounds: u64,
}

/// The configured start candidate and the search space of `sim`.
pub fn prepare(sim: &Simulation) -> Result<(SearchSpace, Genome), String> {
    let model = sim.optimizer.as_ref().ok_or_else(|| {
        format!(
            "{}: mode {:?} has no optimizer file; optimization needs mode \"Genetic Algorithm\" or \"Great Deluge\" with an <optimizer>",
            sim.file.display(),
            sim.files.simulation.properties.mode.name()
        )
    })?;
    let space = SearchSpace::from_model(model);
    if space.genes.is_empty() {
        return Err(format!(
            "{}: no parameter is registered for optimization",
            model.file.display()
        ));
    }
    let s = Simulator::new(
        sim,
        &BuildOptions {
            robots: 1,
            seed: 1,
            record: false,
        },
    )
    .map_err(|e| e.to_string())?;
    let start = space.encode_kernel(s.kernel(0).map_err(|e| e.to_string())?);
    Ok((space, start))
}

/// Where a run stores its evaluations, and what it already holds (for `--resume`).
pub struct Recording<'a> {
    pub store: &'a mut Store,
    pub run: i64,
    /// Evaluations stored by an earlier, interrupted attempt of this run, sorted by
    /// number (as [`Store::evaluations`] returns them).
    pub known: Vec<StoredEval>,
}

/// Runs the optimization of `sim`, calling `on_eval` for every evaluation in order. With a
/// recording, every evaluation is stored as its batch finishes, and stored ones (same
/// number and genome) are reused instead of simulated again.
pub fn optimize(
    sim: &Simulation,
    settings: &RunSettings,
    mut recording: Option<Recording<'_>>,
    mut on_eval: impl FnMut(&Evaluation),
) -> Result<Outcome, String> {
    let (space, start) = prepare(sim)?;
    let Some(model) = sim.optimizer.as_ref() else {
        return Err("no optimizer".into());
    };
    let mut optimizer: Box<dyn Optimizer> = match &model.spec.algorithm {
        Algorithm::Genetic(ga) => Box::new(GeneticAlgorithm::new(
            space.clone(),
            ga.clone(),
            start.clone(),
            settings.seed,
            settings.max_evaluations,
        )),
        Algorithm::GreatDeluge(gd) => Box::new(GreatDeluge::new(
            space.clone(),
            gd.clone(),
            start.clone(),
            settings.seed,
            settings.deluge_batch,
            settings.max_evaluations,
        )),
    };
    let workers = settings.workers.max(1);
    let mut evaluator = Evaluator {
        sim: sim.clone(),
        space,
        fitness: settings.fitness,
        duration: settings.duration,
        seed: settings.seed,
        batch: settings.batch,
        workers,
    };
    let (mut n, mut round, mut best) = (0u64, 0u64, f64::NEG_INFINITY);
    let mut start_score = None;
    let mut simulated = 0u64;
    let mut shared_worlds: Option<bool> = None;
    let mut batching = if settings.batch > 0 {
        format!("{} robots per world (given)", settings.batch)
    } else {
        "one world per candidate (rounds too small to measure)".to_string()
    };
    while !optimizer.finished() && !settings.stop.is_set() {
        let candidates = optimizer.ask();
        if candidates.is_empty() {
            break;
        }
        // Reuse what an interrupted attempt stored; simulate the rest.
        let mut scores = vec![f64::NAN; candidates.len()];
        let mut missing = Vec::new();
        for (i, g) in candidates.iter().enumerate() {
            let number = n + i as u64;
            let known = recording.as_ref().and_then(|r| {
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
                    }
                }
                None => missing.push(i),
            }
        }
        simulated += missing.len() as u64;
        if !missing.is_empty() {
            let todo: Vec<Genome> = missing.iter().map(|i| candidates[*i].clone()).collect();
            let len = todo.len();
            let shared = |k: usize| k.div_ceil(workers).max(1);
            // Parts of the round: (range of `todo`, robots per world).
            let parts: Vec<(std::ops::Range<usize>, usize)> = match (settings.batch, shared_worlds)
            {
                (b, _) if b > 0 => vec![(0..len, b)],
                (_, Some(true)) => vec![(0..len, shared(len))],
                (_, Some(false)) => vec![(0..len, 1)],
                // Not measured yet: one world per candidate for the first `workers`
                // candidates, shared worlds for the rest, and keep the faster.
                (_, None) if len > 2 * workers => {
                    vec![(0..workers, 1), (workers..len, shared(len - workers))]
                }
                (_, None) => vec![(0..len, 1)],
            };
            let mut rates = Vec::new();
            for (range, batch) in parts {
                evaluator.batch = batch;
                let t = std::time::Instant::now();
                let mut store_error = None;
                let offset = range.start;
                let got = evaluator.evaluate_with(
                    &todo[range.clone()],
                    |first, batch_scores, wall| {
                        let Some(r) = recording.as_mut() else { return };
                        let evals: Vec<StoredEval> = batch_scores
                            .iter()
                            .enumerate()
                            .map(|(k, s)| {
                                let i = missing[offset + first + k];
                                StoredEval {
                                    number: n + i as u64,
                                    round,
                                    genome: candidates[i].clone(),
                                    values: evaluator.space.decode(&candidates[i]),
                                    score: *s,
                                    wall: wall / batch_scores.len().max(1) as f64,
                                }
                            })
                            .collect();
                        if let Err(e) = r.store.record(r.run, settings.seed, &evals) {
                            store_error.get_or_insert(e);
                        }
                    },
                )?;
                if let Some(e) = store_error {
                    return Err(e);
                }
                rates.push((
                    batch,
                    range.len() as f64 / t.elapsed().as_secs_f64().max(1e-9),
                ));
                for (k, score) in got.into_iter().enumerate() {
                    scores[missing[offset + k]] = score;
                }
            }
            if settings.batch == 0 && shared_worlds.is_none() && rates.len() == 2 {
                let faster_shared = rates[1].1 > rates[0].1;
                shared_worlds = Some(faster_shared);
                batching = format!(
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
        for (g, s) in candidates.iter().zip(&scores) {
            if n == 0 {
                start_score = Some(*s);
            }
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
        optimizer.tell(&scores);
        round += 1;
    }
    if let Some(r) = recording.as_ref() {
        r.store.finish_run(r.run)?;
    }
    let (g, s) = optimizer
        .best()
        .map(|(g, s)| (g.clone(), s))
        .ok_or_else(|| "the optimizer evaluated nothing".to_string())?;
    Ok(Outcome {
        best: g,
        best_score: s,
        start,
        start_score,
        evaluations: n,
        simulated,
        batching,
        rounds: round,
    })
}

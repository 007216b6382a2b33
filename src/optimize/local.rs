//! Scoring on this host: the round's candidates simulated by the evaluator's threads,
//! spread over worlds as its planner finds fastest ([`Batching`] says how), each batch
//! stored as it finishes.

use std::ops::Range;

use crate::optimize::error::OptimizeError;
use crate::optimize::evaluate::Evaluator;
use crate::optimize::scorer::{
    Batching, Recording, Round, Scorer, ScoringSummary, complete, reuse_stored,
};
use crate::optimize::scores::{CandidateScore, StoredEval};
use crate::optimize::settings::RunSettings;
use crate::optimize::space::Genome;

/// The scorer of a run without a shared store.
pub struct LocalScorer<'a> {
    evaluator: Evaluator,
    planner: Planner,
    recording: Option<Recording<'a>>,
    seed: u64,
    /// Evaluations stored by this call (for the crash aid).
    stored: u64,
    /// Evaluations of finished rounds simulated by this call (the rest came from the store).
    simulated: u64,
}

impl<'a> LocalScorer<'a> {
    /// Scores with `evaluator` on `settings.workers` threads, recording into `recording`.
    pub fn new(
        evaluator: Evaluator,
        settings: &RunSettings,
        recording: Option<Recording<'a>>,
    ) -> LocalScorer<'a> {
        let workers = settings.workers.max(1);
        LocalScorer {
            evaluator: Evaluator {
                workers,
                ..evaluator
            },
            planner: Planner::new(settings.batch, workers),
            recording,
            seed: settings.seed,
            stored: 0,
            simulated: 0,
        }
    }

    /// Simulates the candidates `missing` of the round part by part, storing every batch
    /// as it finishes, and fills their scores.
    fn simulate(
        &mut self,
        round: &Round<'_>,
        missing: &[usize],
        scores: &mut [Option<CandidateScore>],
    ) -> Result<(), OptimizeError> {
        let todo: Vec<Genome> = missing
            .iter()
            .map(|i| round.candidates[*i].clone())
            .collect();
        let mut rates = Vec::new();
        for (range, batch) in self.planner.plan(todo.len()) {
            self.evaluator.batch = batch;
            let t = std::time::Instant::now();
            let got = self.evaluate_part(round, missing, &todo, range.clone())?;
            let rate = range.len() as f64 / t.elapsed().as_secs_f64().max(1e-9);
            rates.push((batch, rate));
            for (k, score) in got.into_iter().enumerate() {
                scores[missing[range.start + k]] = Some(score);
            }
        }
        self.planner.learn(&rates);
        Ok(())
    }

    /// Evaluates `todo[range]` (candidates `missing[range]` of the round), storing each
    /// batch as it finishes.
    fn evaluate_part(
        &mut self,
        round: &Round<'_>,
        missing: &[usize],
        todo: &[Genome],
        range: Range<usize>,
    ) -> Result<Vec<CandidateScore>, OptimizeError> {
        let mut store_error = None;
        let offset = range.start;
        let (space, seed) = (&self.evaluator.space, self.seed);
        let (recording, stored) = (&mut self.recording, &mut self.stored);
        let got = self
            .evaluator
            .evaluate_with(&todo[range], |first, batch_scores, wall| {
                let Some(rec) = recording.as_mut() else {
                    return;
                };
                let evals: Vec<StoredEval> = batch_scores
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        let i = missing[offset + first + k];
                        StoredEval {
                            number: round.first + i as u64,
                            round: round.number,
                            genome: round.candidates[i].clone(),
                            values: space.decode(&round.candidates[i]),
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
        match store_error {
            Some(e) => Err(e.into()),
            None => Ok(got),
        }
    }
}

impl Scorer for LocalScorer<'_> {
    fn score(&mut self, round: &Round<'_>) -> Result<Vec<CandidateScore>, OptimizeError> {
        let known = self.recording.as_ref().map_or(&[][..], |r| &r.known[..]);
        let (mut scores, missing) = reuse_stored(known, round);
        if !missing.is_empty() {
            self.simulate(round, &missing, &mut scores)?;
        }
        // Counted once the round is scored: a round stopped midway is not an evaluation
        // of the run (its finished batches are stored and come from the store on resume).
        self.simulated += missing.len() as u64;
        Ok(complete(scores))
    }

    fn finish(self: Box<Self>, finished: bool) -> Result<ScoringSummary, OptimizeError> {
        let this = *self;
        if let Some(r) = this.recording.filter(|_| finished) {
            r.store.finish_run(r.run)?;
        }
        Ok(ScoringSummary {
            batching: this.planner.report,
            simulated: this.simulated,
        })
    }
}

/// How candidates are spread over worlds: given, or measured on the first large round
/// (one world per candidate against robots sharing worlds) and then kept.
struct Planner {
    given: usize,
    workers: usize,
    shared_worlds: Option<bool>,
    report: Batching,
}

impl Planner {
    fn new(given: usize, workers: usize) -> Planner {
        Planner {
            given,
            workers,
            shared_worlds: None,
            report: if given > 0 {
                Batching::Given(given)
            } else {
                Batching::Unmeasured
            },
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
        self.report = Batching::Measured {
            share: faster_shared,
            alone: rates[0].1,
            shared: rates[1].1,
            robots: rates[1].0,
        };
    }
}

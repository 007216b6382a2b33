//! Scoring through a shared store: a round's candidates go into the store's queue, the
//! driver's own worker threads ([`LocalWorkers`]) and workers on other hosts evaluate
//! them, and their scores come back in candidate order.

use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::evaluate::Evaluator;
use crate::optimize::scorer::{Batching, Round, Scorer, ScoringSummary, complete, reuse_stored};
use crate::optimize::scores::{CandidateScore, StoredEval};
use crate::optimize::settings::RunSettings;
use crate::optimize::shared::driver::{LocalWorkers, evaluate_round};
use crate::optimize::shared::work::RunWork;
use crate::optimize::shared::worker::OUTAGE;
use crate::optimize::space::SearchSpace;
use crate::optimize::store::pg_queue::{DONE, Pending};
use crate::optimize::store::{ExperimentStore, PgStore};
use crate::signal::StopFlag;

/// The scorer of a run on a shared store.
pub struct QueueScorer<'a> {
    store: &'a mut PgStore,
    run: i64,
    seed: u64,
    known: Vec<StoredEval>,
    space: SearchSpace,
    local: LocalWorkers,
    workers: usize,
    /// Evaluations of finished rounds queued by this call (the rest came from the store).
    queued: u64,
    /// The run's stop flag: raised, the wait for a round ends.
    stop: StopFlag,
}

impl<'a> QueueScorer<'a> {
    /// Listens for results and starts the driver's `settings.workers` local worker
    /// threads on `run` (with `known`, its evaluations stored already), each evaluating
    /// with `evaluator`.
    pub fn start(
        store: &'a mut PgStore,
        run: i64,
        known: Vec<StoredEval>,
        evaluator: Evaluator,
        settings: &RunSettings,
        registry: &ModuleRegistry,
    ) -> Result<QueueScorer<'a>, OptimizeError> {
        store.listen(DONE)?;
        let (space, stop) = (evaluator.space.clone(), evaluator.stop.clone());
        let local = LocalWorkers::start(
            store,
            registry,
            RunWork::Candidates(Evaluator {
                workers: 1,
                ..evaluator
            }),
            run,
            settings.workers,
            settings.lease,
        );
        Ok(QueueScorer {
            store,
            run,
            seed: settings.seed,
            known,
            space,
            local,
            workers: settings.workers,
            queued: 0,
            stop,
        })
    }
}

impl Scorer for QueueScorer<'_> {
    fn score(&mut self, round: &Round<'_>) -> Result<Vec<CandidateScore>, OptimizeError> {
        let (mut scores, missing) = reuse_stored(&self.known, round);
        if missing.is_empty() {
            return Ok(complete(scores));
        }
        let pending: Vec<Pending> = missing
            .iter()
            .map(|&i| Pending {
                number: round.first + i as u64,
                round: round.number,
                genome: round.candidates[i].clone(),
                values: self.space.decode(&round.candidates[i]),
            })
            .collect();
        // A lost connection (the server restarted) is made again; queueing the same
        // candidates again changes nothing, and the workers' results are in the store.
        let got = loop {
            let (run, seed, stop) = (self.run, self.seed, &self.stop);
            match evaluate_round(self.store, run, seed, &pending, &mut self.local, stop) {
                Ok(got) => break got,
                Err(_) if self.store.is_closed() => self.store.reconnect(OUTAGE, &|| false)?,
                Err(e) => return Err(e),
            }
        };
        for (k, score) in got.into_iter().enumerate() {
            scores[missing[k]] = Some(score);
        }
        // Counted once the round is scored, as a local run counts (a stopped round is not
        // an evaluation of the run).
        self.queued += missing.len() as u64;
        Ok(complete(scores))
    }

    fn finish(self: Box<Self>, finished: bool) -> Result<ScoringSummary, OptimizeError> {
        let this = *self;
        this.local.finish(this.store)?;
        if finished {
            this.store.finish_run(this.run)?;
        }
        Ok(ScoringSummary {
            batching: Batching::SharedStore(this.workers),
            simulated: this.queued,
        })
    }
}

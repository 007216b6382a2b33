//! The driver's end of a shared store: a round's candidates go into the queue and their
//! scores come back in candidate order; the driver's own cores evaluate too, as a pool of
//! workers restricted to its run.

use std::sync::Arc;
use std::thread::JoinHandle;

use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::evaluate::EvalError;
use crate::optimize::scores::CandidateScore;
use crate::signal::StopFlag;
use std::time::Duration;

use crate::optimize::shared::work::RunWork;
use crate::optimize::shared::worker::{WorkerOptions, WorkerReport, run_pool};
use crate::optimize::store::PgStore;
use crate::optimize::store::pg_queue::Pending;

/// Queues `pending` (candidates of `run`) and waits for their scores and measured
/// quantities, in the same order; a failed episode scores `-inf`. The wait ends with an
/// error if the local workers fail, and with [`EvalError::Stopped`] when `stop` is raised
/// (the queued candidates stay queued: a resumed run queues them again, which changes
/// nothing).
pub fn evaluate_round(
    store: &mut PgStore,
    run: i64,
    seed: u64,
    pending: &[Pending],
    local: &mut LocalWorkers,
    stop: &StopFlag,
) -> Result<Vec<CandidateScore>, OptimizeError> {
    store.enqueue(run, seed, pending)?;
    let numbers: Vec<u64> = pending.iter().map(|p| p.number).collect();
    store.wait_scores(run, &numbers, |_| {
        local.check()?;
        if stop.is_set() {
            return Err(OptimizeError::Eval(EvalError::Stopped));
        }
        Ok(())
    })
}

/// The driver's own evaluating threads, running beside it until dropped or finished.
pub struct LocalWorkers {
    stop: StopFlag,
    handle: Option<JoinHandle<Result<WorkerReport, OptimizeError>>>,
}

impl LocalWorkers {
    /// Starts `threads` workers (none for 0) on `run` of `store`, with its `work` already
    /// built from the driver's configuration, claiming with `lease`.
    pub fn start(
        store: &PgStore,
        registry: &ModuleRegistry,
        work: RunWork,
        run: i64,
        threads: usize,
        lease: Duration,
    ) -> LocalWorkers {
        let stop = StopFlag::default();
        if threads == 0 {
            return LocalWorkers { stop, handle: None };
        }
        // Finishing the driver's round early (it was stopped) abandons their episodes too.
        let work = Arc::new(work.with_stop(stop.clone()));
        let target = store.target().clone();
        let registry = registry.clone();
        let options = WorkerOptions {
            threads,
            lease,
            idle_exit: None,
            only_run: Some(run),
        };
        let flag = stop.clone();
        let handle = std::thread::spawn(move || {
            run_pool(
                &target,
                &registry,
                &options,
                &flag,
                Some((run, work)),
                &|_| {},
            )
        });
        LocalWorkers {
            stop,
            handle: Some(handle),
        }
    }

    /// An error if the threads ended on one (a lost connection): the driver would otherwise
    /// wait for results no one computes.
    pub fn check(&mut self) -> Result<(), OptimizeError> {
        if !self.handle.as_ref().is_some_and(|h| h.is_finished()) {
            return Ok(());
        }
        match self.handle.take().map(|h| h.join()) {
            Some(Ok(Err(e))) => Err(OptimizeError::LocalWorkers(Box::new(e))),
            Some(Err(_)) => Err(OptimizeError::Panicked),
            _ => Ok(()),
        }
    }

    /// Stops the threads (woken through `store`) and returns what they did.
    pub fn finish(mut self, store: &mut PgStore) -> Result<WorkerReport, OptimizeError> {
        self.stop.stop();
        store.wake_workers()?;
        match self.handle.take() {
            None => Ok(WorkerReport::default()),
            Some(h) => h.join().unwrap_or(Err(OptimizeError::Panicked)),
        }
    }
}

impl Drop for LocalWorkers {
    fn drop(&mut self) {
        self.stop.stop();
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

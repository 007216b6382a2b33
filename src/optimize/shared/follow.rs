//! Following a run read-only, as it goes: the control window attaches to a run of a shared
//! store (any store: SQLite too) and draws its learning curve while the driver and the
//! workers elsewhere write it. Nothing is written.

use std::time::Duration;

use crate::optimize::scores::finite_or_worst;
use crate::optimize::session::Evaluation;
use crate::optimize::store::{RunRow, Store, StoreLocation};
use crate::signal::StopFlag;

/// How often a followed run's store is read.
pub const FOLLOW_POLL: Duration = Duration::from_millis(500);

/// Which run of the store `follow_run` read, and how it ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Followed {
    /// The run's id.
    pub run: i64,
    /// Evaluations read.
    pub evaluations: u64,
    /// Whether the run finished (else the follower was stopped).
    pub finished: bool,
}

/// Reads `run` of the store at `location` (default: its latest unfinished run, else its
/// latest run), calling `on_run` with the run chosen, then `on_eval` for each finished
/// evaluation in number order — an
/// evaluation is passed on once all before it are done, so "best so far" is the run's —
/// every `poll`, until the run has finished and everything is read, or `stop` is set.
pub fn follow_run(
    location: &StoreLocation,
    run: Option<i64>,
    stop: &StopFlag,
    poll: Duration,
    on_run: impl FnOnce(&RunRow),
    mut on_eval: impl FnMut(&Evaluation),
) -> Result<Followed, crate::optimize::store::StoreError> {
    let mut store = Store::open_existing(location)?;
    let runs = store.runs()?;
    let chosen = match run {
        Some(id) => runs.iter().find(|r| r.id == id),
        None => runs
            .iter()
            .rev()
            .find(|r| !r.finished)
            .or_else(|| runs.last()),
    }
    .ok_or_else(|| match run {
        Some(run) => crate::optimize::store::StoreError::NoRun {
            store: store.describe(),
            run,
        },
        None => crate::optimize::store::StoreError::NoRuns {
            store: store.describe(),
        },
    })?;
    on_run(chosen);
    let id = chosen.id;
    let (mut next, mut best) = (0u64, f64::NEG_INFINITY);
    loop {
        // Finished is read before the evaluations: a run finished then has all of them.
        let finished = store.run_finished(id)?;
        for e in store.evaluations_from(id, next)? {
            if e.number != next {
                break;
            }
            let score = finite_or_worst(e.score);
            best = best.max(score);
            on_eval(&Evaluation {
                number: e.number,
                round: e.round,
                genome: e.genome,
                values: e.values,
                score,
                best,
            });
            next += 1;
        }
        if finished || stop.is_set() {
            return Ok(Followed {
                run: id,
                evaluations: next,
                finished,
            });
        }
        std::thread::sleep(poll);
    }
}

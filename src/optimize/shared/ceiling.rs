//! The coordinator's ceiling (`proleg bench --store URL`): how many evaluations per second
//! one PostgreSQL store can hand out and take back when evaluating costs nothing. A driver
//! thread enqueues rounds and waits for their scores exactly as an optimization does
//! (`PgStore::enqueue`, `wait_scores`), and client threads — standing in for workers on
//! as many hosts — claim batches and write a constant score back (`claim`,
//! `submit_many`), so that what is measured is the store's path alone: every statement,
//! round trip, lock and notification of a real run, and no simulation.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::optimize::error::OptimizeError;
use crate::optimize::evaluate::CandidateScore;
use crate::optimize::store::pg_queue::{ClaimResult, PENDING, Pending};
use crate::optimize::store::{ExperimentStore, PgStore, PgTarget, RunInfo};

/// What to measure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CeilingSetup {
    /// Evaluations in all.
    pub evaluations: u64,
    /// Evaluations per round (the driver waits for each round's scores).
    pub round: u64,
    /// Client threads claiming (each with its connection).
    pub clients: usize,
    /// Evaluations a client claims at once.
    pub batch: i64,
}

/// What was measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CeilingReport {
    /// The setup.
    pub setup: CeilingSetup,
    /// Evaluations handed out and taken back.
    pub evaluations: u64,
    /// Wall seconds from the first round's enqueue to the last round's scores.
    pub seconds: f64,
}

impl CeilingReport {
    /// Evaluations per second through the store.
    pub fn per_second(&self) -> f64 {
        self.evaluations as f64 / self.seconds.max(1e-9)
    }
}

/// Runs the measurement in a new run of the store at `target` (its tables made when the
/// database has none).
pub fn measure_ceiling(
    target: &PgTarget,
    setup: CeilingSetup,
) -> Result<CeilingReport, OptimizeError> {
    let mut driver = PgStore::open(target, true)?;
    let info = RunInfo {
        config: "coordinator ceiling".into(),
        algorithm: "none (proleg bench --store)".into(),
        seed: 1,
        fitness: "none".into(),
        duration: 0.0,
        genes: vec!["x".into()],
    };
    let run = driver.start_run(&info, "proleg bench", &[], &[])?;
    driver.listen(crate::optimize::store::pg_queue::DONE)?;
    let finished = AtomicBool::new(false);
    let started = Instant::now();
    let outcome = std::thread::scope(|s| {
        let clients: Vec<_> = (0..setup.clients.max(1))
            .map(|k| {
                let finished = &finished;
                s.spawn(move || client(target, run, k, setup.batch, finished))
            })
            .collect();
        let drove = drive(&mut driver, run, setup);
        finished.store(true, Ordering::Relaxed);
        // Wake the clients waiting for work, so that they see the end.
        let woke = driver.wake_workers();
        let mut result = drove.and_then(|n| woke.map(|()| n).map_err(OptimizeError::from));
        for c in clients {
            let ended = c.join().unwrap_or(Err(OptimizeError::Panicked));
            if result.is_ok() {
                result = ended.and(result);
            }
        }
        result
    });
    let seconds = started.elapsed().as_secs_f64();
    let evaluations = outcome?;
    driver.finish_run(run)?;
    Ok(CeilingReport {
        setup,
        evaluations,
        seconds,
    })
}

/// The driver's side: rounds enqueued, their scores awaited; the evaluations done.
fn drive(store: &mut PgStore, run: i64, setup: CeilingSetup) -> Result<u64, OptimizeError> {
    let round = setup.round.max(1);
    let mut number = 0;
    let mut round_index = 0;
    while number < setup.evaluations {
        let n = round.min(setup.evaluations - number);
        let pending: Vec<Pending> = (number..number + n)
            .map(|k| Pending {
                number: k,
                round: round_index,
                genome: vec![k as u32],
                values: vec![k as f64],
            })
            .collect();
        store.enqueue(run, 1, &pending)?;
        let numbers: Vec<u64> = pending.iter().map(|p| p.number).collect();
        store.wait_scores(run, &numbers, |waited| {
            if waited > 60.0 {
                Err(OptimizeError::Stalled { seconds: waited })
            } else {
                Ok(())
            }
        })?;
        number += n;
        round_index += 1;
    }
    Ok(number)
}

/// A client: claims batches of `run` and writes a constant score back until `finished`.
fn client(
    target: &PgTarget,
    run: i64,
    k: usize,
    batch: i64,
    finished: &AtomicBool,
) -> Result<(), OptimizeError> {
    let mut store = PgStore::open(target, false)?;
    store.listen(PENDING)?;
    let id = format!("ceiling/{}/{k}", std::process::id());
    let score = CandidateScore::single(1.0);
    while !finished.load(Ordering::Relaxed) {
        let claims = store.claim(&id, Duration::from_secs(60), Some(run), &[], batch)?;
        if claims.is_empty() {
            store.wait_notification(Duration::from_millis(200))?;
            continue;
        }
        let results: Vec<ClaimResult> = claims
            .iter()
            .map(|claim| ClaimResult {
                claim,
                score: &score,
                wall: 0.0,
            })
            .collect();
        store.submit_many(&id, &results)?;
    }
    Ok(())
}

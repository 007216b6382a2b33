//! The queue of shared evaluations in a PostgreSQL store. The driver writes a round's
//! candidates as `pending` rows ([`PgStore::enqueue`]); workers claim them
//! ([`PgStore::claim`]: `FOR UPDATE SKIP LOCKED`, so two workers never take the same row),
//! each claim with a lease that a heartbeat renews ([`PgStore::renew`]); a row whose lease
//! ran out (its worker died) is claimed again with the next `attempt`. A result is written
//! only by the claim that holds the row's current attempt with a live lease
//! ([`PgStore::submit`]); a late one is discarded, so nothing is counted twice.
//!
//! Wake-ups go through `LISTEN`/`NOTIFY` (channel [`PENDING`] for workers, [`DONE`] for the
//! driver), with polling as the fallback (an expired lease notifies no one).

use std::time::{Duration, Instant};

use postgres::fallible_iterator::FallibleIterator;

use crate::optimize::scores::CandidateScore;
use crate::optimize::scores::finite_or_worst;
use crate::optimize::space::Genome;
use crate::optimize::store::pg::PgStore;
use crate::optimize::store::{Place, StoreError, engine_scores_text, join, score_of};

/// Channel on which the driver announces pending evaluations.
pub const PENDING: &str = "proleg_pending";
/// Channel on which workers announce results (payload: the run id).
pub const DONE: &str = "proleg_done";

/// An evaluation a worker has claimed.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// The run.
    pub run: i64,
    /// The evaluation's number in the run.
    pub number: u64,
    /// Which claim of this row this is (1 for the first): the fencing token of the result.
    pub attempt: i32,
    /// The candidate.
    pub genome: Genome,
}

/// A candidate the driver puts in the queue.
#[derive(Debug, Clone, PartialEq)]
pub struct Pending {
    /// The evaluation's number in the run.
    pub number: u64,
    /// Its round.
    pub round: u64,
    /// The candidate.
    pub genome: Genome,
    /// Its parameter values.
    pub values: Vec<f64>,
}

impl PgStore {
    /// Subscribes this connection to `channel` ([`PENDING`] or [`DONE`]).
    pub fn listen(&mut self, channel: &str) -> Result<(), StoreError> {
        let fail = self.failer();
        let (name, statement) = match channel {
            PENDING => (PENDING, "LISTEN proleg_pending"),
            _ => (DONE, "LISTEN proleg_done"),
        };
        self.client.batch_execute(statement).map_err(&fail)?;
        if !self.listening.contains(&name) {
            self.listening.push(name);
        }
        Ok(())
    }

    /// Waits up to `timeout` for a notification on a channel this connection listens to.
    pub fn wait_notification(&mut self, timeout: Duration) -> Result<bool, StoreError> {
        let fail = self.failer();
        let mut n = self.client.notifications();
        let got = n.timeout_iter(timeout).next().map_err(&fail)?;
        // Several results may have been announced at once: take them all.
        while n.iter().next().map_err(&fail)?.is_some() {}
        Ok(got.is_some())
    }

    /// Writes candidates of `run` as pending (a row already holding the same candidate,
    /// e.g. left by a killed driver, is kept as it is) and wakes the workers.
    pub fn enqueue(&mut self, run: i64, seed: u64, items: &[Pending]) -> Result<(), StoreError> {
        let fail = self.failer();
        let mut tx = self.client.transaction().map_err(&fail)?;
        let st = tx
            .prepare(
                "INSERT INTO evaluations (run, number, round, genome, vals, seed, state)
                 VALUES ($1, $2, $3, $4, $5, $6, 'pending')
                 ON CONFLICT (run, number) DO UPDATE SET round = EXCLUDED.round,
                   genome = EXCLUDED.genome, vals = EXCLUDED.vals, seed = EXCLUDED.seed,
                   score = NULL, state = 'pending', worker = NULL, lease_until = NULL
                 WHERE evaluations.genome <> EXCLUDED.genome",
            )
            .map_err(&fail)?;
        for p in items {
            tx.execute(
                &st,
                &[
                    &run,
                    &(p.number as i64),
                    &(p.round as i64),
                    &join(&p.genome),
                    &join(&p.values),
                    &(seed as i64),
                ],
            )
            .map_err(&fail)?;
        }
        tx.batch_execute("NOTIFY proleg_pending").map_err(&fail)?;
        tx.commit().map_err(&fail)
    }

    /// Wakes every waiting worker (to look for work, or for its stop flag).
    pub fn wake_workers(&mut self) -> Result<(), StoreError> {
        let fail = self.failer();
        self.client
            .batch_execute("NOTIFY proleg_pending")
            .map_err(&fail)
    }

    /// Claims up to `n` pending (or lease-expired) evaluations for `worker`, lowest run
    /// and number first; `only_run` restricts the claim to one run, `refused` skips runs.
    pub fn claim(
        &mut self,
        worker: &str,
        lease: Duration,
        only_run: Option<i64>,
        refused: &[i64],
        n: i64,
    ) -> Result<Vec<Claim>, StoreError> {
        let fail = self.failer();
        let rows = self
            .client
            .query(
                "UPDATE evaluations e SET state = 'running', worker = $1, attempt = e.attempt + 1,
                        lease_until = now() + make_interval(secs => $2)
                 WHERE (e.run, e.number) IN (
                     SELECT run, number FROM evaluations
                     WHERE (state = 'pending' OR (state = 'running' AND lease_until < now()))
                       AND ($3::BIGINT IS NULL OR run = $3) AND NOT (run = ANY($4))
                     ORDER BY run, number
                     LIMIT $5
                     FOR UPDATE SKIP LOCKED)
                 RETURNING e.run, e.number, e.attempt, e.genome",
                &[&worker, &lease.as_secs_f64(), &only_run, &refused, &n],
            )
            .map_err(&fail)?;
        let store = self.target().to_string();
        rows.iter()
            .map(|r| {
                let run: i64 = r.try_get(0).map_err(&fail)?;
                let number = r.try_get::<_, i64>(1).map_err(&fail)? as u64;
                let place = Place {
                    store: &store,
                    run,
                    evaluation: Some(number),
                };
                Ok(Claim {
                    run,
                    number,
                    attempt: r.try_get(2).map_err(&fail)?,
                    genome: place.list("genome", r.try_get(3).map_err(&fail)?)?,
                })
            })
            .collect()
    }

    /// Extends the leases of every evaluation `worker` is running; returns how many.
    pub fn renew(&mut self, worker: &str, lease: Duration) -> Result<u64, StoreError> {
        let fail = self.failer();
        self.client
            .execute(
                "UPDATE evaluations SET lease_until = now() + make_interval(secs => $2)
                 WHERE worker = $1 AND state = 'running' AND lease_until >= now()",
                &[&worker, &lease.as_secs_f64()],
            )
            .map_err(&fail)
    }

    /// Writes a claimed evaluation's score; `false` when the claim was lost (its lease ran
    /// out and it may be claimed again): the result is then discarded.
    pub fn submit(
        &mut self,
        worker: &str,
        claim: &Claim,
        score: &CandidateScore,
        wall: f64,
    ) -> Result<bool, StoreError> {
        let fail = self.failer();
        let rows = self
            .client
            .query(
                "WITH done AS (
                     UPDATE evaluations SET state = 'done', score = $1, wall = $2, lease_until = NULL,
                       engine_scores = $7, rejected = $8, measures = $9
                     WHERE run = $3 AND number = $4 AND attempt = $5 AND worker = $6
                       AND state = 'running' AND lease_until >= now()
                     RETURNING run)
                 SELECT pg_notify('proleg_done', run::TEXT) FROM done",
                &[
                    &score_of(score.score),
                    &wall,
                    &claim.run,
                    &(claim.number as i64),
                    &claim.attempt,
                    &worker,
                    &engine_scores_text(&score.engines),
                    &score.rejected.as_ref().map(ToString::to_string),
                    &join(&score.measures),
                ],
            )
            .map_err(&fail)?;
        Ok(!rows.is_empty())
    }

    /// Gives a claim back untouched (a worker that cannot evaluate its run).
    pub fn release(&mut self, worker: &str, claim: &Claim) -> Result<(), StoreError> {
        let fail = self.failer();
        self.client
            .execute(
                "UPDATE evaluations SET state = 'pending', worker = NULL, lease_until = NULL
                 WHERE run = $1 AND number = $2 AND attempt = $3 AND worker = $4 AND state = 'running'",
                &[&claim.run, &(claim.number as i64), &claim.attempt, &worker],
            )
            .map(|_| ())
            .map_err(&fail)
    }

    /// The scores of `numbers` of `run` once all are done, waiting for results (this
    /// connection must listen to [`DONE`]); `on_wait(seconds)` is called while nothing
    /// arrives, every few seconds, and may stop the wait with an error.
    pub fn wait_scores<E: From<StoreError>>(
        &mut self,
        run: i64,
        numbers: &[u64],
        mut on_wait: impl FnMut(f64) -> Result<(), E>,
    ) -> Result<Vec<CandidateScore>, E> {
        let (Some(first), Some(last)) = (numbers.iter().min(), numbers.iter().max()) else {
            return Ok(Vec::new());
        };
        let fail = self.failer();
        let started = Instant::now();
        loop {
            let rows = self
                .client
                .query(
                    "SELECT number, score, measures, engine_scores FROM evaluations
                     WHERE run = $1 AND number BETWEEN $2 AND $3 AND state = 'done'",
                    &[&run, &(*first as i64), &(*last as i64)],
                )
                .map_err(&fail)?;
            let mut found = std::collections::HashMap::with_capacity(rows.len());
            for r in &rows {
                let number: i64 = r.try_get(0).map_err(&fail)?;
                let score: Option<f64> = r.try_get(1).map_err(&fail)?;
                let text: String = r.try_get(2).map_err(&fail)?;
                let place = Place {
                    store: &self.target().to_string(),
                    run,
                    evaluation: Some(number as u64),
                };
                let engines: String = r.try_get(3).map_err(&fail)?;
                found.insert(
                    number as u64,
                    CandidateScore {
                        score: finite_or_worst(score.unwrap_or(f64::NAN)),
                        engines: place.engines(&engines)?,
                        rejected: None,
                        measures: place.list("measures", &text)?,
                    },
                );
            }
            if numbers.iter().all(|n| found.contains_key(n)) {
                return Ok(numbers
                    .iter()
                    .map(|n| {
                        found
                            .remove(n)
                            .unwrap_or_else(|| CandidateScore::single(f64::NEG_INFINITY))
                    })
                    .collect());
            }
            if !self.wait_notification(Duration::from_secs(2))? {
                on_wait(started.elapsed().as_secs_f64())?;
            }
        }
    }

    /// Counts of `run`'s evaluations by state: (pending, running, done).
    pub fn queue_counts(&mut self, run: i64) -> Result<(u64, u64, u64), StoreError> {
        let fail = self.failer();
        let row = self
            .client
            .query_one(
                "SELECT COUNT(*) FILTER (WHERE state = 'pending'), COUNT(*) FILTER (WHERE state = 'running'),
                        COUNT(*) FILTER (WHERE state = 'done')
                 FROM evaluations WHERE run = $1",
                &[&run],
            )
            .map_err(&fail)?;
        let get = |i: usize| row.try_get::<_, i64>(i).map(|v| v as u64).map_err(&fail);
        Ok((get(0)?, get(1)?, get(2)?))
    }
}

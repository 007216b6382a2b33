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
/// Channel on which workers announce results (payload: `RUN:COUNT`, the run and how many
/// of its results one statement wrote).
pub const DONE: &str = "proleg_done";

/// A run's queue: evaluations waiting, evaluations claimed, and the workers.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct QueueState {
    /// Evaluations no worker holds.
    pub pending: u64,
    /// Evaluations claimed and not written yet.
    pub running: u64,
    /// Every worker that claimed one of the run's evaluations.
    pub workers: Vec<WorkerLease>,
}

/// A worker of one run, as its rows in the queue show it.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkerLease {
    /// Its name (host, process).
    pub worker: String,
    /// Evaluations it holds now.
    pub running: u64,
    /// Evaluations of the run it wrote.
    pub done: u64,
    /// When its lease on what it holds ends, in seconds since 1970 by the database's clock
    /// (its heartbeat moves it on; `None`: it holds nothing).
    pub lease_until: Option<f64>,
}

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

/// A claim's result on its way to the store.
#[derive(Debug, Clone, Copy)]
pub struct ClaimResult<'a> {
    /// The claim it answers.
    pub claim: &'a Claim,
    /// Its score.
    pub score: &'a CandidateScore,
    /// Wall seconds of the episode.
    pub wall: f64,
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

/// A round's candidates as pending rows (kept when a row already holds the same candidate).
const ENQUEUE: &str = "WITH queued AS (
     INSERT INTO evaluations (run, number, round, genome, vals, seed, state)
     SELECT $1, q.number, q.round, q.genome, q.vals, $6, 'pending'
     FROM unnest($2::BIGINT[], $3::BIGINT[], $4::TEXT[], $5::TEXT[]) AS q(number, round, genome, vals)
     ON CONFLICT (run, number) DO UPDATE SET round = EXCLUDED.round,
       genome = EXCLUDED.genome, vals = EXCLUDED.vals, seed = EXCLUDED.seed,
       score = NULL, state = 'pending', worker = NULL, lease_until = NULL
     WHERE evaluations.genome <> EXCLUDED.genome
     RETURNING 1)
 SELECT pg_notify('proleg_pending', '')";

/// Up to `$4` pending (or lease-expired) evaluations of any run but those of `$3`, claimed
/// for worker `$1` with a lease of `$2` s (lowest run and number first).
const CLAIM_ANY: &str =
    "UPDATE evaluations e SET state = 'running', worker = $1, attempt = e.attempt + 1,
        lease_until = now() + make_interval(secs => $2)
 WHERE (e.run, e.number) IN (
     SELECT run, number FROM evaluations
     WHERE state <> 'done' AND (state = 'pending' OR lease_until < now())
       AND NOT (run = ANY($3))
     ORDER BY run, number
     LIMIT $4
     FOR UPDATE SKIP LOCKED)
 RETURNING e.run, e.number, e.attempt, e.genome";

/// The same for run `$3` only (the driver's own threads): its own statement, so that the
/// plan looks up that run alone.
const CLAIM_RUN: &str =
    "UPDATE evaluations e SET state = 'running', worker = $1, attempt = e.attempt + 1,
        lease_until = now() + make_interval(secs => $2)
 WHERE (e.run, e.number) IN (
     SELECT run, number FROM evaluations
     WHERE run = $3 AND state <> 'done' AND (state = 'pending' OR lease_until < now())
     ORDER BY number
     LIMIT $4
     FOR UPDATE SKIP LOCKED)
 RETURNING e.run, e.number, e.attempt, e.genome";

/// Results written where their claim still holds; the rows taken, and the drivers woken.
const SUBMIT: &str = "WITH r AS (
     SELECT * FROM unnest($2::BIGINT[], $3::BIGINT[], $4::INT[], $5::FLOAT8[], $6::FLOAT8[],
                          $7::TEXT[], $8::TEXT[], $9::TEXT[])
       AS r(run, number, attempt, score, wall, engines, rejected, measures)),
 done AS (
     UPDATE evaluations e SET state = 'done', score = r.score, wall = r.wall, lease_until = NULL,
       engine_scores = r.engines, rejected = r.rejected, measures = r.measures
     FROM r
     WHERE e.run = r.run AND e.number = r.number AND e.attempt = r.attempt AND e.worker = $1
       AND e.state = 'running' AND e.lease_until >= now()
     RETURNING e.run, e.number),
 woken AS (SELECT pg_notify('proleg_done', run::TEXT || ':' || n::TEXT)
            FROM (SELECT run, COUNT(*) AS n FROM done GROUP BY run) d)
 SELECT run, number FROM done, (SELECT COUNT(*) FROM woken) w";

/// The driver looks in the store at least this often while it waits for a round.
const LOOK_AT_LEAST: Duration = Duration::from_secs(2);

/// The scores of those of `$2` (numbers of run `$1`) that are done.
const DONE_SCORES: &str = "SELECT number, score, measures, engine_scores FROM evaluations
 WHERE run = $1 AND number = ANY($2) AND state = 'done'";

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

    /// Waits up to `timeout` for results of `run` announced on [`DONE`]; how many arrived
    /// (`None`: a notification that did not say, or none came — then look in the store).
    fn wait_done(&mut self, run: i64, timeout: Duration) -> Result<Option<u64>, StoreError> {
        let fail = self.failer();
        let mut n = self.client.notifications();
        let Some(first) = n.timeout_iter(timeout).next().map_err(&fail)? else {
            return Ok(None);
        };
        let mut count = Some(0u64);
        let mut add = |payload: &str| {
            let said = payload
                .split_once(':')
                .and_then(|(r, k)| Some((r.parse::<i64>().ok()?, k.parse::<u64>().ok()?)));
            count = match (count, said) {
                (Some(c), Some((r, k))) if r == run => Some(c + k),
                (c, Some(_)) => c,
                (_, None) => None,
            };
        };
        add(first.payload());
        // Several results may have been announced at once: take them all.
        while let Some(more) = n.iter().next().map_err(&fail)? {
            add(more.payload());
        }
        Ok(count)
    }

    /// Writes candidates of `run` as pending (a row already holding the same candidate,
    /// e.g. left by a killed driver, is kept as it is) and wakes the workers: one statement
    /// for the whole round.
    pub fn enqueue(&mut self, run: i64, seed: u64, items: &[Pending]) -> Result<(), StoreError> {
        let fail = self.failer();
        let numbers: Vec<i64> = items.iter().map(|p| p.number as i64).collect();
        let rounds: Vec<i64> = items.iter().map(|p| p.round as i64).collect();
        let genomes: Vec<String> = items.iter().map(|p| join(&p.genome)).collect();
        let values: Vec<String> = items.iter().map(|p| join(&p.values)).collect();
        let st = self.prepared(ENQUEUE)?;
        self.client
            .execute(
                &st,
                &[&run, &numbers, &rounds, &genomes, &values, &(seed as i64)],
            )
            .map_err(&fail)?;
        Ok(())
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
        let lease = lease.as_secs_f64();
        let rows = match only_run {
            Some(run) => {
                let st = self.prepared(CLAIM_RUN)?;
                self.client.query(&st, &[&worker, &lease, &run, &n])
            }
            None => {
                let st = self.prepared(CLAIM_ANY)?;
                self.client.query(&st, &[&worker, &lease, &refused, &n])
            }
        }
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
        let accepted = self.submit_many(worker, &[ClaimResult { claim, score, wall }])?;
        Ok(accepted.first().copied().unwrap_or(false))
    }

    /// Writes the scores of several claims in one statement, each only if its claim still
    /// holds (its attempt, with a live lease); says for each whether it was taken, and wakes
    /// the driver of each run written to.
    pub fn submit_many(
        &mut self,
        worker: &str,
        results: &[ClaimResult<'_>],
    ) -> Result<Vec<bool>, StoreError> {
        if results.is_empty() {
            return Ok(Vec::new());
        }
        let fail = self.failer();
        let runs: Vec<i64> = results.iter().map(|r| r.claim.run).collect();
        let numbers: Vec<i64> = results.iter().map(|r| r.claim.number as i64).collect();
        let attempts: Vec<i32> = results.iter().map(|r| r.claim.attempt).collect();
        let scores: Vec<Option<f64>> = results.iter().map(|r| score_of(r.score.score)).collect();
        let walls: Vec<f64> = results.iter().map(|r| r.wall).collect();
        let engines: Vec<String> = results
            .iter()
            .map(|r| engine_scores_text(&r.score.engines))
            .collect();
        let rejected: Vec<Option<String>> = results
            .iter()
            .map(|r| r.score.rejected.as_ref().map(ToString::to_string))
            .collect();
        let measures: Vec<String> = results.iter().map(|r| join(&r.score.measures)).collect();
        let st = self.prepared(SUBMIT)?;
        let rows = self
            .client
            .query(
                &st,
                &[
                    &worker, &runs, &numbers, &attempts, &scores, &walls, &engines, &rejected,
                    &measures,
                ],
            )
            .map_err(&fail)?;
        let mut taken = std::collections::HashSet::with_capacity(rows.len());
        for r in &rows {
            let run: i64 = r.try_get(0).map_err(&fail)?;
            let number: i64 = r.try_get(1).map_err(&fail)?;
            taken.insert((run, number));
        }
        Ok(runs
            .iter()
            .zip(&numbers)
            .map(|(r, n)| taken.contains(&(*r, *n)))
            .collect())
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
        let fail = self.failer();
        let started = Instant::now();
        let mut found = std::collections::HashMap::with_capacity(numbers.len());
        let mut missing: Vec<i64> = numbers.iter().map(|n| *n as i64).collect();
        // Look in the store first, then each time the results announced for this run
        // could complete the round, or a notification did not say how many, or
        // [`LOOK_AT_LEAST`] has passed: one look per round rather than one per batch written.
        let mut announced = u64::MAX;
        let mut last_look = Instant::now();
        while !missing.is_empty() {
            if announced >= missing.len() as u64 || last_look.elapsed() >= LOOK_AT_LEAST {
                last_look = Instant::now();
                let st = self.prepared(DONE_SCORES)?;
                let rows = self.client.query(&st, &[&run, &missing]).map_err(&fail)?;
                for r in &rows {
                    let number: i64 = r.try_get(0).map_err(&fail)?;
                    found.insert(number as u64, self.read_score(run, r)?);
                }
                missing.retain(|n| !found.contains_key(&(*n as u64)));
                announced = 0;
                if missing.is_empty() {
                    break;
                }
            }
            match self.wait_done(run, LOOK_AT_LEAST)? {
                Some(k) => announced = announced.saturating_add(k),
                None => {
                    announced = u64::MAX;
                    on_wait(started.elapsed().as_secs_f64())?;
                }
            }
        }
        Ok(numbers
            .iter()
            .map(|n| {
                found
                    .remove(n)
                    .unwrap_or_else(|| CandidateScore::single(f64::NEG_INFINITY))
            })
            .collect())
    }

    /// The score of a row of [`DONE_SCORES`].
    fn read_score(&self, run: i64, r: &postgres::Row) -> Result<CandidateScore, StoreError> {
        let fail = self.failer();
        let number: i64 = r.try_get(0).map_err(&fail)?;
        let score: Option<f64> = r.try_get(1).map_err(&fail)?;
        let text: String = r.try_get(2).map_err(&fail)?;
        let engines: String = r.try_get(3).map_err(&fail)?;
        let place = Place {
            store: &self.target().to_string(),
            run,
            evaluation: Some(number as u64),
        };
        Ok(CandidateScore {
            score: finite_or_worst(score.unwrap_or(f64::NAN)),
            engines: place.engines(&engines)?,
            rejected: None,
            measures: place.list("measures", &text)?,
        })
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

    /// Where `run`'s queue stands: evaluations pending and running, and every worker that
    /// claimed one of them, with what it runs and when its lease (renewed by its heartbeat
    /// every third of a lease) ends.
    pub fn queue_state(&mut self, run: i64) -> Result<QueueState, StoreError> {
        let fail = self.failer();
        let rows = self
            .client
            .query(
                "SELECT worker, COUNT(*) FILTER (WHERE state = 'running'),
                        COUNT(*) FILTER (WHERE state = 'done'),
                        EXTRACT(EPOCH FROM MAX(lease_until) FILTER (WHERE state = 'running'))::float8
                 FROM evaluations WHERE run = $1 AND worker IS NOT NULL
                 GROUP BY worker ORDER BY worker",
                &[&run],
            )
            .map_err(&fail)?;
        let workers = rows
            .iter()
            .map(|r| {
                Ok(WorkerLease {
                    worker: r.try_get(0).map_err(&fail)?,
                    running: r.try_get::<_, i64>(1).map_err(&fail)? as u64,
                    done: r.try_get::<_, i64>(2).map_err(&fail)? as u64,
                    lease_until: r.try_get(3).map_err(&fail)?,
                })
            })
            .collect::<Result<Vec<_>, StoreError>>()?;
        let (pending, running, _) = self.queue_counts(run)?;
        Ok(QueueState {
            pending,
            running,
            workers,
        })
    }
}

//! How a run's candidates get their scores, behind one interface ([`Scorer`]): simulated
//! on this host's threads ([`crate::optimize::local::LocalScorer`]) or put in a shared
//! store's queue for workers on any host
//! ([`crate::optimize::shared::queue::QueueScorer`]). Either way every score is stored as
//! it comes, and a candidate an interrupted attempt already stored (same number and
//! genome) is reused, not run again. `session::scorer_for` is the one place that tells
//! the two apart, from the store the run records into.

use crate::optimize::error::OptimizeError;
use crate::optimize::scores::{CandidateScore, StoredEval};
use crate::optimize::space::Genome;
use crate::optimize::store::Store;

/// Where a run stores its evaluations, and what it already holds (for `--resume`).
pub struct Recording<'a> {
    /// The experiment store.
    pub store: &'a mut Store,
    /// The run's id in the store.
    pub run: i64,
    /// Evaluations stored by an earlier, interrupted attempt of this run, sorted by
    /// number (as [`crate::optimize::store::ExperimentStore::evaluations`] returns them).
    pub known: Vec<StoredEval>,
    /// Testing aid for resumption: abort the process (no clean-up, like `kill -9`) right
    /// after the batch that brings this call's stored evaluations to this many.
    pub crash_after: Option<u64>,
}

/// A round of candidates to score.
#[derive(Debug, Clone, Copy)]
pub struct Round<'a> {
    /// The first candidate's evaluation number.
    pub first: u64,
    /// The round's number (GA generation, great-deluge batch, ...).
    pub number: u64,
    /// The candidates, in the optimizer's order.
    pub candidates: &'a [Genome],
}

/// How candidates were spread over worlds and hosts, and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Batching {
    /// Robots per world, as the user gave it.
    Given(usize),
    /// One world per candidate: no round was large enough to measure the alternative.
    Unmeasured,
    /// Measured on the first large round: candidates per second with one world each
    /// (`alone`) and with `robots` robots per world (`shared`), and which was kept.
    Measured {
        /// Whether robots share worlds from then on.
        share: bool,
        /// Candidates per second, one world each.
        alone: f64,
        /// Candidates per second with `robots` per world.
        shared: f64,
        /// Robots per world in the shared part.
        robots: usize,
    },
    /// One world per candidate through a shared store, with this many local worker
    /// threads beside the remote workers.
    SharedStore(usize),
}

impl std::fmt::Display for Batching {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Batching::Given(n) => write!(f, "{n} robots per world (given)"),
            Batching::Unmeasured => {
                write!(f, "one world per candidate (rounds too small to measure)")
            }
            Batching::Measured {
                share,
                alone,
                shared,
                robots,
            } => write!(
                f,
                "{} (measured {alone:.2} candidates/s alone, {shared:.2} with {robots} robots per world)",
                if share {
                    "robots share worlds"
                } else {
                    "one world per candidate"
                }
            ),
            Batching::SharedStore(local) => write!(
                f,
                "one world per candidate, through the shared store ({local} local worker thread(s))"
            ),
        }
    }
}

/// How a run's candidates were scored, for its report.
#[derive(Debug, Clone, PartialEq)]
pub struct ScoringSummary {
    /// How candidates were spread over worlds and hosts, and why.
    pub batching: Batching,
    /// Evaluations simulated in this call (the rest came from the store).
    pub simulated: u64,
}

/// Scores rounds of candidates and records them.
pub trait Scorer {
    /// The scores of the round's candidates, in order (a failed episode scores `-inf`).
    fn score(&mut self, round: &Round<'_>) -> Result<Vec<CandidateScore>, OptimizeError>;

    /// Ends the call: stops helpers and, when the optimizer `finished` (it was not
    /// stopped early), marks the run finished in its store; a stopped run stays
    /// unfinished, for `--resume`.
    fn finish(self: Box<Self>, finished: bool) -> Result<ScoringSummary, OptimizeError>;
}

/// The scores an interrupted attempt stored for the round's candidates (same number and
/// genome; `None` for the others), and the indices of the candidates still to score.
pub fn reuse_stored(
    known: &[StoredEval],
    round: &Round<'_>,
) -> (Vec<Option<CandidateScore>>, Vec<usize>) {
    let mut scores = vec![None; round.candidates.len()];
    let mut missing = Vec::new();
    for (i, g) in round.candidates.iter().enumerate() {
        let number = round.first + i as u64;
        // Batches may finish out of order: look the number up, do not index.
        let stored = known
            .binary_search_by_key(&number, |k| k.number)
            .ok()
            .map(|at| &known[at])
            .filter(|k| k.genome == *g);
        match stored {
            Some(k) => {
                scores[i] = Some(CandidateScore {
                    score: if k.score.is_nan() {
                        f64::NEG_INFINITY
                    } else {
                        k.score
                    },
                    engines: k.engines.clone(),
                    rejected: None,
                    measures: k.measures.clone(),
                });
            }
            None => missing.push(i),
        }
    }
    (scores, missing)
}

/// The round's scores once every candidate has one (a hole, which no scorer leaves,
/// scores `-inf`).
pub fn complete(scores: Vec<Option<CandidateScore>>) -> Vec<CandidateScore> {
    scores
        .into_iter()
        .map(|s| s.unwrap_or_else(|| CandidateScore::single(f64::NEG_INFINITY)))
        .collect()
}

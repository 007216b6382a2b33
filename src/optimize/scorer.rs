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

/// How a run's candidates were scored, for its report.
#[derive(Debug, Clone, PartialEq)]
pub struct ScoringSummary {
    /// How candidates were spread over worlds and hosts, and why.
    pub batching: String,
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

//! The neutral records the optimize layer passes between its parts: a candidate's score as
//! an evaluation gives it ([`CandidateScore`]) and an evaluation as a store keeps it
//! ([`StoredEval`]). The evaluator, the scorers, the stores and the queue all speak them,
//! and they import nothing of those parts.

use crate::config::simulation::EngineKind;
use crate::optimize::design::Rejection;
use crate::optimize::space::Genome;

/// One candidate's score, and with cross-engine scores its score on each engine.
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateScore {
    /// The score the optimizer sees (the engines' scores combined).
    pub score: f64,
    /// Each engine's score, in the optimizer file's order (empty on one engine).
    pub engines: Vec<(EngineKind, f64)>,
    /// Why the candidate was rejected (a co-design body not run, a module failed during
    /// its episode; its score is then `-inf`).
    pub rejected: Option<Rejection>,
    /// The quantities measured in its episode (MAP-Elites' measured descriptors; of the
    /// first engine with cross-engine scores, averaged over robust fitness's episodes).
    pub measures: Vec<f64>,
}

impl CandidateScore {
    /// A score on the simulation's one engine.
    pub fn single(score: f64) -> CandidateScore {
        CandidateScore {
            score,
            engines: Vec::new(),
            rejected: None,
            measures: Vec::new(),
        }
    }

    /// A body rejected unrun: `-inf`, with its reason.
    pub fn rejected(why: Rejection) -> CandidateScore {
        CandidateScore {
            score: f64::NEG_INFINITY,
            engines: Vec::new(),
            rejected: Some(why),
            measures: Vec::new(),
        }
    }
}

/// One stored evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredEval {
    /// 0-based evaluation number.
    pub number: u64,
    /// Round it belonged to.
    pub round: u64,
    /// The candidate.
    pub genome: Genome,
    /// Its parameter values.
    pub values: Vec<f64>,
    /// Its score.
    pub score: f64,
    /// Its score on each engine, when the run scores on several (`<engines>`).
    pub engines: Vec<(EngineKind, f64)>,
    /// Why it was rejected (a co-design body unrun, a module failed during its episode; its
    /// score is then `-inf`).
    pub rejected: Option<String>,
    /// The quantities measured in its episode (MAP-Elites' measured descriptors; else
    /// empty).
    pub measures: Vec<f64>,
    /// Wall seconds of its evaluation (a batch's shared by its candidates).
    pub wall: f64,
}

/// A score as stored: a failed episode (NaN) is `-inf`.
pub fn finite_or_worst(score: f64) -> f64 {
    if score.is_nan() {
        f64::NEG_INFINITY
    } else {
        score
    }
}

//! What a worker does with a stored run's claims: an optimization run's candidates are
//! scored by its [`Evaluator`], a suite run's evaluations are episodes of its controller
//! on its courses ([`CourseEpisodes`]). Both come from the run's stored files alone.

use crate::control::ModuleRegistry;
use crate::optimize::error::UnevaluableRun;
use crate::optimize::evaluate::{EvalError, Evaluator};
use crate::optimize::scores::CandidateScore;
use crate::optimize::shared::run_evaluator;
use crate::optimize::shared::suite_job::{CourseEpisodes, SuiteJob};
use crate::optimize::space::Genome;
use crate::optimize::store::RunSpec;
use crate::signal::StopFlag;

/// A stored run's work, as a worker runs it.
pub enum RunWork {
    /// An optimization run: each evaluation a candidate.
    Candidates(Evaluator),
    /// A suite run: each evaluation an episode.
    Courses(CourseEpisodes),
}

impl RunWork {
    /// The work of stored run `spec`, built with this host's module types; an error says
    /// why this host cannot do it.
    pub fn of(spec: &RunSpec, registry: &ModuleRegistry) -> Result<RunWork, UnevaluableRun> {
        Ok(match SuiteJob::of(&spec.info) {
            Some(job) => RunWork::Courses(CourseEpisodes::of(spec, &job, registry)?),
            None => RunWork::Candidates(run_evaluator(spec, registry)?),
        })
    }

    /// The same work, abandoning an episode in flight when `stop` is raised.
    pub fn with_stop(self, stop: StopFlag) -> RunWork {
        match self {
            RunWork::Candidates(e) => RunWork::Candidates(Evaluator { stop, ..e }),
            RunWork::Courses(c) => RunWork::Courses(c.with_stop(stop)),
        }
    }

    /// The stored score of one claimed evaluation.
    pub fn score(&self, genome: &Genome) -> Result<CandidateScore, EvalError> {
        match self {
            RunWork::Candidates(e) => e
                .run_batch_scored(std::slice::from_ref(genome))?
                .pop()
                .ok_or(EvalError::Empty),
            RunWork::Courses(c) => c.run(genome),
        }
    }
}

//! Shared evaluation: one optimization spread over many processes and hosts through a
//! PostgreSQL store.
//!
//! The optimizing process is the **driver** (it owns the optimizer's state): each round it
//! writes the candidates still to score as pending evaluations ([`driver`]) and waits for
//! their scores, read back in candidate order. **Workers** ([`worker`]) claim pending
//! evaluations, run each as a seeded headless episode in a world of its own, and write the
//! score: the driver's own threads, and `proleg worker --store URL` on any host, which needs
//! nothing but the URL: the run's configuration files are in the store ([`run_evaluator`]).
//!
//! The control window follows a run read-only as it goes ([`follow`]); [`ceiling`]
//! measures how many evaluations per second the store itself can coordinate.
//!
//! Each episode is a pure function of the stored configuration, the run's seed and the
//! candidate, so the scores, and therefore every later candidate, are the same whoever
//! evaluates them.
//! [`queue`] is the driver's scorer over the store's queue.
//!
//! A suite run (`proleg suite --store`) goes through the same queue: its evaluations are
//! episodes of one controller on the suite's courses ([`suite_job`]); a worker does
//! whichever a claim's run asks for ([`work::RunWork`]).

pub mod ceiling;
pub mod driver;
pub mod follow;
pub mod queue;
pub mod suite_job;
pub mod work;
pub mod worker;

use std::path::Path;

use crate::config::fitness::Fitness;
use crate::config::simulation::EngineKind;
use crate::config::{MemSource, Simulation, load_simulation_with};
use crate::control::ModuleRegistry;
use crate::optimize::error::UnevaluableRun;
use crate::optimize::evaluate::{Evaluator, scoring_engines};
use crate::optimize::prepare::prepare;
use crate::optimize::space::SearchSpace;
use crate::optimize::store::{RunSpec, program_version};

/// A stored run's simulation, loaded from its stored files with this host's module types.
pub fn stored_simulation(
    spec: &RunSpec,
    registry: &ModuleRegistry,
) -> Result<Simulation, UnevaluableRun> {
    let mut src = MemSource::new();
    for (path, text) in &spec.files {
        src.insert(path, text.as_str());
    }
    Ok(load_simulation_with(
        &src,
        Path::new(&spec.info.config),
        registry,
    )?)
}

/// An error for a suite run, whose evaluations are episodes, not candidates: what
/// exports, replays and evaluators ask before reading a stored run's candidates.
pub fn candidate_run(spec: &RunSpec) -> Result<(), UnevaluableRun> {
    match suite_job::SuiteJob::of(&spec.info) {
        Some(_) => Err(UnevaluableRun::SuiteRun),
        None => Ok(()),
    }
}

/// The evaluator of a stored run, built from its stored files with this host's module
/// types; an error says why this host cannot evaluate it (another program version, a
/// module type it lacks, a configuration that does not load).
pub fn run_evaluator(
    spec: &RunSpec,
    registry: &ModuleRegistry,
) -> Result<Evaluator, UnevaluableRun> {
    candidate_run(spec)?;
    let here = program_version();
    if spec.program != here {
        return Err(UnevaluableRun::Version {
            started: spec.program.clone(),
            here,
        });
    }
    let sim = stored_simulation(spec, registry)?;
    if scoring_engines(&sim).contains(&EngineKind::Mujoco)
        && let Err(e) = crate::sim::engine::ready(EngineKind::Mujoco)
    {
        return Err(UnevaluableRun::NoMujoco(e.to_string()));
    }
    let (space, _) = prepare(&sim, registry).map_err(|e| UnevaluableRun::Setup(Box::new(e)))?;
    let genes: Vec<String> = space.genes.iter().map(|g| g.label()).collect();
    if genes != spec.info.genes {
        return Err(UnevaluableRun::Genes {
            here: genes.join(", "),
            stored: spec.info.genes.join(", "),
        });
    }
    stored_evaluator(spec, &sim, &space, registry)
}

/// The evaluator of a stored run's candidates in `sim` (its stored simulation): the run's
/// fitness, episode duration and seed, and the randomized episodes its optimizer file asks
/// for.
pub fn stored_evaluator(
    spec: &RunSpec,
    sim: &Simulation,
    space: &SearchSpace,
    registry: &ModuleRegistry,
) -> Result<Evaluator, UnevaluableRun> {
    let fitness = Fitness::parse(&spec.info.fitness)?;
    let mut files = MemSource::new();
    for (path, text) in &spec.files {
        files.insert(path, text.as_str());
    }
    Ok(Evaluator::new(
        sim,
        registry,
        space,
        fitness,
        spec.info.duration,
        spec.info.seed,
    )
    .with_files(std::sync::Arc::new(files)))
}

//! A simulation's optimization prepared: its search space (the parameters its optimizer
//! file registers, or a co-design's genes) and the configured start candidate. Read by the
//! run, by workers checking a stored run and by the control window.

use crate::config::Simulation;
use crate::control::{ControlKernel, ModuleRegistry};
use crate::optimize::design::DesignSpace;
use crate::optimize::error::OptimizeError;
use crate::optimize::space::{Genome, SearchSpace};

/// The configured start candidate and the search space of `sim`, whose modules
/// `registry` creates.
pub fn prepare(
    sim: &Simulation,
    registry: &ModuleRegistry,
) -> Result<(SearchSpace, Genome), OptimizeError> {
    let model = sim
        .optimizer
        .as_ref()
        .ok_or_else(|| OptimizeError::NoOptimizer {
            file: sim.file.clone(),
            mode: sim.files.simulation.properties.mode.name().to_string(),
        })?;
    if let Some(design) = DesignSpace::from_model(model) {
        // Bodies and gaits start from the middle of every gene's range.
        let space = design.search_space();
        let start = space.genes.iter().map(|g| g.alleles.count() / 2).collect();
        return Ok((space, start));
    }
    let limits = sim.robot.joints.iter().map(|j| j.limits_deg).collect();
    let kernel = ControlKernel::from_actuation(&sim.actuation, registry, limits)?;
    // A module that cannot run on the robot is refused before the first candidate.
    crate::sim::spawn::check_modules(sim, &kernel)
        .map_err(|e| OptimizeError::Eval(crate::optimize::evaluate::EvalError::Sim(e)))?;
    let space = SearchSpace::from_model(model, &kernel)?;
    if space.genes.is_empty() {
        return Err(OptimizeError::NothingRegistered {
            file: model.file.clone(),
        });
    }
    let start = space.encode_kernel(&kernel);
    Ok((space, start))
}

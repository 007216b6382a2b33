//! One optimization run in one call ([`optimize`]: a [`Session`] prepared and run), and the
//! names a run's callers use.

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::store::Store;

pub use crate::optimize::prepare::prepare;
pub use crate::optimize::scorer::Recording;
pub use crate::optimize::session::{Evaluation, RunOutcome, Session, check_workers};
pub use crate::optimize::settings::{RunChoices, RunSettings};

/// Prepares and runs the optimization of `sim` ([`Session::prepare`], [`Session::run`]).
pub fn optimize(
    sim: &Simulation,
    settings: &RunSettings,
    registry: &ModuleRegistry,
    recording: Option<Recording<'_>>,
    on_eval: impl FnMut(&Evaluation),
) -> Result<RunOutcome, OptimizeError> {
    let shared = matches!(
        recording.as_ref().map(|r| &*r.store),
        Some(Store::Postgres(_))
    );
    Session::prepare(sim, settings, registry, shared)?.run(registry, recording, on_eval)
}

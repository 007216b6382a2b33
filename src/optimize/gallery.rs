//! Which designs a gallery shows (`proleg results --gallery`): a co-design run's best
//! bodies, each once (its best-scoring evaluation), best first. The pictures themselves are
//! rendered by the GUI layer (`gui::video::gallery`).

use crate::control::ModuleRegistry;
use crate::optimize::archive::stored_run;
use crate::optimize::design::DesignSpace;
use crate::optimize::error::OptimizeError;
use crate::optimize::store::Store;

/// One design of a gallery.
#[derive(Debug, Clone, PartialEq)]
pub struct GalleryEntry {
    /// The evaluation shown (the body's best).
    pub number: u64,
    /// Its score.
    pub score: f64,
    /// Its body in one phrase (`8 modules yppyppp plain`).
    pub body: String,
}

/// The best `count` distinct bodies of co-design run `run`, best first (ties: the earlier
/// evaluation); bodies rejected unrun and failed episodes are left out.
pub fn best_designs(
    store: &mut Store,
    run: i64,
    count: usize,
    registry: &ModuleRegistry,
) -> Result<Vec<GalleryEntry>, OptimizeError> {
    let sim = stored_run(store, run, registry)?;
    let design = sim
        .optimizer
        .as_ref()
        .and_then(DesignSpace::from_model)
        .ok_or(OptimizeError::CoDesign(
            "a gallery shows the bodies of a co-design run (an optimizer file with <morphology>); this run has one body",
        ))?;
    let mut evaluations: Vec<_> = store
        .evaluations(run)?
        .into_iter()
        .filter(|e| e.score.is_finite() && e.rejected.is_none())
        .collect();
    evaluations.sort_by(|a, b| b.score.total_cmp(&a.score).then(a.number.cmp(&b.number)));
    let mut out: Vec<GalleryEntry> = Vec::with_capacity(count);
    for e in evaluations {
        if out.len() == count {
            break;
        }
        let body = design.body(&e.genome, "design").summary();
        if out.iter().all(|o| o.body != body) {
            out.push(GalleryEntry {
                number: e.number,
                score: e.score,
                body,
            });
        }
    }
    Ok(out)
}

//! `proleg optimize` in-process, as the tests run it: two workers, quiet, into a store.

use proleg::cli::optimize::{OptimizeOptions, OptimizeReport, run};
use proleg::control::ModuleRegistry;

/// `proleg optimize CONFIG` (from the repository root) for `evals` evaluations of
/// `duration` s with seed `seed` into `store`.
pub fn optimize(config: &str, store: &str, seed: u64, evals: u64, duration: f64) -> OptimizeReport {
    let o = OptimizeOptions {
        config: super::root().join(config),
        seed: Some(seed),
        workers: Some(2),
        batch: 1,
        max_evaluations: Some(evals),
        duration: Some(duration),
        fitness: None,
        out: None,
        evaluations: None,
        store: Some(store.to_string()),
        resume: false,
        lease: None,
        quiet: true,
        crash_after: None,
        engine: None,
    };
    run(&o, &ModuleRegistry::standard()).expect("the optimization runs")
}

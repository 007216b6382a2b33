//! `proleg optimize` in-process, as the tests run it: two workers, quiet, into a store;
//! and the check that a stored score is the mean of its episodes replayed from the store.

use proleg::cli::optimize::{OptimizeOptions, OptimizeReport, run};
use proleg::control::ModuleRegistry;
use proleg::optimize::replay::load_replay;
use proleg::optimize::robust::combine;
use proleg::optimize::store::Store;

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

/// Every stored evaluation of `run` scores the mean of its `episodes` episodes, each
/// replayed from the store, and the episodes differ (by more than `spread` m).
pub fn assert_scores_are_episode_means(s: &mut Store, run: i64, episodes: u32, spread: f64) {
    let registry = ModuleRegistry::standard();
    for e in s.evaluations(run).expect("evaluations") {
        let scores: Vec<f64> = (0..episodes)
            .map(|k| {
                load_replay(s, run, e.number, Some(k), &registry)
                    .and_then(|r| r.score())
                    .expect("episode")
            })
            .collect();
        assert_eq!(combine(&scores, None), e.score, "evaluation {}", e.number);
        let found = scores.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - scores.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(found > spread, "the episodes differ: {scores:?}");
    }
}

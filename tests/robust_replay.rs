//! Robust fitness and replay: a stored evaluation replayed from the store scores
//! exactly what the optimization stored; a robust candidate's score is the mean of its
//! randomized episodes, whose seeds are in the store; randomized episodes really differ; a
//! random start is drawn from the seed.

mod common;

use common::optimize::{assert_scores_are_episode_means, optimize};
use proleg::control::ModuleRegistry;
use proleg::optimize::replay::{ReplayError, Which, load_replay, randomized_check, replay_from};
use proleg::optimize::store::StoreError;
use proleg::optimize::store::{Store, StoreLocation};
use proleg::sim::randomize::episode_seeds;

fn open(store: &str) -> Store {
    Store::open_existing(&StoreLocation::parse(store).expect("location")).expect("store")
}

#[test]
fn a_replayed_evaluation_scores_what_the_optimization_stored() {
    let dir = common::scratch("replay");
    let store = dir.join("r.sqlite").display().to_string();
    let report = optimize(
        "configs/gait_from_scratch_cmaes.simulation.xml",
        &store,
        4,
        12,
        3.0,
    );
    let registry = ModuleRegistry::standard();
    let mut s = open(&store);
    let stored = s.evaluations(report.store.1).expect("evaluations");
    assert_eq!(stored.len(), 12);
    let mut distinct = 0;
    for e in &stored {
        let r = load_replay(&mut s, report.store.1, e.number, None, &registry).expect("replay");
        assert_eq!(r.genome, e.genome);
        let replayed = r.score().expect("replayed");
        assert_eq!(replayed, e.score, "evaluation {}", e.number);
        distinct += usize::from((e.score - stored[0].score).abs() > 1e-6);
    }
    assert!(distinct > 5, "the candidates moved differently");
    // "best" is the highest stored score.
    let best = replay_from(&store, report.store.1, Which::Best, None, &registry).expect("best");
    assert_eq!(best.stored_score, report.outcome.best_score);
    // Bad requests say what is wrong, each with its own variant.
    let err = |r: Result<_, ReplayError>| r.expect_err("an error");
    let e = err(replay_from(&store, 99, Which::Best, None, &registry).map(|_| ()));
    assert!(
        matches!(e, ReplayError::NoEvaluation { run: 99, .. }),
        "{e}"
    );
    let e = err(replay_from(&store, 1, Which::Number(500), None, &registry).map(|_| ()));
    assert!(
        matches!(
            e,
            ReplayError::NoEvaluation {
                number: Some(500),
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("no finished evaluation 500"), "{e}");
    let e = err(replay_from(&store, 1, Which::Number(3), Some(2), &registry).map(|_| ()));
    assert!(
        matches!(e, ReplayError::NoEpisodes { episode: 2, .. }),
        "{e}"
    );
    let e = err(replay_from(
        &dir.join("none.sqlite").display().to_string(),
        1,
        Which::Best,
        None,
        &registry,
    )
    .map(|_| ()));
    assert!(
        matches!(e, ReplayError::Store(StoreError::Missing { .. })),
        "{e}"
    );
    assert!(e.to_string().contains("no such store"), "{e}");
}

#[test]
fn a_random_start_is_drawn_from_the_seed() {
    let dir = common::scratch("random_start");
    let store = dir.join("s.sqlite").display().to_string();
    let config = "configs/gait_from_scratch_ga.simulation.xml";
    let a = optimize(config, &store, 1, 1, 1.0).outcome;
    let b = optimize(config, &store, 1, 1, 1.0).outcome;
    let c = optimize(config, &store, 2, 1, 1.0).outcome;
    assert!(a.start_drawn);
    assert_eq!(a.start, b.start, "same seed, same start");
    assert_ne!(a.start, c.start, "another seed, another start");
    assert_eq!(a.start_score, b.start_score);
}

#[test]
fn robust_fitness_is_the_mean_of_its_stored_randomized_episodes() {
    let dir = common::scratch("robust");
    let store = dir.join("robust.sqlite").display().to_string();
    let report = optimize(
        "configs/gait_from_scratch_robust.simulation.xml",
        &store,
        3,
        3,
        2.0,
    );
    let run = report.store.1;
    let registry = ModuleRegistry::standard();
    let mut s = open(&store);
    let spec = s.run_spec(run).expect("spec");
    // Every episode's seed is stored, drawn from the run's seed.
    let seeds: Vec<u64> = spec.episodes.iter().map(|e| e.seed).collect();
    assert_eq!(seeds, episode_seeds(3, 8));
    assert!(
        spec.episodes[0].draws.contains("friction x"),
        "{:?}",
        spec.episodes[0]
    );
    assert_scores_are_episode_means(&mut s, run, 8, 1e-3);
    let e = replay_from(&store, run, Which::Best, Some(8), &registry)
        .map(|_| ())
        .expect_err("an error");
    assert!(
        matches!(
            e,
            ReplayError::Episode {
                episode: 8,
                count: 8
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("episodes 0 to 7"), "{e}");
}

#[test]
fn the_robustness_check_reevaluates_on_fresh_episodes() {
    let dir = common::scratch("robust_check");
    let store = dir.join("c.sqlite").display().to_string();
    let report = optimize(
        "configs/gait_from_scratch_cmaes.simulation.xml",
        &store,
        2,
        2,
        2.0,
    );
    let registry = ModuleRegistry::standard();
    let ranges = proleg::config::robustness::Robustness::typical();
    let check = |seed| {
        randomized_check(
            &store,
            1,
            Which::Best,
            &ranges,
            proleg::optimize::replay::FreshEpisodes {
                count: 5,
                seed,
                course: None,
            },
            None,
            &registry,
        )
        .expect("check")
    };
    let a = check(1000);
    assert_eq!(a.nominal, report.outcome.best_score, "nominal = stored");
    assert_eq!(a.scores.len(), 5);
    assert_eq!(a, check(1000), "seeded");
    assert_ne!(a.scores, check(1001).scores, "another seed, other episodes");
}

#[test]
fn the_robustness_check_runs_on_a_suite_course_when_asked() {
    let dir = common::scratch("robust_course");
    let store = dir.join("c.sqlite").display().to_string();
    optimize(
        "configs/gait_from_scratch_cmaes.simulation.xml",
        &store,
        2,
        2,
        2.0,
    );
    let registry = ModuleRegistry::standard();
    let ranges = proleg::config::robustness::Robustness::typical();
    let check = |course: Option<(&str, u64)>| {
        randomized_check(
            &store,
            1,
            Which::Best,
            &ranges,
            proleg::optimize::replay::FreshEpisodes {
                count: 2,
                seed: 1000,
                course: course.map(|(task, seed)| proleg::optimize::replay::OnCourse {
                    suite: common::root().join("configs/suites/locomotion.suite.xml"),
                    task: task.into(),
                    seed,
                }),
            },
            None,
            &registry,
        )
    };
    let own = check(None).expect("the run's world");
    let steps = check(Some(("steps-medium", 101))).expect("a test course");
    assert_eq!(steps.scores.len(), 2);
    // Another world, other scores: the candidate ran on the course, not on its own floor
    // (two seconds keep it on the course's flat start, so courses of two families would
    // score alike).
    assert_ne!(own.nominal, steps.nominal);
    assert_ne!(own.scores, steps.scores);
    assert_eq!(steps, check(Some(("steps-medium", 101))).unwrap(), "seeded");
    let err = check(Some(("lava-medium", 1))).unwrap_err().to_string();
    assert!(
        err.contains("no task lava-medium") && err.contains("steps-medium"),
        "{err}"
    );
}

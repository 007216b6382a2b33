//! The command line's logic as a library: `proleg::cli` returns typed reports, and tests
//! assert on their values rather than on printed text.

mod common;

use proleg::cli::error::CliError;
use proleg::cli::optimize::{OptimizeOptions, run as optimize};
use proleg::cli::run::{RunRequest, run};
use proleg::control::ModuleRegistry;

fn request(duration: f64) -> RunRequest {
    RunRequest {
        duration: Some(duration),
        ..RunRequest::of(common::root().join("configs/demo.simulation.xml"))
    }
}

#[test]
fn a_run_report_holds_the_motion_and_the_data_file() {
    let dir = common::scratch("cli_reports_run");
    let file = dir.join("run.data.xml");
    let req = RunRequest {
        data: Some(file.clone()),
        every: Some(10),
        ..request(3.0)
    };
    let r = run(&req, &ModuleRegistry::standard()).unwrap();
    assert_eq!(r.summary.steps, 3000);
    assert!((r.summary.sim_time - 3.0).abs() < 1e-9);
    assert!(r.summary.displacement > 0.1, "{:?}", r.summary);
    assert_eq!(r.robot, "snake5p");
    assert!(r.stopped.is_none() && r.failures.is_empty() && !r.real_robot_mode);
    let (written, rounds) = r.data.clone().unwrap();
    assert_eq!(written, file);
    assert!(rounds >= 1 && file.is_file());
    // The printed summary is the report's own rendering.
    let text = r.to_string();
    assert!(text.contains("steps           3000"), "{text}");
}

#[test]
fn a_bad_request_is_an_error_naming_the_argument() {
    let registry = ModuleRegistry::standard();
    let option = |e: CliError| match e {
        CliError::Option { option, value, .. } => (option, value),
        other => panic!("not an option error: {other}"),
    };
    let e = run(&request(-1.0), &registry).unwrap_err();
    assert_eq!(option(e), ("--duration", "-1".to_string()));
    let e = run(
        &RunRequest {
            realtime: f64::NAN,
            ..request(1.0)
        },
        &registry,
    )
    .unwrap_err();
    assert_eq!(option(e), ("--realtime", "NaN".to_string()));
    let e = run(
        &RunRequest {
            every: Some(0),
            data: Some(common::scratch("cli_reports_every").join("x.data.xml")),
            ..request(1.0)
        },
        &registry,
    )
    .unwrap_err();
    assert_eq!(option(e), ("--every", "0".to_string()));
    let e = run(
        &RunRequest {
            physics: "substeps=many".into(),
            ..request(1.0)
        },
        &registry,
    )
    .unwrap_err();
    assert!(
        matches!(&e, CliError::Physics(_)) && e.to_string().contains("physics setting `substeps`"),
        "{e}"
    );
}

#[test]
fn an_optimize_report_counts_evaluations_and_keeps_the_best() {
    let dir = common::scratch("cli_reports_optimize");
    let store = dir.join("ga.sqlite");
    let o = OptimizeOptions {
        config: common::root().join("configs/experiment1_ga.simulation.xml"),
        seed: Some(3),
        workers: Some(2),
        batch: 0,
        max_evaluations: Some(12),
        duration: Some(1.0),
        fitness: None,
        out: None,
        evaluations: None,
        store: Some(store.display().to_string()),
        resume: false,
        lease: None,
        quiet: true,
        crash_after: None,
        engine: None,
    };
    let r = optimize(&o, &ModuleRegistry::standard()).unwrap();
    // The budget ends the run after the round that reaches it (a GA generation).
    assert!(
        r.outcome.evaluations >= 12 && r.outcome.rounds >= 1,
        "{r:?}"
    );
    assert_eq!(
        r.outcome.simulated, r.outcome.evaluations,
        "a new store: all simulated"
    );
    // The report names the store and the run it wrote: the store's one run, holding every
    // evaluation the run made.
    assert_eq!(r.store.0, store.display().to_string());
    let mut opened = proleg::optimize::store::Store::open_existing(
        &proleg::optimize::store::StoreLocation::Sqlite(store.clone()),
    )
    .unwrap();
    let runs = opened.runs().unwrap();
    assert_eq!(
        runs.iter()
            .map(|run| (run.id, run.evaluations))
            .collect::<Vec<_>>(),
        [(r.store.1, r.outcome.evaluations)],
        "{runs:?}"
    );
    let start = r.outcome.start_score.unwrap();
    assert!(r.outcome.best_score >= start, "{r:?}");
    assert_eq!(r.best_values.len(), r.outcome.best.len());
    assert!(r.per_hour() > 0.0);
}

#[test]
fn a_run_ends_where_its_robot_leaves_the_world_and_scores_as_an_evaluation_does() {
    use proleg::cli::run::RunStop;
    use proleg::config::fitness::Fitness;
    use proleg::config::simulation::EngineKind;
    use proleg::optimize::evaluate::EpisodeWorld;
    use proleg::optimize::evaluate::Evaluator;
    use proleg::optimize::space::SearchSpace;
    use proleg::sim::WorldExit;
    let dir = common::scratch("cli_reports_edge");
    let sim = common::floor_ending_at(&dir, 0.8);
    let registry = ModuleRegistry::standard();
    let r = run(
        &RunRequest {
            config: sim.file.clone(),
            ..request(15.0)
        },
        &registry,
    )
    .unwrap();
    assert!(
        matches!(r.stopped, Some(RunStop::Left(WorldExit::Left(_)))),
        "{:?}",
        r.stopped
    );
    assert!(
        r.summary.sim_time < 12.0,
        "it fell off at {} s",
        r.summary.sim_time
    );
    assert!(r.to_string().contains("left the world"), "{r}");
    // The same step as an optimizer's episode of the same world: the same distance.
    let along =
        proleg::measure::distance_along(r.summary.start_com, r.summary.end_com, r.heading.0);
    let space = SearchSpace::default();
    let scored = Evaluator::new(&sim, &registry, &space, Fitness::Distance, 15.0, 1)
        .run_world(
            &sim,
            EpisodeWorld::nominal(1, Some(EngineKind::Rapier)),
            &[vec![]],
        )
        .unwrap()[0];
    assert_eq!(along, scored);
}

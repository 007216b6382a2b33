//! Training on a task suite: an optimizer file's `<courses>` makes each candidate's
//! episodes the suite's train courses (never a test seed, never a held-out task), the
//! stored episodes name their course, a candidate's score is the mean of its courses'
//! scores as replayed from the store, and bad `<courses>` are located errors.

mod common;

use std::path::Path;

use common::optimize::{assert_scores_are_episode_means, optimize};
use proleg::config::courses::{CoursesSpec, train_tasks};
use proleg::config::optimizer::parse_optimizer_file;
use proleg::config::suite::load_suite;
use proleg::config::{ErrorKind, FsSource, Pos};
use proleg::control::load_simulation;
use proleg::optimize::store::{Store, StoreLocation};

const CONFIG: &str = "configs/suite_sine.simulation.xml";

#[test]
fn the_shipped_file_trains_on_one_train_course_of_each_named_task() {
    let sim = load_simulation(common::root().join(CONFIG)).unwrap();
    let courses = sim
        .optimizer
        .as_ref()
        .and_then(|o| o.courses.as_ref())
        .expect("courses");
    let suite = load_suite(&FsSource, &courses.suite).unwrap();
    let names: Vec<&str> = courses.courses.iter().map(|c| c.task.as_str()).collect();
    assert_eq!(
        names,
        [
            "rough-medium",
            "hills-medium",
            "steps-medium",
            "stairs-medium",
            "slope-medium",
            "pegs-medium"
        ]
    );
    for c in courses.courses.iter() {
        let task = suite.tasks.iter().find(|t| t.name == c.task).unwrap();
        assert!(task.train.contains(&c.seed) && !task.test.contains(&c.seed));
        // The course is the task's, generated: not the simulation's flat floor.
        assert_ne!(c.environment, sim.environment, "{}", c.task);
        assert_eq!(c.environment.robot_pose, sim.environment.robot_pose);
    }
}

#[test]
fn a_candidate_scores_the_mean_of_its_train_courses_as_replayed_from_the_store() {
    let dir = common::scratch("suite_training");
    let store = dir.join("courses.sqlite").display().to_string();
    let report = optimize(CONFIG, &store, 5, 3, 2.0);
    let run = report.store.1;
    let mut s = Store::open_existing(&StoreLocation::parse(&store).unwrap()).unwrap();
    let spec = s.run_spec(run).unwrap();
    assert_eq!(spec.episodes.len(), 6);
    assert!(
        spec.episodes[0]
            .draws
            .starts_with("course rough-medium seed 1;"),
        "{:?}",
        spec.episodes[0].draws
    );
    assert!(
        spec.episodes[5]
            .draws
            .starts_with("course pegs-medium seed 1;")
    );
    // The suite is stored with the run: a replay loads it from the store.
    assert!(
        spec.files
            .iter()
            .any(|(p, _)| p.ends_with("locomotion.suite.xml"))
    );
    // Two seconds do not take the snake off its courses' flat start: the rough courses'
    // episodes differ from the pegs' (a height field under it, a box floor), not from
    // each other.
    assert_scores_are_episode_means(&mut s, run, 6, 0.0);
    drop(s);
    // `proleg suite SUITE STORE --run R`: the run's best candidate is the controller.
    let args = |run: i64, out: &str| proleg::cli::suite::SuiteArgs {
        suite: common::root().join("configs/suites/locomotion.suite.xml"),
        controller: store.clone().into(),
        run: Some(run),
        engines: vec![proleg::config::simulation::EngineKind::Rapier],
        tasks: vec!["pegs-easy".into()],
        threads: Some(2),
        store: None,
        lease: 60.0,
        out: Some(dir.join(out)),
        quiet: true,
    };
    let registry = proleg::control::ModuleRegistry::standard();
    let scored = proleg::cli::suite::run(&args(run, "best"), &registry).unwrap();
    assert_eq!(scored.report.controller, format!("{store} run {run}"));
    let candidate = dir.join("best/controller/candidate.simulation.xml");
    assert!(
        candidate.is_file(),
        "the candidate is exported beside the table"
    );
    let mut untuned = args(run, "untuned");
    untuned.controller = common::root().join(CONFIG);
    untuned.run = None;
    let untuned = proleg::cli::suite::run(&untuned, &registry).unwrap();
    assert_ne!(
        scored.report.tasks[0].mean, untuned.report.tasks[0].mean,
        "the candidate's genes, not the file's gait"
    );
    let e = proleg::cli::suite::run(&args(run + 7, "none"), &registry).unwrap_err();
    assert!(
        matches!(e, proleg::cli::suite::SuiteCommandError::Store(_)),
        "{e}"
    );
    assert!(e.to_string().contains(&format!("{}", run + 7)), "{e}");
}

fn spec(tasks: &[&str]) -> CoursesSpec {
    CoursesSpec {
        suite: "suites/locomotion.suite.xml".into(),
        tasks: tasks.iter().map(|t| t.to_string()).collect(),
        episodes: None,
        stages: Vec::new(),
        pos: Pos::new(40, 3),
    }
}

#[test]
fn held_out_and_unknown_tasks_and_doubled_episode_counts_are_located_errors() {
    let path = common::root().join("configs/suites/locomotion.suite.xml");
    let suite = load_suite(&FsSource, &path).unwrap();
    let file = Path::new("x.cmaes.xml");
    let e = train_tasks(file, &spec(&["pegs-easy", "channel-easy"]), &suite, &path).unwrap_err();
    assert_eq!((e.pos.line, e.kind), (40, ErrorKind::InvalidValue), "{e}");
    assert!(
        e.to_string().contains("\"channel-easy\" is held out"),
        "{e}"
    );
    let e = train_tasks(file, &spec(&["lava"]), &suite, &path).unwrap_err();
    assert_eq!(e.kind, ErrorKind::UnknownReference, "{e}");
    assert!(e.to_string().contains("pegs-hard"), "lists the tasks: {e}");
    let all = train_tasks(file, &spec(&[]), &suite, &path).unwrap();
    assert_eq!(all.len(), 18, "every task with train seeds");
    assert!(all.iter().all(|t| !t.held_out()));

    let text =
        std::fs::read_to_string(common::root().join("configs/optimizer/suite_sine.cmaes.xml"))
            .unwrap();
    let both = text.replace(
        "</cmaEvolutionStrategy>",
        "<robustness><episodes>4</episodes></robustness></cmaEvolutionStrategy>",
    );
    let both = both.replace("pegs-medium\"/>", "pegs-medium\" episodes=\"3\"/>");
    let e = parse_optimizer_file("x.cmaes.xml", &both).unwrap_err();
    assert!(e.to_string().contains("<courses episodes>"), "{e}");
    let round = parse_optimizer_file("x.cmaes.xml", &text).unwrap();
    let again = parse_optimizer_file(
        "x.cmaes.xml",
        &proleg::config::optimizer::write_optimizer_file(&round),
    )
    .unwrap();
    assert_eq!(again.courses, round.courses);
    assert_eq!(round.courses.as_ref().map(|c| c.tasks.len()), Some(6));
}

//! Co-design: a genome's body is the robot the builder makes, it loads and runs like any
//! robot, the same candidate scores the same every time, a killed co-design run resumes
//! to the same archive, and a stored body replays to its stored score.

mod common;

use std::sync::Arc;

use proleg::config::resolve::robot::JointOrientation;
use proleg::config::source::FsSource;
use proleg::control::{ModuleRegistry, load_simulation_in};
use proleg::optimize::design::{Design, DesignSpace};
use proleg::optimize::evaluate::Evaluator;
use proleg::optimize::fitness::Fitness;
use proleg::optimize::replay::{Which, replay_from};
use proleg::optimize::run::prepare;

const CONFIG: &str = "configs/codesign_flat.simulation.xml";

#[test]
fn a_genome_builds_a_body_that_loads_and_crawls_the_same_every_time() {
    let registry = ModuleRegistry::standard();
    let sim = load_simulation_in(common::root().join(CONFIG), &registry).unwrap();
    let (space, start) = prepare(&sim, &registry).unwrap();
    let model = sim.optimizer.as_ref().unwrap();
    let design_space = DesignSpace::from_model(model).unwrap();
    assert_eq!(space, design_space.search_space());
    // modules, 8 orientation genes, parts, 2 orientations x 3 gait parameters.
    assert_eq!(space.genes.len(), 1 + 8 + 1 + 6);
    // 7 modules: joints y y p y p p (two yaw joints in a row need the YY part).
    let mut genome = start.clone();
    genome[0] = 4;
    genome[1..9].copy_from_slice(&[1, 1, 0, 1, 0, 0, 0, 0]);
    let design = Design::of(&sim, Arc::new(FsSource)).unwrap();
    let body = design.simulation(&genome, &registry).unwrap();
    let kinds: Vec<JointOrientation> = body.robot.joints.iter().map(|j| j.orientation).collect();
    use JointOrientation::{Pitch as P, Yaw as Y};
    assert_eq!(kinds, vec![Y, Y, P, Y, P, P]);
    assert_eq!(
        body.actuation.modules.len(),
        2,
        "one sine per orientation group"
    );

    // A 6-module pitch snake with the demo's wave: amplitude 40, phase difference 60,
    // 1 Hz (the pitch group's genes; the yaw group's are unused).
    let mut snake = start.clone();
    snake[0] = 3;
    snake[1..9].copy_from_slice(&[0; 8]);
    snake[10..13].copy_from_slice(&[8, 16, 3]);
    let evaluator = Evaluator::new(&sim, &registry, &space, Fitness::Displacement, 3.0, 1);
    let genomes = vec![snake.clone(), genome.clone(), snake];
    let scores = evaluator.evaluate(&genomes).unwrap();
    assert!(scores.iter().all(|s| s.is_finite()), "{scores:?}");
    assert_eq!(scores[0], scores[2], "the same candidate scores the same");
    assert_ne!(scores[0], scores[1], "another body moves otherwise");
    assert!(scores[0] > 0.1, "the pitch snake crawls: {scores:?}");
}

#[test]
fn a_killed_co_design_run_resumes_to_the_same_archive() {
    let dir = common::scratch("codesign_resume");
    let run = |extra: &[&str], store: &std::path::Path| {
        common::optimize(CONFIG, ("60", "1"), store, extra)
    };
    let whole = dir.join("whole.sqlite");
    let (ok, full, err) = run(&[], &whole);
    assert!(ok, "{err}");
    let archive = common::archive_line(&whole);
    assert!(archive.contains("share of yaw joints"), "{archive}");
    let killed = dir.join("killed.sqlite");
    let (ok, _, _) = run(&["--crash-after", "45"], &killed);
    assert!(!ok, "the crash aid aborts the process");
    let (ok, resumed, err) = run(&["--resume"], &killed);
    assert!(ok, "{err}");
    let best = |out: &str| -> Vec<String> {
        out.lines()
            .skip_while(|l| !l.starts_with("best score"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(best(&resumed), best(&full));
    assert_eq!(common::archive_line(&killed), archive);
    // A stored body replays to its stored score: the best, and one from the middle.
    let registry = ModuleRegistry::standard();
    for which in [Which::Best, Which::Number(30)] {
        let r = replay_from(whole.to_str().unwrap(), 1, which, None, &registry).unwrap();
        assert_eq!(r.score().unwrap(), r.stored_score, "{}", r.label);
    }
}

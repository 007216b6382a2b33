//! The learned controllers shipped in `configs/learned/`: each simulation file runs its
//! network on one held-out test course of the suite task it was trained for, and goes the
//! distance docs/suite.md reports for it, on rapier and on MuJoCo (the episode `proleg
//! suite` runs: its course, duration and measure).

mod common;

use std::path::Path;

use proleg::config::resolve::environment::EnvironmentModel;
use proleg::config::simulation::EngineKind;
use proleg::config::suite::load_suite;
use proleg::config::{FsSource, Simulation};
use proleg::control::{ModuleRegistry, load_simulation};
use proleg::sim::episode::course::{EpisodeKey, run_episode};

/// Shipped file, its task, the test course it is on, whether it runs a learned network,
/// and the metres `proleg suite` measured for it there on rapier and on MuJoCo
/// (`scripts/learned-suite-experiment`'s `suite_policy` and `suite_sine` journals).
const SHIPPED: &[(&str, &str, u64, bool, f64, f64)] = &[
    (
        "configs/learned/steps_medium.simulation.xml",
        "steps-medium",
        101,
        true,
        8.502361511190731,
        8.459732814548923,
    ),
    (
        "configs/learned/steps_medium_robust.simulation.xml",
        "steps-medium",
        101,
        true,
        9.452888066569962,
        8.593312175024545,
    ),
    (
        "configs/learned/steps_medium_sine.simulation.xml",
        "steps-medium",
        101,
        false,
        3.2508854617675143,
        3.253600288425668,
    ),
];

const SUITE: &str = "configs/suites/locomotion.suite.xml";

/// What a world is made of, without where its files wrote it (the shipped file's
/// `<Terrain>` element and the suite's task are on different lines).
fn world(e: &EnvironmentModel) -> String {
    let text = format!(
        "{:?} {:?} {:?} {:?}",
        e.physics, e.bodies, e.robot_pose, e.meshes
    );
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while let Some(at) = rest.find("pos: Pos {") {
        out.push_str(&rest[..at]);
        let end = rest[at..].find('}').map_or(rest.len(), |k| at + k + 1);
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

fn distance(sim: &Simulation, task_name: &str, seed: u64, engine: EngineKind) -> f64 {
    let suite_path = common::root().join(SUITE);
    let suite = load_suite(&FsSource, &suite_path).unwrap();
    let (index, task) = suite
        .tasks
        .iter()
        .enumerate()
        .find(|(_, t)| t.name == task_name)
        .unwrap();
    // The shipped world is the task's test course, as `proleg suite` builds it.
    let course = sim.on_course(task, seed, &suite_path).unwrap().environment;
    assert_eq!(
        world(&sim.environment),
        world(&course),
        "{task_name} {seed}"
    );
    assert_eq!(sim.files.simulation.properties.duration, task.duration);
    let key = EpisodeKey {
        task: index,
        seed,
        engine,
    };
    let registry = ModuleRegistry::standard();
    run_episode(sim, task, key, &registry, None)
        .unwrap()
        .unwrap()
        .distance
}

#[test]
fn each_shipped_controller_goes_its_reported_distance_on_its_test_course() {
    assert!(!SHIPPED.is_empty());
    for &(file, task, seed, learned, rapier, mujoco) in SHIPPED {
        let sim = load_simulation(common::root().join(file)).unwrap();
        let runs_policy = sim
            .files
            .actuation
            .modules
            .iter()
            .any(|m| m.name == "Policy");
        assert_eq!(runs_policy, learned, "{file}");
        let got = distance(&sim, task, seed, EngineKind::Rapier);
        assert!(
            (got - rapier).abs() < 1e-6,
            "{file} rapier: {got} m, not {rapier}"
        );
        if common::mujoco_here("learned_configs") {
            let got = distance(&sim, task, seed, EngineKind::Mujoco);
            assert!(
                (got - mujoco).abs() < 1e-6,
                "{file} MuJoCo: {got} m, not {mujoco}"
            );
        }
    }
}

#[test]
fn every_simulation_file_in_the_folder_is_shipped_with_its_figures() {
    let dir = common::root().join("configs/learned");
    for f in common::files_ending(&dir, ".simulation.xml") {
        let name = f.strip_prefix(common::root()).unwrap_or(Path::new(""));
        let training = f
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("train_"));
        assert!(
            training || SHIPPED.iter().any(|s| Path::new(s.0) == name),
            "{} has no figures in this test",
            name.display()
        );
    }
}

//! Experiment 2 (thesis 6.2): the detailed robot with the sine generator alone (30° / 55°)
//! gets stuck at the irregular obstacle, though on the same floor without the obstacle it
//! crawls on; with the adaptive touch module added (parameters found by `proleg optimize`
//! on `configs/experiment2_gd.simulation.xml`) it gets over the last hill: the whole robot
//! is past its crest after 90 s.

mod common;

use proleg::config::body::BodyKind;
use proleg::control::load_simulation;
use proleg::sim::{BuildOptions, Simulator};

/// The obstacle spans y = 0.6 m to 4.2 m; the robot starts with its centre at y = 0.14 m.
const OBSTACLE_END: f64 = 4.2;
/// The crest of the obstacle's last hill.
const LAST_CREST: f64 = 3.77;
/// Half the robot's length (5 modules of 72 mm): a centre this far past the crest puts the
/// tail past it too.
const HALF_LENGTH: f64 = 0.18;

fn run(config: &str, without_obstacle: bool) -> [f64; 3] {
    let mut sim = load_simulation(common::root().join(config)).unwrap();
    if without_obstacle {
        sim.environment.bodies.retain(|b| b.name != "obstacle");
    }
    let mut s = Simulator::new(
        &sim,
        &BuildOptions {
            robots: 1,
            seed: 1,
            record: false,
            ..Default::default()
        },
    )
    .unwrap();
    s.run_for(90.0).end_com
}

#[test]
fn sine_alone_gets_stuck_at_the_obstacle() {
    let stuck = run("configs/experiment2_sine_only.simulation.xml", false);
    let free = run("configs/experiment2_sine_only.simulation.xml", true);
    eprintln!(
        "90 s, sine alone: y = {:.3} m with the obstacle, {:.3} m without",
        stuck[1], free[1]
    );
    // It crosses the hump, the plateau and its trough, and stops at the last hill.
    assert!(
        stuck[1] < LAST_CREST,
        "got over the last hill: y = {}",
        stuck[1]
    );
    assert!(
        free[1] > OBSTACLE_END,
        "on the open floor it should crawl on: y = {}",
        free[1]
    );
}

#[test]
fn the_adaptive_module_gets_over_the_last_hill() {
    let end = run("configs/experiment2_adaptive.simulation.xml", false);
    eprintln!("90 s, sine + adaptive touch: y = {:.3} m", end[1]);
    assert!(
        end[1] > LAST_CREST + HALF_LENGTH,
        "did not get over the last hill: y = {}",
        end[1]
    );
}

#[test]
fn a_height_field_on_a_moving_body_collides_as_its_triangles() {
    // Rapier's height fields have no volume: a dynamic body made of one would get no mass
    // and no inertia. The obstacle made dynamic keeps the mass it is given and settles.
    let mut sim =
        load_simulation(common::root().join("configs/experiment2_adaptive.simulation.xml"))
            .unwrap();
    let obstacle = sim
        .environment
        .bodies
        .iter()
        .position(|b| b.name == "obstacle");
    let obstacle = obstacle.expect("the obstacle body");
    sim.environment.bodies[obstacle].kind = BodyKind::Dynamic;
    sim.environment.bodies[obstacle].mass = 20.0;
    let mut s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
    let body = s.environment_bodies()[obstacle].body;
    let props = s.body_state(body).expect("the obstacle's rigid body");
    assert!((props.mass - 20.0).abs() < 1e-3, "{props:?}");
    let inertia = props.inertia;
    assert!(
        inertia.iter().all(|i| *i > 0.0),
        "a moving body needs inertia: {inertia:?}"
    );
    s.run_steps(500);
    let at = s.body_position(body).unwrap();
    assert!(at.iter().all(|v| v.is_finite()), "{at:?}");
}

//! Gravity comes from the environment, not a constant: on a 3.71 m/s² (Mars) world the
//! logged potential energy and the cost-of-transport fitness use 3.71.

use proleg::config::Simulation;
use proleg::config::fitness::Fitness;
use proleg::control::ModuleRegistry;
use proleg::control::load_simulation;
use proleg::optimize::evaluate::Evaluator;
use proleg::optimize::space::SearchSpace;
use proleg::sim::datalog::{DataSettings, ROBOT_HANDLER};
use proleg::sim::{BuildOptions, Simulator};

const MARS: f64 = 3.71;

fn on_mars(config: &str) -> Simulation {
    let mut sim = load_simulation(config).unwrap();
    sim.environment.physics.gravity = [0.0, 0.0, -MARS];
    sim
}

#[test]
fn potential_energy_uses_the_world_gravity() {
    let sim = on_mars("configs/demo.simulation.xml");
    let mut s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
    assert!((s.gravity()[2] + MARS).abs() < 1e-6, "{:?}", s.gravity());
    s.enable_data(
        DataSettings {
            every: 1,
            ..DataSettings::default()
        },
        None,
    );
    s.run_steps(500);
    let log = s.data(0).unwrap();
    let spec = log
        .handlers
        .iter()
        .find(|h| h.name == ROBOT_HANDLER)
        .unwrap();
    let ring = log.ring(ROBOT_HANDLER).unwrap();
    let (_, frame) = ring.get(ring.len() - 1).unwrap();
    let potential = frame[spec.offset(spec.find("potential_energy").unwrap())];
    let z = s.com(0).unwrap()[2];
    let expected = s.mass(0).unwrap() * MARS * z;
    assert!(
        (potential - expected).abs() < 1e-4 * expected.abs().max(1e-9),
        "logged {potential} J, m g z = {expected} J (g = {MARS})"
    );
}

#[test]
fn cost_of_transport_weighs_the_robot_with_the_world_gravity() {
    let sim = on_mars("configs/experiment1_ga.simulation.xml");
    let reference = Simulator::new(&sim, &BuildOptions::default()).unwrap();
    let space = SearchSpace::from_model(
        sim.optimizer.as_ref().unwrap(),
        reference.kernel(0).unwrap(),
    )
    .unwrap();
    let genome = space.encode_kernel(reference.kernel(0).unwrap());
    let evaluator = Evaluator::new(
        &sim,
        &ModuleRegistry::standard(),
        &space,
        Fitness::CostOfTransport,
        2.0,
        1,
    );
    let score = evaluator.evaluate(std::slice::from_ref(&genome)).unwrap()[0];
    // The same episode by hand.
    let episode = BuildOptions {
        record: false,
        ..BuildOptions::default()
    };
    let mut s = Simulator::new(&sim, &episode).unwrap();
    space.apply(&genome, s.kernel_mut(0).unwrap()).unwrap();
    let moved = s.run_for(2.0).displacement;
    let energy = s.energy(0).unwrap().joules;
    let expected = -energy / (s.mass(0).unwrap() * MARS * moved);
    assert!(
        energy > 0.0 && moved > 0.05,
        "energy {energy} J, moved {moved} m"
    );
    assert!(
        (score - expected).abs() < 1e-4 * expected.abs(),
        "score {score}, -E/(m g d) with g = {MARS}: {expected}"
    );
}

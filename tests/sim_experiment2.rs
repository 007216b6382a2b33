//! Experiment 2's terrain (thesis 6.2): the detailed robot with the sine generator alone
//! (30° / 55°) gets stuck at the irregular obstacle, though on the same floor without the
//! obstacle it crawls on. (The adaptive module that crosses it is issue 4's remaining part.)

mod common;

use proleg::config::load_simulation;
use proleg::sim::clock::SimClock;
use proleg::sim::{BuildOptions, Simulator};

fn run(without_obstacle: bool) -> [f64; 3] {
    let mut sim =
        load_simulation(common::root().join("configs/experiment2_sine_only.simulation.xml"))
            .unwrap();
    if without_obstacle {
        sim.environment.bodies.retain(|b| b.name != "obstacle");
    }
    let mut s = Simulator::new(
        &sim,
        &BuildOptions {
            robots: 1,
            seed: 1,
            record: false,
        },
    )
    .unwrap();
    s.world_mut().resource_mut::<SimClock>().realtime_factor = 0.0;
    s.run_for(90.0).end_com
}

#[test]
fn sine_alone_gets_stuck_at_the_obstacle() {
    let stuck = run(false);
    let free = run(true);
    eprintln!(
        "90 s, sine alone: {:.3} m with the obstacle, {:.3} m without",
        stuck[1], free[1]
    );
    // The obstacle starts at y = 0.6 m and its first hump peaks at 0.89 m.
    assert!(stuck[1] < 1.2, "crossed the first hump: y = {}", stuck[1]);
    assert!(
        free[1] > 3.0,
        "on the open floor it should crawl on: y = {}",
        free[1]
    );
}

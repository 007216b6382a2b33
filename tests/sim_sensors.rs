//! Tactile pads in the simulated world: resting on the floor they read pressed, lifted
//! they read released, and a change is reported only after its debounce steps.

mod common;

use proleg::config::{Simulation, load_simulation};
use proleg::sim::clock::SimClock;
use proleg::sim::tactile::{RobotSensors, TactileSensor};
use proleg::sim::{BuildOptions, Simulator};

fn tactile_sine_only() -> Simulation {
    load_simulation(common::root().join("configs/experiment2_sine_only.simulation.xml")).unwrap()
}

fn still(sim: &Simulation) -> Simulator {
    let mut s = Simulator::new(sim, &BuildOptions::default()).unwrap();
    s.world_mut().resource_mut::<SimClock>().realtime_factor = 0.0;
    s.set_parameter(0, 0, "Amplitude", None, 0.0).unwrap();
    s
}

fn readings(s: &Simulator) -> Vec<bool> {
    s.world().get::<RobotSensors>(s.robots()[0]).unwrap().0.tactile.clone()
}

#[test]
fn pads_resting_on_the_floor_read_pressed() {
    let mut s = still(&tactile_sine_only());
    s.run_steps(200);
    let r = readings(&s);
    assert_eq!(r.len(), 12);
    assert!(r.iter().all(|p| *p), "{r:?}");
    let normals = s.world().get::<RobotSensors>(s.robots()[0]).unwrap().0.tactile_normals.clone();
    assert!(normals.iter().all(|n| n[2] > 0.99), "normals point up from the floor: {normals:?}");
}

#[test]
fn lifted_pads_read_released_until_they_land() {
    let mut sim = tactile_sine_only();
    sim.environment.robot_pose.translation[2] = 0.3;
    let mut s = still(&sim);
    s.run_steps(50);
    assert!(readings(&s).iter().all(|p| !*p), "pressed in the air");
    s.run_steps(1500);
    assert!(readings(&s).iter().filter(|p| **p).count() >= 10, "{:?}", readings(&s));
}

#[test]
fn a_landing_is_reported_after_the_debounce_steps() {
    let mut sim = tactile_sine_only();
    sim.environment.robot_pose.translation[2] = 0.05;
    let mut s = still(&sim);
    let debounce = sim.robot.sensors.iter().find_map(|x| match &x.sensor {
        proleg::config::sensor::Sensor::Tactile(t) => Some(t.debounce),
        _ => None,
    });
    let debounce = debounce.unwrap() as usize;
    assert!(debounce >= 2);
    let mut first_raw = None;
    let mut first_pressed = None;
    for step in 0..2000 {
        s.step();
        let world = s.world_mut();
        let mut q = world.query::<&TactileSensor>();
        let pad = q.iter(world).find(|p| p.index == 0).unwrap().clone();
        if pad.raw && first_raw.is_none() {
            first_raw = Some(step);
        }
        if pad.state.pressed && first_pressed.is_none() {
            first_pressed = Some(step);
        }
    }
    let (raw, pressed) = (first_raw.unwrap(), first_pressed.unwrap());
    assert!(pressed >= raw + debounce - 1, "raw contact at step {raw}, reported at {pressed}");
}

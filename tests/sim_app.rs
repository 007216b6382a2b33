//! The simulation inside a Bevy App, headless with MinimalPlugins and manual updates (as
//! Bevy's tests/how_to_test_systems.rs): the pipeline runs its sets in order each step.

mod common;

use bevy::prelude::*;
use proleg::control::ModuleRegistry;
use proleg::control::load_simulation;
use proleg::sim::clock::SimClock;
use proleg::sim::robot::SimRobot;
use proleg::sim::servo::{JointState, SimJoint};
use proleg::sim::spawn::{SimEnvObject, SimLink, build_world};
use proleg::sim::{BuildOptions, SimDriverPlugin, SimPlugins, StepsPerUpdate};

fn app() -> (App, Entity) {
    let sim = load_simulation(common::root().join("configs/demo.simulation.xml")).unwrap();
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, SimPlugins, SimDriverPlugin));
    let robots = build_world(
        app.world_mut(),
        &sim,
        &BuildOptions::default(),
        &ModuleRegistry::default(),
    )
    .unwrap();
    (app, robots[0])
}

#[test]
fn updates_step_the_pipeline() {
    let (mut app, robot) = app();
    app.update();
    assert_eq!(
        app.world().resource::<SimClock>().step,
        0,
        "paused until steps are asked for"
    );
    app.insert_resource(StepsPerUpdate(100));
    for _ in 0..5 {
        app.update();
    }
    assert_eq!(app.world().resource::<SimClock>().step, 500);
    // The kernel drove the servos: joints moved away from zero.
    let joints = app.world().get::<SimRobot>(robot).unwrap().joints.clone();
    let moved = joints
        .iter()
        .filter(|j| app.world().get::<JointState>(**j).unwrap().angle.abs() > 5.0)
        .count();
    assert!(moved >= 3, "only {moved} joints moved");
}

#[test]
fn every_entity_is_named() {
    let (mut app, _) = app();
    let world = app.world_mut();
    // Every entity the world builder spawned (Bevy's own entities aside) has a name.
    let mut unnamed = world.query_filtered::<Entity, (
        Without<Name>,
        Or<(
            With<SimRobot>,
            With<SimLink>,
            With<SimJoint>,
            With<SimEnvObject>,
        )>,
    )>();
    let count = unnamed.iter(world).count();
    let mut ours = world.query_filtered::<Entity, Or<(
        With<SimRobot>,
        With<SimLink>,
        With<SimJoint>,
        With<SimEnvObject>,
    )>>();
    assert_eq!(ours.iter(world).count(), 1 + 6 + 5 + 1);
    let mut named = world.query::<&Name>();
    let names: Vec<String> = named.iter(world).map(|n| n.to_string()).collect();
    assert_eq!(count, 0, "unnamed entities; named: {names:?}");
    for expected in ["snake5p", "link Tail", "joint J5", "environment: floor"] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} missing in {names:?}"
        );
    }
}

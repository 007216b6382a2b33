//! Physics with known answers on both engines at their production settings: friction onset at atan μ on a tilted box floor, a height-field slope and a
//! trimesh slope, sliding to rest after v² / (2 μ g), resting contact without penetration
//! or drift on the floor and on a height field, a drop that settles without bouncing, a
//! servo following its model after a 30° step and stalling at its torque limit, a
//! pendulum's period.
//! `proleg check-physics` prints the same table.

mod common;

use proleg::bench::physics_checks::{report, run};
use proleg::config::simulation::EngineKind;
use proleg::control::{ModuleRegistry, load_simulation};

fn checks_pass(engine: EngineKind) {
    let base = load_simulation(common::root().join("configs/demo.simulation.xml")).unwrap();
    let checks = run(&base, engine, &ModuleRegistry::standard()).unwrap();
    let table = report(engine, &checks);
    println!("{table}");
    assert_eq!(checks.len(), 18, "{table}");
    assert!(checks.iter().all(|c| c.measured.is_finite()), "{table}");
    assert!(checks.iter().all(|c| c.pass), "{table}");
}

#[test]
fn rapier_passes_the_physical_checks() {
    checks_pass(EngineKind::Rapier);
}

#[test]
fn mujoco_passes_the_physical_checks() {
    if common::mujoco_here("physical checks on MuJoCo") {
        checks_pass(EngineKind::Mujoco);
    }
}

#[test]
fn the_command_prints_the_table_and_exits_0() {
    let (ok, out, err) = common::proleg(&["check-physics", "--engine", "rapier"]);
    assert!(ok, "{out}{err}");
    assert!(
        out.contains("friction onset, mu 0.5") && out.contains("18 of 18 checks pass"),
        "{out}"
    );
}

//! Reference trajectories: each reference scenario runs a few seconds on each engine and
//! its trajectory (centre of mass, heading and every joint angle, every 10 steps, as exact
//! bits) is hashed and compared with the hash stored in `tests/reference/trajectories.tsv`
//! (MuJoCo's rows are the scenario prefixed `mujoco:`). Any change to
//! physics, servos, modules or the order of the step shows up here. When a change is meant
//! to move the trajectories, update the file deliberately and say why in the commit:
//!
//! ```sh
//! PROLEG_UPDATE_REFERENCE=1 cargo test --release --test sim_reference
//! ```

use std::hash::Hasher;
use std::path::Path;

mod common;

use proleg::config::simulation::EngineKind;
use proleg::control::load_simulation;
use proleg::sim::{BuildOptions, Simulator};

const TABLE: &str = "tests/reference/trajectories.tsv";

/// Scenario, simulated seconds.
const SCENARIOS: [(&str, f64); 4] = [
    ("configs/demo.simulation.xml", 4.0),
    ("configs/experiment2_adaptive.simulation.xml", 4.0),
    ("configs/snake8py_slope.simulation.xml", 4.0),
    ("configs/snake16py_stairs.simulation.xml", 2.0),
];

fn trajectory_hash(config: &str, seconds: f64, engine: EngineKind) -> u64 {
    let sim = load_simulation(config).unwrap();
    let opts = BuildOptions {
        robots: 1,
        seed: sim.files.simulation.properties.seed,
        record: false,
        engine: engine.into(),
        ..Default::default()
    };
    let mut s = Simulator::new(&sim, &opts).unwrap();
    let steps = (seconds / s.clock().dt).round() as u64;
    let mut h = fnv::FnvHasher::default();
    for _ in 0..steps / 10 {
        s.run_steps(10);
        for v in s.com(0).unwrap() {
            h.write_u64(v.to_bits());
        }
        h.write_u64(s.heading(0).unwrap().to_bits());
        for j in s.joint_states(0).unwrap() {
            h.write_u64(j.angle.to_bits());
        }
    }
    h.finish()
}

#[test]
fn reference_trajectories_match_their_stored_hashes() {
    let stored = std::fs::read_to_string(TABLE).unwrap_or_default();
    let lookup = |config: &str| {
        stored
            .lines()
            .filter(|l| !l.starts_with('#'))
            .find_map(|l| {
                let mut f = l.split('\t');
                (f.next() == Some(config)).then(|| f.nth(1).map(str::to_string))?
            })
    };
    let mut table = String::from("# scenario\tseconds\ttrajectory hash (tests/sim_reference.rs)\n");
    let mut changed = Vec::new();
    let mut engines = vec![EngineKind::Rapier];
    if common::mujoco_here("reference trajectories on MuJoCo") {
        engines.push(EngineKind::Mujoco);
    }
    for engine in engines {
        for (config, seconds) in SCENARIOS {
            let key = match engine {
                EngineKind::Rapier => config.to_string(),
                EngineKind::Mujoco => format!("mujoco:{config}"),
            };
            let hash = format!("{:016x}", trajectory_hash(config, seconds, engine));
            eprintln!("{key} {seconds} s: {hash}");
            if lookup(&key).as_deref() != Some(hash.as_str()) {
                changed.push(format!("{key}: stored {:?}, now {hash}", lookup(&key)));
            }
            table.push_str(&format!("{key}\t{seconds}\t{hash}\n"));
        }
    }
    if std::env::var_os("PROLEG_UPDATE_REFERENCE").is_some() {
        std::fs::write(Path::new(TABLE), table).unwrap();
        return;
    }
    assert!(
        changed.is_empty(),
        "trajectories changed (if meant, update with PROLEG_UPDATE_REFERENCE=1 and say why in the commit):\n{}",
        changed.join("\n")
    );
}

#[test]
fn the_hash_sees_a_changed_parameter() {
    let sim = load_simulation("configs/demo.simulation.xml").unwrap();
    let run = |amplitude: f64| {
        let mut s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
        s.set_parameter(0, 0, "Amplitude", None, amplitude).unwrap();
        s.run_steps(200);
        s.joint_states(0).unwrap()[2].angle
    };
    assert_ne!(run(40.0).to_bits(), run(39.9).to_bits());
}

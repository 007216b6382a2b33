//! The thesis's listings B.1-B.7 load as written, with the values they hold.

mod common;

use proleg::config::actuation::parse_actuation_file;
use proleg::config::optimizer::{Algorithm, BoundType, parse_optimizer_file};
use proleg::config::resolve::JointOrientation;
use proleg::config::sensor::{Sensor, parse_sensor_file};
use proleg::config::simulation::Mode;
use proleg::control::load_simulation;

fn read(rel: &str) -> (String, String) {
    let p = common::thesis().join(rel);
    let text = std::fs::read_to_string(&p).unwrap();
    (p.display().to_string(), text)
}

#[test]
fn b1_to_b6_load_as_one_simulation() {
    let sim = load_simulation(common::thesis().join("demo.simulation.xml")).unwrap();
    let p = &sim.files.simulation.properties;
    assert_eq!(p.mode, Mode::SingleRun);
    assert_eq!(p.accuracy, 30);
    assert_eq!(p.step_width, 0.001);
    assert!(p.storing_data && p.show_viewer && !p.parallel_computing);

    // B.2: six links, five joints alternating pitch and yaw, placed 72 mm apart.
    let r = &sim.robot;
    assert_eq!(r.name, "MFIdemo_5py");
    let names: Vec<&str> = r.links.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["Tail", "1Seg", "2Seg", "3Seg", "4Seg", "Head"]);
    assert_eq!(r.pattern(), "PYPYP");
    assert_eq!(r.joints[1].orientation, JointOrientation::Yaw);
    let anchors: Vec<f64> = r
        .joints
        .iter()
        .map(|j| (j.anchor[1] * 1000.0).round())
        .collect();
    assert_eq!(anchors, [0.0, 72.0, 144.0, 216.0, 288.0]);
    assert!(
        r.joints
            .iter()
            .all(|j| j.max_torque == 0.4 && j.max_vel == 4.5 && j.limits_deg == [-90.0, 90.0])
    );

    // B.5: two overlapping-free groups.
    let m = &sim.actuation.modules;
    assert_eq!(m.len(), 2);
    assert_eq!(m[0].descriptor.type_name, "DirectJointAccess");
    assert_eq!(m[0].joints.to_string(), "01010");
    assert_eq!(m[1].descriptor.type_name, "PatternGenerator_sinusoidal");
    assert_eq!(m[1].joints.to_string(), "10101");

    // B.6: the floor, its friction, and the pose kept in the trailing comment.
    let e = &sim.environment;
    assert_eq!(e.physics.gravity, [0.0, 0.0, -9.81]);
    assert!(e.physics.self_collision);
    assert_eq!(e.bodies.len(), 1);
    assert_eq!(e.bodies[0].name, "floor");
    assert_eq!(e.bodies[0].geoms[0].friction, Some(0.1));
    assert_eq!(e.bodies[0].geoms[0].transparency, Some(0.05));
    assert_eq!(e.robot_pose.translation, [0.0, 0.0, 0.0]);
    assert_eq!(e.robot_pose.rotation, [1.0, 0.0, 0.0, 0.0]);
    assert!(sim.warnings.is_empty(), "{:?}", sim.warnings);
}

#[test]
fn b3_and_b4_sensor_files() {
    let (f, t) = read("configuration/sensors/tactile.sensor.xml");
    let Sensor::Tactile(s) = parse_sensor_file(&f, &t).unwrap() else {
        panic!("not tactile")
    };
    assert!(s.power);
    let (f, t) = read("configuration/sensors/laser.sensor.xml");
    let Sensor::Laser2d(l) = parse_sensor_file(&f, &t).unwrap() else {
        panic!("not a laser")
    };
    assert_eq!(
        (
            l.min_angle,
            l.max_angle,
            l.resolution,
            l.max_range,
            l.scan_time
        ),
        (-1.0, 1.0, 1.0, 1.0, 1.0)
    );
    assert!(l.render && l.power);
}

#[test]
fn b5_actuation_file() {
    let (f, t) = read("configuration/actuation/MFIdemo_5py_2012.09.06_17:38.actuation.xml");
    let a = parse_actuation_file(&f, &t).unwrap();
    assert_eq!(a.valid_robot.as_deref(), Some("MFIdemo_5py.robot.xml"));
    assert_eq!(a.modules.len(), 2);
}

#[test]
fn b7_genetic_algorithm_file() {
    let (f, t) = read("configuration/ga/adaptive.ga.xml");
    let o = parse_optimizer_file(&f, &t).unwrap();
    let Algorithm::Genetic(g) = &o.algorithm else {
        panic!("not a GA")
    };
    assert_eq!(
        (
            g.popsize,
            g.pmut,
            g.pcross,
            g.n_convergence,
            g.p_convergence
        ),
        (30, 0.01, 0.9, 50, 0.99)
    );
    assert_eq!((g.flush_frequency, g.ga_mode), (1, 1));
    assert_eq!(o.parameters.len(), 2);
    assert_eq!(o.parameters[0].module, "Global Adaptive Touch");
    assert_eq!(o.parameters[1].parameter, "back to zero constant");
    let g0 = &o.genome[0];
    assert_eq!(
        (
            g0.lower.as_slice(),
            g0.upper.as_slice(),
            g0.increments.as_slice()
        ),
        (&[50.0][..], &[800.0][..], &[25.0][..])
    );
    assert_eq!(g0.lower_bound_type, BoundType::Exclusive);
    assert!(g0.uniform);
}

#[test]
fn b7_resolves_against_the_adaptive_module() {
    let sim = load_simulation(common::thesis().join("adaptive_ga.simulation.xml")).unwrap();
    let o = sim.optimizer.unwrap();
    // The thesis's names map onto the module's parameters.
    assert_eq!(o.parameters[0].module, "Global_Adaptive_Touch");
    assert_eq!(o.parameters[0].parameter.name, "Get-stuck");
    assert_eq!(o.parameters[1].parameter.name, "Recovering");
    // Exclusive bounds: 50 < v < 800 in steps of 25 -> 29 values; 0.01 < v < 1 -> 98.
    assert_eq!(o.parameters[0].alleles, [29]);
    assert_eq!(o.parameters[1].alleles, [98]);
}

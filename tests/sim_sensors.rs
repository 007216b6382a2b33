//! Tactile pads in the simulated world: resting on the floor they read pressed, lifted
//! they read released, and a change is reported only after its debounce steps; a laser
//! measures a wall at a known distance. Every test runs on both engines (MuJoCo where its
//! library is, see `common::mujoco_here`).

mod common;

use proleg::config::Simulation;
use proleg::config::simulation::EngineKind;
use proleg::control::load_simulation;
use proleg::sim::{BuildOptions, Simulator};

/// Each test as a module with one test per engine.
macro_rules! on_both_engines {
    ($($name:ident),*) => {$(
        mod $name {
            use super::*;

            #[test]
            fn rapier() {
                super::$name(EngineKind::Rapier);
            }

            #[test]
            fn mujoco() {
                if common::mujoco_here(stringify!($name)) {
                    super::$name(EngineKind::Mujoco);
                }
            }
        }
    )*};
}

on_both_engines!(
    pads_resting_on_the_floor_read_pressed,
    lifted_pads_read_released_until_they_land,
    a_landing_is_reported_after_the_debounce_steps,
    laser_measures_a_wall_at_a_known_distance
);

fn tactile_sine_only(engine: EngineKind) -> Simulation {
    load_simulation(common::root().join("configs/experiment2_sine_only.simulation.xml"))
        .unwrap()
        .with_engine(Some(engine))
}

fn still(sim: &Simulation) -> Simulator {
    let mut s = Simulator::new(sim, &BuildOptions::default()).unwrap();
    s.set_parameter(0, 0, "Amplitude", None, 0.0).unwrap();
    s
}

fn readings(s: &Simulator) -> Vec<bool> {
    s.sensors(0).unwrap().tactile.clone()
}

fn pads_resting_on_the_floor_read_pressed(engine: EngineKind) {
    let mut s = still(&tactile_sine_only(engine));
    s.run_steps(200);
    let r = readings(&s);
    assert_eq!(r.len(), 12);
    assert!(r.iter().all(|p| *p), "{r:?}");
    let normals = s.sensors(0).unwrap().tactile_normals.clone();
    assert!(
        normals.iter().all(|n| n[2] > 0.99),
        "normals point up from the floor: {normals:?}"
    );
}

fn lifted_pads_read_released_until_they_land(engine: EngineKind) {
    let mut sim = tactile_sine_only(engine);
    sim.environment.robot_pose.translation[2] = 0.3;
    let mut s = still(&sim);
    s.run_steps(50);
    assert!(readings(&s).iter().all(|p| !*p), "pressed in the air");
    s.run_steps(1500);
    assert!(
        readings(&s).iter().filter(|p| **p).count() >= 10,
        "{:?}",
        readings(&s)
    );
}

fn a_landing_is_reported_after_the_debounce_steps(engine: EngineKind) {
    let mut sim = tactile_sine_only(engine);
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
        let pad = s.tactile_pads(0).unwrap()[0];
        if pad.raw && first_raw.is_none() {
            first_raw = Some(step);
        }
        if pad.pressed && first_pressed.is_none() {
            first_pressed = Some(step);
        }
    }
    let (raw, pressed) = (first_raw.unwrap(), first_pressed.unwrap());
    assert!(
        pressed >= raw + debounce - 1,
        "raw contact at step {raw}, reported at {pressed}"
    );
}

fn laser_measures_a_wall_at_a_known_distance(engine: EngineKind) {
    use proleg::config::body::{BodyKind, Geom, Shape};
    use proleg::config::resolve::{EnvBody, RobotSensor};
    use proleg::config::sensor::{Laser2d, Sensor};
    use proleg::config::transform::Pose;
    let mut sim = load_simulation(common::root().join("configs/demo.simulation.xml"))
        .unwrap()
        .with_engine(Some(engine));
    // A laser 7 cm ahead of the head's joint, 2 cm up; a wall whose face is at y = 1.95 m.
    let head = sim
        .robot
        .links
        .iter()
        .position(|l| l.name == "Head")
        .unwrap();
    sim.robot.sensors.push(RobotSensor {
        name: "laser".into(),
        link: head,
        pose: Pose::from_translation([0.0, 0.07, 0.02]),
        sensor: Sensor::Laser2d(Laser2d {
            min_angle: -30.0,
            max_angle: 30.0,
            resolution: 15.0,
            max_range: 3.0,
            scan_time: 0.01,
            render: false,
            power: true,
        }),
    });
    let wall = Geom {
        shape: Shape::Box {
            extents: [1.0, 0.05, 0.25],
        },
        pose: Pose::IDENTITY,
        diffuse_color: None,
        ambient_color: None,
        transparency: None,
        friction: None,
        visible: true,
        pos: Default::default(),
    };
    sim.environment.bodies.push(EnvBody {
        name: "wall".into(),
        kind: BodyKind::Static,
        pose: Pose::from_translation([0.0, 2.0, 0.25]),
        geoms: vec![wall],
        mass: 1.0,
    });
    let mut s = still(&sim);
    s.run_steps(20);
    let ranges = s.sensors(0).unwrap().laser[0].clone();
    assert_eq!(ranges.len(), 5, "beams at -30, -15, 0, 15, 30 deg");
    let origin_y = 0.288 + 0.07;
    let straight = 1.95 - origin_y;
    for (r, a) in ranges.iter().zip([-30.0f64, -15.0, 0.0, 15.0, 30.0]) {
        let expected = straight / a.to_radians().cos();
        assert!(
            (r - expected).abs() < 0.01,
            "beam {a} deg: {r} m, expected {expected} m"
        );
    }
}

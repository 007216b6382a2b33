//! The real-robot mode against an emulated Dynamixel bus on a pseudo-terminal: the
//! kernel's goal positions reach the servos, their readings come back into the data file,
//! a servo that stops answering ends the run with a timeout, bad ports and ids are
//! reported, and the torque is off at the end in every case.

mod common;

use std::path::Path;
use std::sync::atomic::AtomicBool;

use proleg::control::{ModuleRegistry, load_simulation};
use proleg::data::export::{SeriesSelector, XAxis, for_each_row};
use proleg::robot_io::dynamixel::DynamixelChain;
use proleg::robot_io::dynamixel::table::position_raw;
use proleg::robot_io::emulator::EmulatedBus;
use proleg::robot_io::real_mode::{RealOptions, kernel_for, run};
use proleg::robot_io::{Info, RobotControl, RobotError, Target};

const CONFIG: &str = "configs/snake5p_real.simulation.xml";

fn sim() -> proleg::config::Simulation {
    load_simulation(common::root().join(CONFIG)).unwrap_or_else(|e| panic!("{e}"))
}

fn chain(bus: &EmulatedBus, sim: &proleg::config::Simulation) -> DynamixelChain {
    DynamixelChain::new(
        bus.path(),
        None,
        sim.robot.servos.clone(),
        &sim.robot.pattern(),
    )
}

fn options(duration: f64) -> RealOptions {
    RealOptions {
        duration: Some(duration),
        read_every: Some(10),
        every: Some(10),
        seed: 1,
    }
}

/// One column of a data file.
fn column(file: &Path, series: &str) -> Vec<f64> {
    let wanted = [SeriesSelector::parse(series).unwrap()];
    let mut values = Vec::new();
    for_each_row(file, XAxis::SimTime, &wanted, |_, _, row| {
        values.push(row[0]);
        Ok(())
    })
    .unwrap();
    values
}

#[test]
fn the_kernel_drives_the_emulated_servos_and_their_readings_are_recorded() {
    let sim = sim();
    let bus = EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0).unwrap();
    // One answer half-way arrives garbled (line noise): that read-back is skipped.
    bus.garble_after(1000);
    let mut robot = chain(&bus, &sim);
    let data = common::scratch("real-mode").join("real.data.xml");
    let stop = AtomicBool::new(false);
    let s = run(
        &sim,
        &ModuleRegistry::standard(),
        &mut robot,
        &options(1.0),
        Some(&data),
        &stop,
    )
    .unwrap();
    assert_eq!(s.error, None);
    assert_eq!(s.shutdown_error, None);
    assert_eq!(s.steps, 1000);
    assert_eq!((s.reads, s.failed_reads), (100, 1));
    assert_eq!(s.samples, 100);
    // Every step's goals went out as one sync write (plus the start pose and torque on/off).
    let stats = bus.stats();
    assert!(stats.sync_writes >= 1002, "{stats:?}");
    assert_eq!(stats.sync_reads, 101);
    // The last goals are the kernel's angles of the last step, through the servo map.
    let mut kernel = kernel_for(&sim, 1, &ModuleRegistry::standard()).unwrap();
    let dt = sim.files.simulation.properties.step_width;
    let mut last = Vec::new();
    let zeros = vec![0.0; 5];
    for step in 0..1000u64 {
        last = kernel.compute(step as f64 * dt, dt, step, &zeros).to_vec();
    }
    let servos = bus.servos();
    for (servo, angle) in servos.iter().zip(&last) {
        assert_eq!(servo.goal(), position_raw(*angle), "servo {}", servo.id);
        assert!(!servo.torque(), "servo {} left with torque on", servo.id);
    }
    // The servos moved, and what they measured is in the data file.
    let real = column(&data, "Robot_Data/real_joint_positions[4]");
    let desired = column(&data, "Robot_Data/desired_joint_positions[4]");
    assert_eq!(real.len(), 100);
    let swing = real.iter().cloned().fold(f64::MIN, f64::max)
        - real.iter().cloned().fold(f64::MAX, f64::min);
    assert!(swing > 40.0, "the head joint swung {swing} deg");
    let err: f64 = real
        .iter()
        .zip(&desired)
        .map(|(r, d)| (r - d).abs())
        .sum::<f64>()
        / 100.0;
    assert!(
        err < 15.0,
        "mean distance between measured and desired {err} deg"
    );
    assert!(
        column(&data, "Robot_Data/servo_currents[0]")
            .iter()
            .all(|c| *c > 0.0)
    );
    assert_eq!(
        column(&data, "PatternGenerator_sinusoidal/Angle[4]").len(),
        100,
        "the module's series are recorded too"
    );
}

#[test]
fn a_servo_that_stops_answering_ends_the_run_with_torque_off() {
    let sim = sim();
    let bus = EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0).unwrap();
    bus.set_silent_after(3, 300);
    let mut robot = chain(&bus, &sim);
    let data = common::scratch("real-timeout").join("cut.data.xml");
    let stop = AtomicBool::new(false);
    let s = run(
        &sim,
        &ModuleRegistry::standard(),
        &mut robot,
        &options(5.0),
        Some(&data),
        &stop,
    )
    .unwrap();
    assert_eq!(
        s.error.as_deref(),
        Some("servo 3 did not answer (timeout)"),
        "{s:?}"
    );
    assert!(s.steps > 100 && s.steps < 5000, "{} steps", s.steps);
    // Steps are paced in real time: the wall time covers them, error or not.
    let dt = sim.files.simulation.properties.step_width;
    assert!(
        s.wall >= (s.steps - 1) as f64 * dt,
        "{} s for {} steps",
        s.wall,
        s.steps
    );
    assert_eq!(s.failed_reads, 3, "three failures in a row stop the run");
    assert_eq!(s.shutdown_error, None);
    assert!(bus.servos().iter().all(|servo| !servo.torque()));
    // The data file is closed and readable up to the error.
    assert!(column(&data, "Robot_Data/real_joint_positions[0]").len() >= 10);
}

#[test]
fn commands_requests_and_connection_errors() {
    let sim = sim();
    let bus = EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0).unwrap();
    let mut robot = chain(&bus, &sim);
    assert_eq!(robot.enable_servos(true), Err(RobotError::NotConnected));
    robot.connect().unwrap();
    assert_eq!(robot.meta().ids, [1, 2, 3, 4, 5]);
    assert_eq!(robot.meta().topology, "PPPPP");
    robot.send_command("torque", &[1.0], Target::Id(2)).unwrap();
    let mut torque = [0.0; 5];
    robot.request(Info::Torque, &mut torque).unwrap();
    assert_eq!(torque, [0.0, 1.0, 0.0, 0.0, 0.0]);
    let mut temps = [0.0; 5];
    robot.request(Info::Temperatures, &mut temps).unwrap();
    assert!(temps.iter().all(|t| *t > 20.0));
    assert!(matches!(
        robot.send_command("dance", &[], Target::All),
        Err(RobotError::Command(m)) if m.contains("unknown command")
    ));
    assert!(matches!(
        robot.send_command("torque", &[1.0], Target::Id(9)),
        Err(RobotError::Command(m)) if m.starts_with("servo 9 is not one of")
    ));
    assert!(matches!(
        robot.set_joint_angles(&[0.0; 3]),
        Err(RobotError::Command(m)) if m == "3 angles for 5 joints"
    ));
    // A small negative velocity followed by a position whose low byte is FD makes the
    // answer carry `FF FF FF FD FD` (byte stuffing, as the protocol wants it); the
    // readings still come through.
    bus.hold_present(2, 0x05FD, -3);
    let mut readings = proleg::robot_io::Readings::new(5);
    robot.read(&mut readings).unwrap();
    let expected = proleg::robot_io::dynamixel::table::position_deg(0x05FD);
    assert!(
        (readings.positions[1] - expected).abs() < 1e-9,
        "{readings:?}"
    );
    assert!(
        (readings.speeds[1] + 3.0 * 0.229 * 6.0).abs() < 1e-9,
        "{readings:?}"
    );
    robot.send_command("torque", &[0.0], Target::All).unwrap();
    robot.disconnect();

    // A servo missing from the bus: connecting names it.
    let short = EmulatedBus::start(&[1, 2, 4, 5], 600.0).unwrap();
    let mut robot = chain(&short, &sim);
    assert_eq!(robot.connect(), Err(RobotError::Timeout { id: 3 }));
    assert!(!robot.is_connected());
    // A port that does not exist.
    let mut robot = DynamixelChain::new(
        Path::new("/dev/proleg-no-such-port"),
        None,
        sim.robot.servos.clone(),
        "PPPPP",
    );
    match robot.connect() {
        Err(RobotError::Port { port, .. }) => assert_eq!(port, "/dev/proleg-no-such-port"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_cli_runs_the_real_robot_mode_on_the_emulator() {
    let bus = EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0).unwrap();
    let data = common::scratch("real-cli").join("cli.data.xml");
    let (ok, out, err) = common::proleg(&[
        "robot",
        CONFIG,
        "--port",
        bus.path().to_str().unwrap(),
        "--duration",
        "0.5",
        "--data",
        data.to_str().unwrap(),
    ]);
    assert!(ok, "{out}\n{err}");
    for needle in ["steps           500", "torque off      yes", "(16 samples)"] {
        assert!(out.contains(needle), "{needle} missing in\n{out}");
    }
    assert!(
        bus.servos()
            .iter()
            .all(|s| !s.torque() && s.goals_written >= 500)
    );
    // `proleg run` on the real-robot file simulates the twin and says how to drive servos.
    let (ok, out, err) = common::proleg(&["run", CONFIG, "--duration", "0.1"]);
    assert!(ok, "{err}");
    assert!(
        out.contains("Real Robot Control: this run simulates the robot's twin")
            && out.contains("--port PORT"),
        "{out}"
    );
    let (ok, _, err) = common::proleg(&["robot", CONFIG, "--port", "/dev/proleg-no-such-port"]);
    assert!(!ok);
    assert!(
        err.contains("cannot open /dev/proleg-no-such-port"),
        "{err}"
    );
}

/// The experiment-1 simulation with its robot file's `<Servos>` replaced by `servos`.
fn with_servos(name: &str, servos: &str) -> Result<proleg::config::Simulation, String> {
    let root = common::root();
    let dir = common::scratch(name);
    let robot = std::fs::read_to_string(root.join("configs/robots/snake5p.robot.xml")).unwrap();
    let start = robot.find("  <Servos").unwrap();
    let end = robot.find("</Servos>").unwrap() + "</Servos>".len();
    let robot = format!("{}{servos}{}", &robot[..start], &robot[end..]).replace(
        "../parts/",
        &format!("{}/", root.join("configs/parts").display()),
    );
    std::fs::write(dir.join("r.robot.xml"), robot).unwrap();
    let sim = std::fs::read_to_string(root.join(CONFIG))
        .unwrap()
        .replace("robots/snake5p.robot.xml", "r.robot.xml")
        .replace(
            "actuation/",
            &format!("{}/", root.join("configs/actuation").display()),
        )
        .replace(
            "environments/",
            &format!("{}/", root.join("configs/environments").display()),
        );
    std::fs::write(dir.join("r.simulation.xml"), sim).unwrap();
    load_simulation(dir.join("r.simulation.xml")).map_err(|e| e.to_string())
}

#[test]
fn servo_maps_are_checked_against_the_robot() {
    let ok = with_servos(
        "servos-ok",
        r#"<Servos baud="57600"><Servo joint="J1" id="11" offset="10" direction="-1"/><Servo joint="J2" id="12"/><Servo joint="J3" id="13"/><Servo joint="J4" id="14"/><Servo joint="J5" id="15"/></Servos>"#,
    )
    .unwrap();
    let m = &ok.robot.servos;
    assert_eq!(m.baud, 57600);
    assert_eq!(m.joints[0].id, 11);
    // Joint angle 20 deg -> servo angle -20 + 10 = -10 deg, and back.
    assert_eq!(m.joints[0].servo_angle(20.0), -10.0);
    assert_eq!(m.joints[0].joint_angle(-10.0), 20.0);
    for (name, servos, needle) in [
        (
            "servos-unknown",
            r#"<Servos><Servo joint="J9" id="1"/></Servos>"#,
            "the robot has no such joint",
        ),
        (
            "servos-twice",
            r#"<Servos><Servo joint="J1" id="1"/><Servo joint="J2" id="1"/></Servos>"#,
            "servo id 1 is used twice",
        ),
        (
            "servos-missing",
            r#"<Servos><Servo joint="J1" id="1"/></Servos>"#,
            "no servo for joint(s) J2, J3, J4, J5",
        ),
    ] {
        let e = with_servos(name, servos).unwrap_err();
        assert!(e.contains("r.robot.xml:") && e.contains(needle), "{e}");
    }
}

#[test]
fn a_policy_module_drives_the_emulated_servos_with_the_real_robot_s_senses() {
    // The demo sine plus a Policy whose network reads the 18 inputs a real robot gives
    // (angles and speeds from the servos' readings, gravity and velocity zero, the sine's
    // phase): it runs (no failure, which would output 0) and its offsets reach the servos.
    use proleg::config::actuation::ParamValue;
    use proleg::config::resolve::{ModuleInstance, ParamAssignment, WeightsFile};
    use proleg::control::policy::{Activation, Layer, PolicyNet};
    let mut sim = sim();
    let weights = common::scratch("real-mode-policy").join("offsets.safetensors");
    let bias = [0.5, -0.5, 0.25, -0.25, 0.5];
    PolicyNet::new(
        vec![Layer {
            weight: vec![0.0; 5 * 18],
            bias: bias.to_vec(),
        }],
        Activation::Tanh,
    )
    .unwrap()
    .write(&weights)
    .unwrap();
    let registry = ModuleRegistry::standard();
    sim.actuation.modules.push(ModuleInstance {
        descriptor: registry.get("Policy").unwrap().clone(),
        joints: proleg::config::mask::JointMask(vec![true; 5]),
        params: vec![ParamAssignment {
            name: "Amplitude",
            value: ParamValue::Uniform(20.0),
        }],
        weights: Some(WeightsFile {
            path: weights.clone(),
            bytes: std::fs::read(&weights).unwrap().into(),
        }),
        pos: Default::default(),
    });
    let bus = EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0).unwrap();
    let mut robot = chain(&bus, &sim);
    let stop = AtomicBool::new(false);
    let s = run(&sim, &registry, &mut robot, &options(0.5), None, &stop).unwrap();
    assert_eq!(s.error, None);
    // The goals are the sine's of the last step plus each joint's 20 deg x bias (the
    // network's weights are zero: its output is its bias whatever it reads).
    let mut sine = kernel_for(
        &load_simulation(common::root().join(CONFIG)).unwrap(),
        1,
        &registry,
    )
    .unwrap();
    let dt = sim.files.simulation.properties.step_width;
    let mut last = Vec::new();
    for step in 0..500u64 {
        last = sine.compute(step as f64 * dt, dt, step, &[0.0; 5]).to_vec();
    }
    for ((servo, angle), b) in bus.servos().iter().zip(&last).zip(bias) {
        assert_eq!(
            servo.goal(),
            position_raw(angle + 20.0 * b),
            "servo {}",
            servo.id
        );
    }
}

/// A faulty line: answers that arrive split or after noise are read whole; one cut short
/// is a timeout naming its servo; a corrupted one is a bus error; none is a panic. (A
/// repeated answer may arrive after the next request went out and is then taken for the
/// next servo's, a wrong-id error, or not: a race the `dynamixel_bus` fuzz target meets.)
#[test]
fn a_faulty_line_is_read_through_or_reported() {
    use proleg::robot_io::emulator::line::LineFault;
    let sim = sim();
    let bus = EmulatedBus::start(&[1, 2, 3, 4, 5], 600.0).unwrap();
    bus.set_faults(
        [
            LineFault::Split(4),
            LineFault::Noise(vec![0xFF, 0xFF, 0x00]),
        ]
        .into(),
    );
    let mut robot = chain(&bus, &sim);
    robot.connect().unwrap();
    let mut readings = proleg::robot_io::Readings::new(5);
    robot.read(&mut readings).unwrap();
    bus.set_faults([LineFault::Truncate(6)].into());
    assert_eq!(
        robot.request(Info::Temperatures, &mut [0.0; 5]),
        Err(RobotError::Timeout { id: 1 })
    );
    bus.set_faults([LineFault::Corrupt { at: 9, xor: 0x40 }].into());
    match robot.request(Info::Errors, &mut [0.0; 5]) {
        Err(RobotError::Bus(why)) => assert!(why.contains("servo 1"), "{why}"),
        other => panic!("{other:?}"),
    }
    robot.disconnect();
}

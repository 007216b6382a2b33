//! Servo identification against a known truth: an emulated Dynamixel chain whose servos
//! hide their gain, top speed, dead band and latency is driven by the real-robot mode for
//! 20 s; `calibrate` recovers them from the recording, and the replay then tracks the
//! recording several times better than the robot file's servo model did. Written with
//! `-o` into a folder far from `configs/` and moved, its simulation runs the calibrated
//! robot. A 3-s recording
//! is too short for the latency, and a recording of another robot is refused. On a gait
//! recorded on the same chain, the simulation with the calibrated servos tracks the
//! recording several times closer than with the robot file's.

mod common;

use std::path::Path;
use std::sync::atomic::AtomicBool;

use proleg::calibrate::fit::{Identified, Unidentifiable};
use proleg::calibrate::recording::read_recording;
use proleg::calibrate::{CalibrateError, CalibrateOptions, calibrate};
use proleg::control::{ModuleRegistry, load_simulation};
use proleg::robot_io::dynamixel::DynamixelChain;
use proleg::robot_io::emulator::EmulatedBus;
use proleg::robot_io::emulator::servo::ServoDynamics;
use proleg::robot_io::real_mode::{RealOptions, run};

/// The hidden truth: none of them the robot file's.
const TRUTH: ServoDynamics = common::HIDDEN_SERVOS;

/// The calibration recording's gait: the tail joints slow (the dead band and the gain
/// show), the others fast (the top speed and the lag).
const SWEEP: &str = "configs/calibration_sweep.simulation.xml";

/// Records `seconds` of `sim`'s gait on the emulated chain into `data`.
fn record(sim: &proleg::config::Simulation, seconds: f64, data: &Path) {
    let bus = EmulatedBus::start_with(&[1, 2, 3, 4, 5], TRUTH).unwrap();
    let mut robot = DynamixelChain::new(
        bus.path(),
        None,
        sim.robot.servos.clone(),
        &sim.robot.pattern(),
    );
    let options = RealOptions {
        duration: Some(seconds),
        read_every: Some(10),
        every: Some(10),
        seed: 1,
    };
    let stop = AtomicBool::new(false);
    let s = run(
        sim,
        &ModuleRegistry::standard(),
        &mut robot,
        &options,
        Some(data),
        &stop,
    )
    .unwrap();
    assert_eq!(s.error, None);
}

#[test]
#[expect(
    clippy::too_many_lines,
    reason = "one scenario, read top to bottom (tests may run past 80 lines)"
)]
fn hidden_servo_dynamics_are_recovered_from_a_recording() {
    let dir = common::scratch("calibrate");
    let sim = load_simulation(common::root().join(SWEEP)).unwrap();
    let data = dir.join("sweep.data.xml");
    record(&sim, 20.0, &data);
    let rec = read_recording(&data).unwrap();
    let options = CalibrateOptions {
        per_joint: false,
        runs: 3,
        seed: 1,
    };
    // `proleg calibrate DATA --config SWEEP -o FAR`, FAR where no folder above holds the
    // shipped parts: a folder that stands alone.
    let far = std::env::temp_dir().join(format!("proleg-calibrated-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&far);
    let written = proleg::cli::calibrate::run(
        &proleg::cli::calibrate::CalibrateArgs {
            data: data.clone(),
            config: common::root().join(SWEEP),
            out: Some(far.join("calibrated")),
            per_joint: options.per_joint,
            runs: options.runs,
            seed: options.seed,
            check: None,
            check_data: None,
            port: None,
            check_seconds: None,
        },
        &ModuleRegistry::standard(),
    )
    .unwrap();
    let report = written.report.clone();
    let g = &report.groups[0];
    let within = |id: &Identified, truth: f64, tol: f64, what: &str| {
        let v = id
            .value()
            .unwrap_or_else(|| panic!("{what}: {id:?}\n{report}"));
        assert!(
            (v - truth).abs() <= tol,
            "{what}: {v} against {truth}\n{report}"
        );
    };
    within(&g.gain, TRUTH.gain, 0.1 * TRUTH.gain, "gain");
    within(
        &g.max_vel_deg_s,
        TRUTH.speed_deg_s,
        0.1 * TRUTH.speed_deg_s,
        "top speed",
    );
    within(
        &g.dead_band_deg,
        TRUTH.dead_band_deg,
        0.1 * TRUTH.dead_band_deg,
        "dead band",
    );
    within(
        &g.latency_s,
        TRUTH.latency_s,
        rec.sample_period(),
        "latency",
    );
    for (j, (before, after)) in report.rms_before.iter().zip(&report.rms_after).enumerate() {
        assert!(
            after * 3.0 <= *before,
            "J{}: {before} -> {after}\n{report}",
            j + 1
        );
    }

    // The folder moved elsewhere, its simulation runs the calibrated robot: its joints
    // carry the fitted values.
    let calibrated = far.join("calibrated");
    let moved = far.join("moved elsewhere");
    std::fs::rename(&calibrated, &moved).unwrap();
    let simulation = written.simulation.as_ref().expect("a simulation with -o");
    let simulation = moved.join(simulation.strip_prefix(&calibrated).unwrap());
    let (ok, text, err) = common::proleg(&["run", simulation.to_str().unwrap()]);
    assert!(ok && text.contains("displacement"), "{err}");
    let source = proleg::config::RecordingSource::new(&proleg::config::FsSource);
    let calibrated =
        proleg::config::load_simulation_with(&source, &simulation, &ModuleRegistry::standard())
            .unwrap();
    for (path, _) in source.files() {
        assert!(Path::new(&path).starts_with(&moved), "{path} is outside");
    }
    let j = &calibrated.robot.joints[2];
    assert_eq!(
        j.servo_gain,
        Some((g.gain.value().unwrap() * 1e4).round() / 1e4)
    );
    assert!((j.latency_s - g.latency_s.value().unwrap()).abs() < 1e-4);
    assert!((j.dead_band_deg - g.dead_band_deg.value().unwrap()).abs() < 1e-4);
    std::fs::remove_dir_all(&far).unwrap();

    // What it buys on a gait: the demo sine recorded on the same chain against its
    // simulation on the floor, with the robot file's servos and with the calibrated ones.
    let demo = load_simulation(common::root().join("configs/snake5p_real.simulation.xml")).unwrap();
    let gait = dir.join("gait.data.xml");
    record(&demo, 4.0, &gait);
    let gap = proleg::calibrate::check::gait_gap(
        &read_recording(&gait).unwrap(),
        &demo,
        &report,
        &ModuleRegistry::standard(),
    )
    .unwrap();
    for (j, (before, after)) in gap.before.iter().zip(&gap.after).enumerate() {
        assert!(
            after * 3.0 <= *before,
            "J{}: {before} -> {after}\n{gap}",
            j + 1
        );
    }

    // Three seconds: the goals turn back too rarely to tell the latency.
    let short = dir.join("short.data.xml");
    record(&sim, 3.0, &short);
    let report = calibrate(&read_recording(&short).unwrap(), &sim, &options).unwrap();
    assert!(
        matches!(
            report.groups[0].latency_s,
            Identified::Unidentifiable(Unidentifiable::TooFewReversals { .. })
        ),
        "{report}"
    );
    assert!(
        report.to_string().contains("too short for the latency"),
        "{report}"
    );

    // A robot of another joint count is refused, naming both.
    let other =
        load_simulation(common::root().join("configs/snake8py_slope.simulation.xml")).unwrap();
    let e = calibrate(&rec, &other, &options).unwrap_err();
    assert!(
        matches!(
            e,
            CalibrateError::JointCount {
                found: 5,
                expected: 7,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn the_simulator_honours_a_servo_latency_and_dead_band() {
    use proleg::sim::{BuildOptions, Simulator};
    let nominal = load_simulation(common::root().join(SWEEP)).unwrap();
    let registry = ModuleRegistry::standard();
    let angles_after = |sim: &proleg::config::Simulation, steps: u64| -> Vec<f64> {
        let mut s = Simulator::with_registry(sim, &BuildOptions::default(), &registry).unwrap();
        s.run_steps(steps);
        s.joint_states(0).unwrap().iter().map(|j| j.angle).collect()
    };
    // 40 ms into the fast joints' swing: moving without latency, still with 50 ms of it.
    let mut late = nominal.clone();
    for j in &mut late.robot.joints {
        j.latency_s = 0.05;
    }
    let moved = angles_after(&nominal, 40);
    let held = angles_after(&late, 40);
    assert!(moved[4].abs() > 1.0, "{moved:?}");
    assert!(held[4].abs() < 0.2, "{held:?}");
    // A dead band wider than the swing keeps a joint where it is.
    let mut slack = nominal.clone();
    for j in &mut slack.robot.joints {
        j.dead_band_deg = 90.0;
    }
    let still = angles_after(&slack, 200);
    assert!(still.iter().all(|a| a.abs() < 0.5), "{still:?}");
}

#[test]
fn bad_recordings_say_what_is_missing() {
    let dir = common::scratch("calibrate-bad");
    let config = common::root().join(SWEEP);
    let sim = load_simulation(&config).unwrap();
    let data = dir.join("rec.data.xml");
    record(&sim, 0.3, &data);
    let text = std::fs::read_to_string(&data).unwrap();
    let calibrate_cli = |file: &Path| {
        common::proleg(&[
            "calibrate",
            file.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "-o",
            dir.to_str().unwrap(),
        ])
    };
    // No real positions recorded.
    let no_real = dir.join("no_real.data.xml");
    std::fs::write(
        &no_real,
        text.replace("real_joint_positions", "other_positions"),
    )
    .unwrap();
    let (ok, _, err) = calibrate_cli(&no_real);
    assert!(
        !ok && err.contains("real_joint_positions") && err.contains("no_real.data.xml"),
        "{err}"
    );
    // 30 samples are too few.
    let (ok, _, err) = calibrate_cli(&data);
    assert!(
        !ok && err.contains("30 samples") && err.contains("at least 50"),
        "{err}"
    );
    // A file that is not there.
    let (ok, _, err) = calibrate_cli(&dir.join("none.data.xml"));
    assert!(!ok && err.contains("none.data.xml"), "{err}");
}

//! The core simulation on the experiment-1 set-up (snake5p, flat floor, sine 40° / 55°):
//! the robot crawls, the phase sign sets the direction, parameters matter, servos keep
//! their limits, and runs are deterministic. Physics-heavy: run with `--release`.

mod common;

use proleg::config::Simulation;
use proleg::control::load_simulation;
use proleg::sim::{BuildOptions, Simulator};

fn demo() -> Simulation {
    load_simulation(common::root().join("configs/demo.simulation.xml")).unwrap()
}

fn simulator(sim: &Simulation) -> Simulator {
    Simulator::new(
        sim,
        &BuildOptions {
            robots: 1,
            seed: 1,
            record: true,
            ..Default::default()
        },
    )
    .unwrap()
}

/// Runs `seconds` and returns the start and end centre of mass.
fn crawl(
    sim: &Simulation,
    seconds: f64,
    setup: impl FnOnce(&mut Simulator),
) -> ([f64; 3], [f64; 3], Simulator) {
    let mut s = simulator(sim);
    setup(&mut s);
    let r = s.run_for(seconds);
    (r.start_com, r.end_com, s)
}

#[test]
fn uniform_sine_crawls_forward_head_first() {
    let (start, end, s) = crawl(&demo(), 30.0, |_| {});
    let dy = end[1] - start[1];
    eprintln!("experiment 1, uniform 40 deg / 55 deg: {dy:.3} m forward in 30 s");
    assert!(dy > 1.0, "moved only {dy} m along +y");
    // Straight, not in a circle: the heading stays near +y and progress is steady.
    let t = s.track(0).unwrap();
    assert!(
        t.heading.iter().all(|h| (h - 90.0).abs() < 30.0),
        "heading left +y by more than 30 deg"
    );
    let third = t.len() / 3;
    let (y1, y2, y3) = (t.com[third][1], t.com[2 * third][1], t.com[t.len() - 1][1]);
    assert!(
        start[1] < y1 && y1 < y2 && y2 < y3,
        "not steady: {y1} {y2} {y3}"
    );
}

#[test]
fn negative_phase_difference_crawls_backward() {
    let (start, end, _) = crawl(&demo(), 20.0, |s| {
        s.set_parameter(0, 0, "Phase_Difference", None, -55.0)
            .unwrap()
    });
    let dy = end[1] - start[1];
    eprintln!("phase difference -55 deg: {dy:.3} m in 20 s");
    assert!(dy < -0.5, "moved {dy} m along +y");
}

#[test]
fn zero_amplitude_stays_put() {
    let (start, end, _) = crawl(&demo(), 20.0, |s| {
        s.set_parameter(0, 0, "Amplitude", None, 0.0).unwrap()
    });
    let d = ((end[0] - start[0]).powi(2) + (end[1] - start[1]).powi(2)).sqrt();
    assert!(d < 0.01, "moved {d} m with zero amplitude");
}

#[test]
fn tail_amplitude_changes_the_result() {
    let sim = demo();
    let (s0, e0, _) = crawl(&sim, 20.0, |_| {});
    let (s1, e1, _) = crawl(&sim, 20.0, |s| {
        s.set_parameter(0, 0, "Amplitude", Some(0), 0.0).unwrap()
    });
    let (d0, d1) = (e0[1] - s0[1], e1[1] - s1[1]);
    eprintln!("20 s: uniform {d0:.3} m, tail amplitude 0: {d1:.3} m");
    assert!(
        (d0 - d1).abs() > 0.01,
        "tail amplitude made no difference: {d0} vs {d1}"
    );
}

#[test]
fn same_seed_same_trajectory() {
    let hash = || {
        let mut s = simulator(&demo());
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for _ in 0..50 {
            s.run_steps(100);
            for v in s
                .com(0)
                .unwrap()
                .iter()
                .chain(s.joint_states(0).unwrap().iter().map(|j| &j.angle))
            {
                h = (h ^ v.to_bits()).wrapping_mul(0x0100_0000_01b3);
            }
        }
        h
    };
    assert_eq!(hash(), hash());
}

#[test]
fn servos_keep_torque_and_speed_limits_on_the_floor() {
    let sim = demo();
    let mut s = simulator(&sim);
    let max_torque = sim.robot.joints[0].max_torque;
    let max_speed = sim.robot.joints[0].max_vel.to_degrees();
    let (mut samples, mut fast) = (0usize, 0usize);
    let mut worst_torque: f64 = 0.0;
    for _ in 0..10_000 {
        s.step();
        for j in s.joint_states(0).unwrap() {
            samples += 1;
            worst_torque = worst_torque.max(j.torque.abs());
            assert!(
                j.commanded_velocity.abs() <= max_speed + 1e-9,
                "commanded {} deg/s",
                j.commanded_velocity
            );
            if j.velocity.abs() > max_speed * 1.05 {
                fast += 1;
            }
        }
    }
    eprintln!(
        "worst applied torque {worst_torque:.3} N·m (max {max_torque}); {fast} of {samples} joint-steps above max speed"
    );
    assert!(
        worst_torque <= max_torque * 1.001,
        "torque {worst_torque} beyond {max_torque}"
    );
    assert!(
        worst_torque > 0.25 * max_torque,
        "torque readings look dead: {worst_torque}"
    );
    assert!(
        (fast as f64) < 0.01 * samples as f64,
        "{fast} of {samples} joint-steps above max speed"
    );
}

#[test]
fn servo_follows_a_sine_without_gravity() {
    let mut sim = demo();
    sim.environment.physics.gravity = [0.0; 3];
    let mut s = simulator(&sim);
    s.set_parameter(0, 0, "Frequency", None, 1.0).unwrap();
    s.set_parameter(0, 0, "Amplitude", None, 40.0).unwrap();
    s.run_steps(1000);
    let (mut sq, mut n) = (0.0, 0usize);
    for _ in 0..5000 {
        s.step();
        let desired = s.kernel(0).unwrap().desired().to_vec();
        for (j, d) in s.joint_states(0).unwrap().iter().zip(desired) {
            sq += (d - j.angle).powi(2);
            n += 1;
        }
    }
    let rms = (sq / n as f64).sqrt();
    eprintln!("tracking a 1 Hz, 40 deg sine without gravity: RMS error {rms:.2} deg");
    assert!(rms < 5.0, "RMS tracking error {rms} deg");
}

#[test]
fn robots_of_a_batch_are_independent() {
    let sim = demo();
    let mut batch = Simulator::new(
        &sim,
        &BuildOptions {
            robots: 3,
            seed: 1,
            record: false,
            ..Default::default()
        },
    )
    .unwrap();
    batch.set_parameter(1, 0, "Amplitude", None, 0.0).unwrap();
    batch
        .set_parameter(2, 0, "Phase_Difference", None, -55.0)
        .unwrap();
    batch.run_steps(10_000);
    let mut single = simulator(&sim);
    single.run_steps(10_000);
    // Robot 0 is not disturbed by the others sharing its world.
    assert_eq!(batch.com(0).unwrap(), single.com(0).unwrap());
    let (y0, y1, y2) = (
        batch.com(0).unwrap()[1],
        batch.com(1).unwrap()[1],
        batch.com(2).unwrap()[1],
    );
    let start = 0.144;
    assert!(
        y0 > start + 0.3 && (y1 - start).abs() < 0.01 && y2 < start - 0.1,
        "{y0} {y1} {y2}"
    );
}

#[test]
fn joint_limits_stop_a_joint_the_servo_cannot_hold() {
    let mut sim = demo();
    sim.environment.physics.gravity = [0.0; 3];
    for j in &mut sim.robot.joints {
        j.limits_deg = [-10.0, 10.0];
        j.max_torque = 0.001;
    }
    let mut s = simulator(&sim);
    s.set_parameter(0, 0, "Amplitude", None, 0.0).unwrap();
    s.run_steps(10);
    // Spin the head about the pitch axis, far faster than the weak servo can brake.
    s.set_link_angular_velocity(0, 5, [20.0, 0.0, 0.0]).unwrap();
    let mut worst: f64 = 0.0;
    for _ in 0..500 {
        s.step();
        worst = worst.max(s.joint_states(0).unwrap()[4].angle.abs());
    }
    eprintln!("head joint pushed at 20 rad/s against ±10 deg limits: reached {worst:.2} deg");
    assert!(worst > 5.0, "the push did not move the joint ({worst} deg)");
    assert!(worst < 11.0, "the limit did not hold: {worst} deg");
}

#[test]
fn both_cpgs_are_standard_modules_and_the_phase_chain_crawls() {
    let sim = load_simulation(common::root().join("configs/gait_from_scratch_cpg.simulation.xml"))
        .unwrap();
    let registry = proleg::control::ModuleRegistry::standard();
    assert!(registry.get("PatternGenerator_cpg_matsuoka").is_some());
    // The experiment-1 wave, made by the phase-oscillator chain instead of the sine.
    let (start, end, _) = crawl(&sim, 10.0, |s| {
        for (name, value) in [
            ("Amplitude", 40.0),
            ("Phase_Difference", 55.0),
            ("Frequency", 1.0),
        ] {
            s.set_parameter(0, 0, name, None, value).unwrap();
        }
    });
    let dy = end[1] - start[1];
    eprintln!("phase-oscillator CPG, 40 deg / 55 deg / 1 Hz: {dy:.3} m in 10 s");
    assert!(dy > 0.5, "moved only {dy} m along +y");
}

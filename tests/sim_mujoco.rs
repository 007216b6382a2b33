//! The MuJoCo engine inside the tool: the demo crawls on it through the same pipeline,
//! its runs are bit-identical whatever runs beside them, its servos follow the same model
//! as rapier's, and a missing library, a file that is not MuJoCo, another MuJoCo version
//! or a model MuJoCo rejects is one line and exit 1 (never a panic, never an exit from
//! inside MuJoCo).

mod common;

use proleg::config::simulation::EngineKind;
use proleg::control::load_simulation;
use proleg::measure::ground_distance;
use proleg::sim::{BuildOptions, Simulator};

fn demo() -> proleg::config::Simulation {
    load_simulation(common::root().join("configs/demo.simulation.xml"))
        .unwrap()
        .with_engine(Some(EngineKind::Mujoco))
}

/// Robot 0's centre of mass after `seconds`, and every joint angle every 10 steps, as bits.
fn trajectory(sim: &proleg::config::Simulation, seconds: f64) -> ([f64; 3], Vec<u64>) {
    let mut s = Simulator::new(sim, &BuildOptions::default()).unwrap();
    assert_eq!(s.engine_kind(), EngineKind::Mujoco);
    let mut bits = Vec::new();
    for _ in 0..(seconds / 0.01) as usize {
        s.run_steps(10);
        bits.extend(s.joint_states(0).unwrap().iter().map(|j| j.angle.to_bits()));
    }
    (s.com(0).unwrap(), bits)
}

#[test]
fn the_demo_crawls_forward_on_mujoco() {
    if !common::mujoco_here("demo on MuJoCo") {
        return;
    }
    let sim = demo();
    let mut s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
    let start = s.com(0).unwrap();
    s.run_steps(10_000);
    let end = s.com(0).unwrap();
    let d = ground_distance(start, end);
    assert!(d > 0.5, "10 s of the sine gait moved {d} m");
    // It crawls along its chain (+y), not sideways, and stays on the floor.
    assert!(
        end[1] - start[1] > 0.4 && end[2].abs() < 0.1,
        "{start:?} -> {end:?}"
    );
}

#[test]
fn mujoco_runs_are_bit_identical_whatever_runs_beside_them() {
    if !common::mujoco_here("MuJoCo determinism") {
        return;
    }
    let sim = demo();
    let alone = trajectory(&sim, 2.0);
    let beside: Vec<_> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..3)
            .map(|_| scope.spawn(|| trajectory(&sim, 2.0)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for t in beside {
        assert_eq!(t, alone);
    }
}

#[test]
fn a_servo_follows_the_same_model_on_both_engines() {
    if !common::mujoco_here("servo model") {
        return;
    }
    // The demo's sine: the joints track their targets within a few degrees on both.
    for engine in [EngineKind::Rapier, EngineKind::Mujoco] {
        let sim = demo().with_engine(Some(engine));
        let mut s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
        let mut error = 0.0;
        for _ in 0..3000 {
            s.step();
            error += s.tracking_error(0).unwrap();
        }
        let mean = error / 3000.0;
        assert!(mean < 6.0, "{engine}: mean tracking error {mean} deg");
        // The motor's torque stays within the servo's limit.
        let limit = sim.robot.joints[0].max_torque;
        for j in s.joint_states(0).unwrap() {
            assert!(j.torque.abs() <= limit * 1.0001, "{engine}: {j:?}");
        }
    }
}

#[test]
fn the_run_command_takes_the_engine_and_says_which() {
    if !common::mujoco_here("run --engine") {
        return;
    }
    let (ok, out, err) = common::proleg(&[
        "run",
        "configs/demo.simulation.xml",
        "--duration",
        "1",
        "--engine",
        "mujoco",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("physics         mujoco 4.0.0"), "{out}");
}

/// `proleg run --engine mujoco` with `PROLEG_MUJOCO` set to `library`: (ok, stderr).
fn run_with_library(library: &str) -> (bool, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args([
            "run",
            "configs/demo.simulation.xml",
            "--duration",
            "0.1",
            "--engine",
            "mujoco",
        ])
        .current_dir(common::root())
        .env("PROLEG_MUJOCO", library)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_missing_or_foreign_library_is_one_line_and_exit_1() {
    let (ok, err) = run_with_library("/nonexistent/libmujoco.so.4.0.0");
    assert!(!ok);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("MuJoCo 4.0.0 is not installed") && err.contains("install-mujoco"),
        "{err}"
    );
    let libc = [
        "/lib/x86_64-linux-gnu/libc.so.6",
        "/usr/lib/x86_64-linux-gnu/libc.so.6",
    ]
    .into_iter()
    .find(|p| std::path::Path::new(p).exists())
    .expect("libc");
    let (ok, err) = run_with_library(libc);
    assert!(!ok);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("is not MuJoCo 4.0.0's library"), "{err}");
    // Debian's MuJoCo 2.2.2 (scripts/test installs it): another version, said so.
    let old = "/usr/lib/x86_64-linux-gnu/libmujoco.so.2.2.2";
    if std::path::Path::new(old).exists() {
        let (ok, err) = run_with_library(old);
        assert!(!ok);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("is MuJoCo 2.2.2, proleg needs 4.0.0"), "{err}");
    }
    // Nothing else breaks: rapier runs without the library.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["run", "configs/demo.simulation.xml", "--duration", "0.1"])
        .current_dir(common::root())
        .env("PROLEG_MUJOCO", "/nonexistent/libmujoco.so.4.0.0")
        .output()
        .unwrap();
    assert!(out.status.success());
}

#[test]
fn a_model_mujoco_rejects_is_an_error_naming_the_file() {
    if !common::mujoco_here("rejected model") {
        return;
    }
    let mut sim = demo();
    // A negative principal moment, past proleg's loader (which refuses it in a file): no
    // body has it, and MuJoCo's balanceinertia (which repairs rounding of the triangle
    // inequality) does not make it one.
    sim.robot.links[0].inertia = Some(proleg::config::resolve::robot::LinkInertia {
        com: [0.0; 3],
        tensor: [-1e-3, 0.0, 0.0, 0.0, 1e-3, 0.0, 0.0, 0.0, 1e-3],
    });
    let Err(e) = Simulator::new(&sim, &BuildOptions::default()) else {
        panic!("MuJoCo took an impossible inertia");
    };
    let text = e.to_string();
    assert!(
        text.starts_with("MuJoCo rejects the model of") && text.contains("demo.simulation.xml"),
        "{text}"
    );
    assert_eq!(text.lines().count(), 1, "{text}");
}

#[test]
fn dragging_a_robot_moves_it_on_mujoco_as_on_rapier() {
    if !common::mujoco_here("drag on MuJoCo") {
        return;
    }
    for engine in [EngineKind::Rapier, EngineKind::Mujoco] {
        let sim = demo().with_engine(Some(engine));
        let mut s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
        s.run_steps(100);
        let before = s.com(0).unwrap();
        // The viewer's drag: every link of the robot by the same offset.
        let bodies = s.robot_bodies(0).unwrap();
        s.translate_bodies(&bodies, [0.5, -0.25, 0.0]);
        let after = s.com(0).unwrap();
        assert!(
            (after[0] - before[0] - 0.5).abs() < 1e-6 && (after[1] - before[1] + 0.25).abs() < 1e-6,
            "{engine}: {before:?} -> {after:?}"
        );
        s.run_steps(100);
        assert!(s.com(0).unwrap().iter().all(|v| v.is_finite()), "{engine}");
    }
}

#[test]
fn a_stored_mujoco_evaluation_replays_to_its_stored_score() {
    if !common::mujoco_here("replay on MuJoCo") {
        return;
    }
    let dir = common::scratch("mujoco_replay");
    let store = dir.join("ga.sqlite").display().to_string();
    let (ok, out, err) = common::proleg(&[
        "optimize",
        "configs/experiment1_ga.simulation.xml",
        "--max-evals",
        "10",
        "--duration",
        "1",
        "--quiet",
        "--engine",
        "mujoco",
        "--store",
        &store,
    ]);
    assert!(ok, "{err}");
    let best: f64 = out
        .lines()
        .find_map(|l| l.strip_prefix("best score"))
        .and_then(|t| t.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no best score in {out}"));
    let (ok, listing, err) = common::proleg(&["results", &store]);
    assert!(ok, "{err}");
    assert!(listing.contains("genetic algorithm on mujoco"), "{listing}");
    let (ok, out, err) = common::proleg(&["robustness", &store, "--run", "1", "--episodes", "1"]);
    assert!(ok, "{err}");
    assert!(out.contains(", on mujoco"), "{out}");
    let nominal: f64 = out
        .lines()
        .find_map(|l| l.strip_prefix("nominal"))
        .and_then(|t| t.trim().parse().ok())
        .unwrap_or_else(|| panic!("no nominal score in {out}"));
    assert!(
        (nominal - best).abs() < 1e-4,
        "stored {best}, replayed {nominal}"
    );
}

/// Worlds of one file share MuJoCo's compiled model (built once, not on every reset or
/// evaluation); dragging a static body changes the dragged world's model only, and a world
/// built after the drag gets the file's.
#[test]
fn a_static_body_dragged_in_one_world_stays_put_in_the_others() {
    if !common::mujoco_here("shared models") {
        return;
    }
    let sim = demo();
    let world = || Simulator::new(&sim, &BuildOptions::default()).unwrap();
    let (mut a, mut b) = (world(), world());
    let floor = a.environment_bodies()[0].body;
    let z = |s: &Simulator| s.body_position(floor).unwrap()[2];
    let z0 = z(&b);
    a.translate_bodies(&[floor], [0.0, 0.0, -0.5]);
    assert!((z(&a) - (z0 - 0.5)).abs() < 1e-9, "{} vs {z0}", z(&a));
    let mut c = world();
    assert_eq!((z(&b), z(&c)), (z0, z0));
    for s in [&mut a, &mut b, &mut c] {
        s.run_steps(300);
    }
    let height = |s: &Simulator| s.com(0).unwrap()[2];
    assert!(
        height(&a) < height(&b) - 0.2,
        "{} vs {}",
        height(&a),
        height(&b)
    );
    assert_eq!(height(&b).to_bits(), height(&c).to_bits());
}

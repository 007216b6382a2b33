//! A real mouse on the control window (issue 33, point 1): xdotool drives `proleg gui` on an
//! Xvfb server of the test's own. A press on a panel belongs to the panel even when the
//! drag leaves it (the Amplitude slider dragged into the viewer changes Amplitude and moves
//! no floor); a click on Start selects nothing behind the toolbar; a left drag on the
//! ground orbits the camera instead of moving the floor. Input is sent step by step, each
//! step acknowledged by the window two frames after the test said it was sent, so a drag
//! spans several frames at any frame rate and nothing depends on timing.
#![cfg(feature = "gui")]

mod common;

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::window::{Xvfb, get, scratch, state};
use proleg::sim::{BuildOptions, Simulator};

/// Where the demo's floor is when nothing moved it.
fn floor_at_rest() -> [f64; 3] {
    let sim = proleg::control::load_simulation(common::root().join("configs/demo.simulation.xml"))
        .unwrap();
    let s = Simulator::new(&sim, &BuildOptions::default()).unwrap();
    let floor = s.environment_bodies()[0].body;
    s.body_position(floor).unwrap()
}

fn floor_in(s: &[(String, String)]) -> [f64; 3] {
    let v: Vec<f64> = get(s, "environment_0")
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

/// Whether the floor in state `s` is where it rests (to the state's 6 decimals).
fn floor_stays(s: &[(String, String)]) -> bool {
    let (now, rest) = (floor_in(s), floor_at_rest());
    now.iter().zip(rest).all(|(a, b)| (a - b).abs() < 1e-5)
}

/// The demo's control window, driven step by step: it draws a few frames, then for each
/// step waits until the test says the step's input was sent, draws two more frames (it has
/// handled the input) and says so; at the end it writes its state and closes.
struct Driven {
    window: Child,
    id: String,
    dir: PathBuf,
    step: usize,
}

impl Driven {
    fn open(x: &Xvfb, name: &str, steps: usize) -> Driven {
        let dir = scratch(name);
        let script = dir.join("pointer.script");
        let mut text = format!("wait 10\nstate {}\n", dir.join("ack0").display());
        for k in 1..=steps {
            text.push_str(&format!(
                "wait-for file {} 3000\nwait 2\nstate {}\n",
                dir.join(format!("sent{k}")).display(),
                dir.join(format!("ack{k}")).display()
            ));
        }
        text.push_str(&format!(
            "state {}\nquit\n",
            dir.join("state.txt").display()
        ));
        std::fs::write(&script, text).unwrap();
        let window = Command::new(env!("CARGO_BIN_EXE_proleg"))
            .args(["gui", "configs/demo.simulation.xml", "--script"])
            .arg(&script)
            .env("DISPLAY", &x.1)
            .env("XDG_RUNTIME_DIR", scratch(&format!("{name}-xdg")))
            .current_dir(common::root())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("proleg gui");
        let id = x.xdotool(&["search", "--sync", "--onlyvisible", "--name", "proleg"]);
        let id = id.lines().next().expect("the window").to_string();
        x.xdotool(&["windowfocus", "--sync", &id]);
        let mut d = Driven {
            window,
            id,
            dir,
            step: 0,
        };
        d.await_ack();
        d
    }

    /// Waits (at most 5 minutes) until the window acknowledged the current step.
    fn await_ack(&mut self) {
        let ack = self.dir.join(format!("ack{}", self.step));
        let started = Instant::now();
        while !ack.exists() {
            if let Ok(Some(status)) = self.window.try_wait() {
                panic!("the window ended ({status}) before step {}", self.step);
            }
            assert!(
                started.elapsed() < Duration::from_secs(300),
                "no acknowledgement of step {}",
                self.step
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// One step of input: the pointer moved to `at` on the window, then xdotool's `then`
    /// (a press, a release, a click); the window handles it before the next step.
    fn input(&mut self, x: &Xvfb, at: (&str, &str), then: &[&str]) {
        let mut all = vec!["mousemove", "--window", self.id.as_str(), at.0, at.1];
        all.extend(then);
        x.xdotool(&all);
        self.step += 1;
        std::fs::write(self.dir.join(format!("sent{}", self.step)), "").unwrap();
        self.await_ack();
    }

    /// The window's state once it closed.
    fn finish(self) -> Vec<(String, String)> {
        let out = self.window.wait_with_output().expect("the window");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        state(&self.dir.join("state.txt"))
    }
}

#[test]
fn a_slider_dragged_into_the_viewer_changes_its_parameter_and_moves_no_floor() {
    let x = Xvfb::start();
    let mut w = Driven::open(&x, "pointer-slider", 6);
    // Press on the Amplitude slider, drag along it and on into the viewer, release there.
    w.input(&x, ("985", "231"), &["mousedown", "1"]);
    for at in [
        ("1010", "231"),
        ("1040", "231"),
        ("700", "300"),
        ("400", "350"),
    ] {
        w.input(&x, at, &[]);
    }
    w.input(&x, ("400", "350"), &["mouseup", "1"]);
    let s = w.finish();
    assert_eq!(get(&s, "selected"), "false", "nothing behind the panel");
    assert!(floor_stays(&s), "the floor moved: {:?}", floor_in(&s));
    let params = get(&s, "parameters");
    assert!(
        params.contains("PatternGenerator_sinusoidal:Amplitude=")
            && !params.contains("PatternGenerator_sinusoidal:Amplitude=40,40,40,40,40;"),
        "the slider moved: {params}"
    );
}

#[test]
fn start_selects_nothing_and_a_left_drag_on_the_ground_orbits() {
    let x = Xvfb::start();
    let mut w = Driven::open(&x, "pointer-orbit", 7);
    // Start, in the toolbar above the floor.
    w.input(&x, ("730", "11"), &["click", "1"]);
    // A left drag on the ground, left of the robot.
    w.input(&x, ("250", "450"), &["mousedown", "1"]);
    for px in ["300", "350", "400", "450"] {
        w.input(&x, (px, "450"), &[]);
    }
    w.input(&x, ("450", "450"), &["mouseup", "1"]);
    let s = w.finish();
    assert_eq!(get(&s, "running"), "true", "Start was clicked");
    assert_eq!(
        get(&s, "selected"),
        "false",
        "Start selects nothing behind it"
    );
    assert!(floor_stays(&s), "the floor moved: {:?}", floor_in(&s));
    let yaw: f64 = get(&s, "camera")
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((yaw - (-0.9)).abs() > 0.05, "the camera orbited: yaw {yaw}");
}

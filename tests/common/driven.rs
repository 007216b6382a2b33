//! A window driven by real input step by step, each step acknowledged by the window's
//! script a few frames after the test said it was sent: input spans frames at any frame
//! rate and nothing depends on timing.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::window::{Xvfb, scratch, state};

/// A window (`proleg ARGS`), driven step by step: it draws a few frames, then for each
/// step waits until the test says the step's input was sent, draws two more frames (it has
/// handled the input) and says so; at the end it writes its state and closes.
pub struct Driven {
    window: Child,
    /// The X window's id.
    pub id: String,
    dir: PathBuf,
    step: usize,
}

impl Driven {
    /// Opens `proleg ARGS` on `x`'s display for `steps` steps of input; the script starts
    /// with `prelude` (e.g. `slow-frames 400\n`).
    pub fn open(x: &Xvfb, name: &str, args: &[&str], prelude: &str, steps: usize) -> Driven {
        let dir = scratch(name);
        let script = dir.join("driven.script");
        let mut text = format!("{prelude}wait 10\nstate {}\n", dir.join("ack0").display());
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
            .args(args)
            .arg("--script")
            .arg(&script)
            .env("DISPLAY", &x.1)
            .env("XDG_RUNTIME_DIR", scratch(&format!("{name}-xdg")))
            .current_dir(crate::common::root())
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
    pub fn await_ack(&mut self) {
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
    pub fn input(&mut self, x: &Xvfb, at: (&str, &str), then: &[&str]) {
        let mut all = vec!["mousemove", "--window", self.id.as_str(), at.0, at.1];
        all.extend(then);
        x.xdotool(&all);
        self.sent();
    }

    /// One step of keyboard input: xdotool `ARGS` (e.g. `key ctrl+a`, `type TEXT`) to the
    /// focused window.
    pub fn keys(&mut self, x: &Xvfb, args: &[&str]) {
        x.xdotool(args);
        self.sent();
    }

    /// Says the current step's input was sent and waits until the window handled it.
    fn sent(&mut self) {
        self.step += 1;
        std::fs::write(self.dir.join(format!("sent{}", self.step)), "").unwrap();
        self.await_ack();
    }

    /// The window's state as it acknowledged the current step.
    pub fn now(&self) -> Vec<(String, String)> {
        state(&self.dir.join(format!("ack{}", self.step)))
    }

    /// The window's state once it closed.
    pub fn finish(self) -> Vec<(String, String)> {
        let out = self.window.wait_with_output().expect("the window");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        state(&self.dir.join("state.txt"))
    }
}

//! Both windows as desktop applications: idle, they take (almost) no
//! CPU — once they have drawn their last frames, measured from the kernel's accounting
//! over 10 s, below 10 % of one core; they
//! close within half a second of SIGTERM; and a control window opened from the
//! configuration window is reaped when it closes (no zombie). Each window runs on an Xvfb
//! server of the test's own with Mesa's software renderer.
#![cfg(feature = "gui")]

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::window::{Xvfb, scratch};

/// Longest a window may take to show and write its first state (software rendering under
/// a loaded CI machine).
const SHOW_TIMEOUT: Duration = Duration::from_secs(300);

/// Starts `proleg ARGS --script SCRIPT` on `x`'s display.
fn open(x: &Xvfb, args: &[&str], script: &Path, dir: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(args)
        .arg("--script")
        .arg(script)
        .env("DISPLAY", &x.1)
        .env("XDG_RUNTIME_DIR", dir)
        .env("WGPU_BACKEND", "vulkan")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start proleg")
}

/// Waits until `path` exists (the window's script wrote it), or fails.
fn wait_for_file(path: &Path, window: &mut Child) {
    let started = Instant::now();
    while !path.exists() {
        if let Ok(Some(status)) = window.try_wait() {
            panic!(
                "the window closed with {status} before writing {}",
                path.display()
            );
        }
        assert!(
            started.elapsed() < SHOW_TIMEOUT,
            "{} never written",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The fields of /proc/PID/stat after the command name (field 3, the state, first).
fn proc_stat(pid: u32) -> Option<Vec<String>> {
    let text = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let rest = text.rsplit_once(')')?.1;
    Some(rest.split_whitespace().map(str::to_string).collect())
}

/// CPU seconds process `pid` has used (user + system).
fn cpu_seconds(pid: u32) -> f64 {
    let f = proc_stat(pid).expect("the window is running");
    let ticks: f64 = f[11].parse::<f64>().expect("utime") + f[12].parse::<f64>().expect("stime");
    let hz: f64 = Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .ok()
        .and_then(|o| String::from_utf8_lossy(&o.stdout).trim().parse().ok())
        .unwrap_or(100.0);
    ticks / hz
}

/// Waits (at most a minute) for the first wall second in which `pid` used less than 5 % of
/// a core: the window has drawn its last frames after its script and gone idle.
fn settle(pid: u32) {
    for _ in 0..60 {
        let c0 = cpu_seconds(pid);
        std::thread::sleep(Duration::from_secs(1));
        if cpu_seconds(pid) - c0 < 0.05 {
            return;
        }
    }
    panic!("the window never went idle");
}

/// CPU share of one core `pid` takes over 10 s of wall time, once settled.
fn idle_share(pid: u32) -> f64 {
    settle(pid);
    let (c0, t0) = (cpu_seconds(pid), Instant::now());
    std::thread::sleep(Duration::from_secs(10));
    (cpu_seconds(pid) - c0) / t0.elapsed().as_secs_f64()
}

/// Sends SIGTERM and returns how long the window took to exit, and its status.
fn terminate(window: &mut Child) -> (Duration, std::process::ExitStatus) {
    let sent = Instant::now();
    let ok = Command::new("kill")
        .args(["-TERM", &window.id().to_string()])
        .status()
        .expect("kill")
        .success();
    assert!(ok, "kill -TERM failed");
    loop {
        if let Some(status) = window.try_wait().expect("wait") {
            return (sent.elapsed(), status);
        }
        if sent.elapsed() > Duration::from_secs(20) {
            let _ = window.kill();
            panic!("the window ignored SIGTERM for 20 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// A script that lets the window settle, says so in `ack`, and then leaves it idle.
fn idle_script(dir: &Path) -> (PathBuf, PathBuf) {
    let (script, ack) = (dir.join("idle.script"), dir.join("ack.txt"));
    std::fs::write(&script, format!("wait 5\nstate {}\n", ack.display())).expect("script");
    (script, ack)
}

fn idle_then_sigterm(name: &str, args: &[&str]) {
    let x = Xvfb::start();
    let dir = scratch(name);
    let (script, ack) = idle_script(&dir);
    let mut window = open(&x, args, &script, &dir);
    wait_for_file(&ack, &mut window);
    let share = idle_share(window.id());
    let (took, status) = terminate(&mut window);
    assert!(
        share < 0.10,
        "{name}: idle at {:.1} % of a core",
        share * 100.0
    );
    assert!(status.success(), "{name}: SIGTERM closed it with {status}");
    assert!(
        took < Duration::from_millis(500),
        "{name}: took {took:?} to exit"
    );
}

#[test]
fn the_paused_control_window_idles_and_exits_on_sigterm() {
    idle_then_sigterm("idle-control", &["gui", "configs/demo.simulation.xml"]);
}

#[test]
fn the_wizard_idles_and_exits_on_sigterm() {
    let out = scratch("idle-wizard-out");
    let out = out.display().to_string();
    idle_then_sigterm("idle-wizard", &["wizard", "--out", &out]);
}

/// The children of process `pid` (by their parent in /proc).
fn children(pid: u32) -> Vec<u32> {
    let Ok(rd) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    rd.flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|c| proc_stat(*c).is_some_and(|f| f[1] == pid.to_string()))
        .collect()
}

#[test]
fn a_control_window_opened_from_the_wizard_is_reaped_when_it_closes() {
    let x = Xvfb::start();
    let dir = scratch("reap");
    let out = dir.join("out");
    let (script, ack) = (dir.join("open.script"), dir.join("ack.txt"));
    std::fs::write(
        &script,
        format!(
            "wait 3\nopen-control configs/demo.simulation.xml\nstate {}\n",
            ack.display()
        ),
    )
    .expect("script");
    let out = out.display().to_string();
    let mut wizard = open(&x, &["wizard", "--out", &out], &script, &dir);
    wait_for_file(&ack, &mut wizard);
    let child = *children(wizard.id())
        .first()
        .expect("the control window runs as the wizard's child");
    // The child closes (as from its title bar or a signal); the wizard, idle, must reap it.
    let ok = Command::new("kill")
        .args(["-TERM", &child.to_string()])
        .status()
        .expect("kill")
        .success();
    assert!(ok);
    let sent = Instant::now();
    while let Some(f) = proc_stat(child) {
        assert!(
            sent.elapsed() < Duration::from_secs(30),
            "the closed control window stays as process state {}",
            f[0]
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let (_, status) = terminate(&mut wizard);
    assert!(status.success(), "{status}");
}

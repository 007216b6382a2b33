//! A real keyboard and mouse on the control window: xdotool (Debian's, installed by the
//! test command) clicks into the viewer of `proleg gui` on an Xvfb server of the test's
//! own and presses Space, then D; the window's script waits until the simulation runs
//! and the debug view is on, so nothing depends on timing. At two frames a second (issue
//! 33, point 6), a quick Ctrl+A in the Configuration field selects its text, the path typed
//! next replaces it, and Enter loads it.
#![cfg(feature = "gui")]

mod common;

use std::process::{Command, Stdio};

use common::driven::Driven;
use common::window::{Xvfb, get, scratch, state};

#[test]
fn space_and_d_pressed_on_a_real_keyboard_start_the_run_and_the_debug_view() {
    let dir = scratch("keys");
    let (st, script) = (dir.join("state.txt"), dir.join("keys.script"));
    std::fs::write(
        &script,
        format!(
            "wait-for running 600\nwait-for debug 600\nstate {}\nquit\n",
            st.display()
        ),
    )
    .unwrap();
    let x = Xvfb::start();
    // xdotool's --sync search waits for the window to show.
    let window = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(["gui", "configs/demo.simulation.xml", "--script"])
        .arg(&script)
        .env("DISPLAY", &x.1)
        .env("XDG_RUNTIME_DIR", scratch("keys-xdg"))
        .current_dir(common::root())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("proleg gui");
    let id = x.xdotool(&["search", "--sync", "--onlyvisible", "--name", "proleg"]);
    let id = id.lines().next().expect("the window").to_string();
    // A click in the viewer focuses the window (no window manager here), then the keys.
    x.xdotool(&["windowfocus", "--sync", &id]);
    x.xdotool(&["mousemove", "--window", &id, "600", "300", "click", "1"]);
    x.xdotool(&["keydown", "space", "keyup", "space"]);
    x.xdotool(&["keydown", "d", "keyup", "d"]);
    let out = window.wait_with_output().expect("the window");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let s = state(&st);
    assert_eq!(get(&s, "running"), "true");
    assert_eq!(get(&s, "debug_view"), "true");
}

#[test]
fn at_two_frames_a_second_ctrl_a_selects_the_field_and_enter_loads_the_typed_path() {
    let x = Xvfb::start();
    let demo = ["gui", "configs/demo.simulation.xml"];
    let mut w = Driven::open(&x, "keys-slow", &demo, "slow-frames 400\n", 4);
    // Into the Configuration field, then a whole Ctrl+A within one frame.
    w.input(&x, ("200", "11"), &["click", "1"]);
    w.keys(&x, &["key", "ctrl+a"]);
    w.keys(&x, &["type", "configs/cpg_gait.simulation.xml"]);
    w.keys(&x, &["key", "Return"]);
    let s = w.finish();
    assert_eq!(get(&s, "error"), "");
    assert_eq!(get(&s, "config"), "configs/cpg_gait.simulation.xml");
}

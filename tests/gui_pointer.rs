//! A real mouse on the control window: xdotool drives `proleg gui` on an
//! Xvfb server of the test's own. A press on a panel belongs to the panel even when the
//! drag leaves it (the Amplitude slider dragged into the viewer changes Amplitude and moves
//! no floor); a click on Start selects nothing behind the toolbar; a left drag on the
//! ground orbits the camera instead of moving the floor; on the wizard's environment page,
//! a click in the Selection panel keeps the selection and the value typed there takes; a
//! click after a drag still selects; in the environment editor a terrain dragged from the
//! library lands and its difficulty slider, dragged, makes it the hardest. Input is sent step by step, each
//! step acknowledged by the window two frames after the test said it was sent, so a drag
//! spans several frames at any frame rate and nothing depends on timing.
#![cfg(feature = "gui")]

mod common;

use common::driven::Driven;
use common::window::{Xvfb, get};
use proleg::sim::{BuildOptions, Simulator};

/// The demo's control window.
const DEMO: [&str; 2] = ["gui", "configs/demo.simulation.xml"];

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

#[test]
fn a_slider_dragged_into_the_viewer_changes_its_parameter_and_moves_no_floor() {
    let x = Xvfb::start();
    let mut w = Driven::open(&x, "pointer-slider", &DEMO, "", 6);
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
    let mut w = Driven::open(&x, "pointer-orbit", &DEMO, "", 7);
    // Start, in the toolbar above the floor.
    w.input(&x, ("730", "11"), &["click", "1"]);
    // A left drag on the ground, left of the robot.
    w.input(&x, ("250", "450"), &["mousedown", "1"]);
    for px in ["300", "350", "400", "450"] {
        w.input(&x, (px, "450"), &[]);
    }
    w.input(&x, ("450", "450"), &["mouseup", "1"]);
    let s = w.finish();
    // The run stepped (it may have ended since: the demo lasts 30 s of real time, and a
    // loaded machine draws this test's frames slowly).
    let steps: u64 = get(&s, "steps").parse().unwrap();
    assert!(steps > 0, "Start was clicked");
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

#[test]
fn a_click_after_a_drag_still_selects() {
    let x = Xvfb::start();
    let mut w = Driven::open(&x, "pointer-click-after-drag", &DEMO, "", 6);
    // A left drag on the ground orbits; the click after it selects the floor (a press
    // starts a new gesture: the drag before it does not turn the click into one).
    w.input(&x, ("250", "450"), &["mousedown", "1"]);
    for px in ["300", "350", "400"] {
        w.input(&x, (px, "450"), &[]);
    }
    w.input(&x, ("400", "450"), &["mouseup", "1"]);
    w.input(&x, ("400", "450"), &["click", "1"]);
    let s = w.finish();
    assert_eq!(get(&s, "selected"), "true", "the click selected the floor");
    assert!(floor_stays(&s), "the floor moved: {:?}", floor_in(&s));
}

#[test]
fn a_position_typed_in_the_wizards_selection_panel_keeps_the_selection_and_takes() {
    let x = Xvfb::start();
    let out = common::window::scratch("pointer-editor-out");
    let out = out.display().to_string();
    let args = ["wizard", "--out", &out];
    // The wizard's environment page (page 3), a box added and selected.
    let mut w = Driven::open(
        &x,
        "pointer-editor",
        &args,
        "slow-frames 400\nnext\nnext\nadd box 1 0\nselect 1\n",
        4,
    );
    // At two frames a second, a click on the Selection panel's x field (a drag value: the
    // click edits it), then the new value typed over the old one.
    w.input(&x, ("1055", "76"), &["click", "1"]);
    w.keys(&x, &["key", "ctrl+a"]);
    w.keys(&x, &["type", "0.5"]);
    w.keys(&x, &["key", "Return"]);
    let s = w.finish();
    assert_eq!(get(&s, "selected"), "1", "the click kept the selection");
    assert!(
        get(&s, "selected_position").starts_with("0.5000 "),
        "{}",
        get(&s, "selected_position")
    );
}

/// The environment editor's library entry "terrain pegs" (window pixels).
const LIBRARY_PEGS: (&str, &str) = ("62", "385");
/// A point of the perspective view, on the ground.
const PERSPECTIVE: (&str, &str) = ("520", "640");
/// The Selection panel's difficulty slider: its handle at the medium tier, and a point
/// past its right end.
const DIFFICULTY_SLIDER: (&str, &str) = ("1038", "172");
const DIFFICULTY_SLIDER_END: (&str, &str) = ("1200", "172");

#[test]
fn a_terrain_dragged_from_the_editors_library_lands_and_its_difficulty_slider_changes_it() {
    let x = Xvfb::start();
    let mut w = Driven::open(
        &x,
        "pointer-terrain",
        &["wizard"],
        "slow-frames 400\ntool editor\n",
        7,
    );
    let objects: usize = get(&w.now(), "env_objects").parse().unwrap();
    // Press on the library's "terrain pegs", drag it over the perspective view, release.
    w.input(&x, LIBRARY_PEGS, &["mousedown", "1"]);
    w.input(&x, (LIBRARY_PEGS.0, "420"), &[]);
    w.input(&x, PERSPECTIVE, &[]);
    w.input(&x, PERSPECTIVE, &["mouseup", "1"]);
    let s = w.now();
    assert_eq!(get(&s, "env_objects"), (objects + 1).to_string(), "dropped");
    assert_eq!(
        get(&s, "selected_terrain"),
        "pegs d0.50 seed 1",
        "at the medium tier"
    );
    // The Selection panel's difficulty slider, pressed and dragged to its right end.
    w.input(&x, DIFFICULTY_SLIDER, &["mousedown", "1"]);
    w.input(&x, DIFFICULTY_SLIDER_END, &[]);
    w.input(&x, DIFFICULTY_SLIDER_END, &["mouseup", "1"]);
    let s = w.finish();
    assert_eq!(
        get(&s, "selected_terrain"),
        "pegs d1.00 seed 1",
        "the hardest pegs"
    );
}

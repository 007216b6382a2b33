//! Windows that hold still: controls keep their place when counts and banners
//! appear, so a click aimed at one lands on it. With a real mouse (xdotool on an Xvfb of
//! the test's own): "Add plot" takes the click right after a series is ticked (its count
//! no longer appears in front of it), and a run paused at its duration shows its banner
//! over the viewer, leaving the toolbar and the docked panels where they were.
#![cfg(feature = "gui")]

mod common;

use common::driven::Driven;
use common::window::{Xvfb, get, scratch, state};

/// The demo's control window.
const DEMO: [&str; 2] = ["gui", "configs/demo.simulation.xml"];

/// A rectangle of the state (`LEFT TOP RIGHT BOTTOM`).
fn rect(s: &[(String, String)], key: &str) -> [f64; 4] {
    let v: Vec<f64> = get(s, key)
        .split_whitespace()
        .map(|x| x.parse().unwrap_or(f64::NAN))
        .collect();
    assert_eq!(v.len(), 4, "{key} = {:?}", get(s, key));
    [v[0], v[1], v[2], v[3]]
}

/// The centre of a rectangle as xdotool's coordinates.
fn centre(r: [f64; 4]) -> (String, String) {
    (
        format!("{:.0}", (r[0] + r[2]) / 2.0),
        format!("{:.0}", (r[1] + r[3]) / 2.0),
    )
}

#[test]
fn add_plot_takes_the_click_right_after_a_series_is_ticked() {
    let x = Xvfb::start();
    let mut w = Driven::open(&x, "layout-add-plot", &DEMO, "panel plots\n", 2);
    let before = w.now();
    let add = rect(&before, "add_plot_rect");
    let (bx, by) = centre(rect(&before, "first_series_rect"));
    w.input(&x, (&bx, &by), &["click", "1"]);
    let ticked = w.now();
    assert_eq!(
        get(&ticked, "series_ticked"),
        "1",
        "the click ticked a series"
    );
    assert_eq!(
        rect(&ticked, "add_plot_rect"),
        add,
        "Add plot stayed where it was"
    );
    let (ax, ay) = centre(add);
    w.input(&x, (&ax, &ay), &["click", "1"]);
    let s = w.finish();
    assert_eq!(
        get(&s, "plots_shown"),
        "1",
        "the click on Add plot added a plot"
    );
    assert_eq!(get(&s, "series_ticked"), "0");
}

#[test]
fn a_paused_runs_banner_leaves_the_toolbar_and_the_panels_where_they_were() {
    let x = Xvfb::start();
    let before = scratch("layout-banner-before").join("before.txt");
    let prelude = format!(
        "panel all\nwait 5\nstate {}\nspeed 0\nstart\nwait-for paused 20000\nwait 3\n",
        before.display()
    );
    let w = Driven::open(&x, "layout-banner", &DEMO, &prelude, 0);
    let s = w.finish();
    let before = state(&before);
    assert!(
        get(&s, "halt").starts_with("Paused at the simulation's duration"),
        "{}",
        get(&s, "halt")
    );
    assert_eq!(get(&before, "halt"), "");
    for key in ["toolbar_rect", "params_rect", "plots_rect", "viewer_rect"] {
        assert_eq!(rect(&s, key), rect(&before, key), "{key} moved");
    }
}

//! `proleg run` and `proleg bench` from the command line.

mod common;

use common::proleg;

#[test]
fn run_prints_the_motion_summary() {
    let (ok, out, err) = proleg(&["run", "configs/demo.simulation.xml", "--duration", "5"]);
    assert!(ok, "{err}");
    for needle in [
        "steps           5000",
        "simulated time  5.000 s",
        "real-time factor",
        "start COM",
        "end COM",
        "displacement",
        "mean speed",
    ] {
        assert!(out.contains(needle), "{needle:?} missing in:\n{out}");
    }
    let line = out.lines().find(|l| l.starts_with("displacement")).unwrap();
    let d: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!(d > 0.2, "{line}");
}

#[test]
fn run_refuses_bad_input_with_a_message() {
    let (ok, _, err) = proleg(&["run", "configs/demo.simulation.xml", "--duration=-3"]);
    assert!(!ok && err.contains("--duration -3"), "{err}");
    let (ok, _, err) = proleg(&["run", "configs/demo.simulation.xml", "--duration", "NaN"]);
    assert!(!ok && err.contains("--duration NaN"), "{err}");
    let (ok, _, err) = proleg(&["run", "configs/nothing.simulation.xml"]);
    assert!(
        !ok && err.contains("configs/nothing.simulation.xml"),
        "{err}"
    );
}

#[test]
fn run_drives_sensing_modules() {
    // Experiment 2's adaptive module reads the 12 touch pads: the recording must show pads
    // pressed and released, and the module's desired angles moving.
    let dir = common::scratch("cli_sensing");
    let data = dir.join("e2.data.xml");
    let csv = dir.join("e2.csv");
    let (ok, out, err) = proleg(&[
        "run",
        "configs/experiment2_adaptive.simulation.xml",
        "--duration",
        "3",
        "--data",
        data.to_str().unwrap(),
        "--every",
        "10",
    ]);
    assert!(ok && out.contains("steps           3000"), "{err}{out}");
    let (ok, out, err) = proleg(&[
        "data",
        "export",
        data.to_str().unwrap(),
        "--x",
        "stepcount",
        "--series",
        "tactile/pressed,Global_Adaptive_Touch/desired_angle",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(
        ok && out.contains("wrote 300 rows x 18 columns"),
        "{err}{out}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let pads = |r: &Vec<f64>| r[1..13].iter().filter(|p| **p > 0.0).count();
    let pressed: Vec<usize> = rows.iter().map(pads).collect();
    assert!(
        pressed.iter().any(|n| *n > 0) && pressed.iter().any(|n| *n < 12),
        "pads never change: {pressed:?}"
    );
    let first = &rows[0][13..18];
    assert!(
        rows.iter().any(|r| &r[13..18] != first),
        "the adaptive module's desired angles never moved"
    );
}

#[test]
fn bench_prints_ratios() {
    let (ok, out, err) = proleg(&["bench", "--seconds", "0.5", "--batches", "2"]);
    assert!(ok, "{err}");
    for needle in [
        "rapier step, motors held, 1 robot",
        "pipeline, 1 robot(s)/world",
        "pipeline, 2 robot(s)/world",
        "robot-steps/s",
    ] {
        assert!(out.contains(needle), "{needle:?} missing in:\n{out}");
    }
}

#[test]
fn run_records_data_that_info_and_export_read() {
    let dir = common::scratch("cli_data");
    let data = dir.join("demo.data.xml");
    let data_s = data.to_str().unwrap();
    let (ok, out, err) = proleg(&[
        "run",
        "configs/demo.simulation.xml",
        "--duration",
        "1",
        "--data",
        data_s,
        "--every",
        "10",
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("data            "), "{out}");
    let (ok, out, err) = proleg(&["data", "info", data_s]);
    assert!(ok, "{err}");
    for needle in [
        "status    complete",
        "handler   PatternGenerator_sinusoidal (100 frames)",
        "handler   Robot_Data (100 frames)",
        "  y_pos [1]",
        "  servo_currents [5]",
        "simtime   0.010 s .. 1.000 s",
    ] {
        assert!(out.contains(needle), "{needle:?} missing in:\n{out}");
    }
    let csv = dir.join("out.csv");
    let (ok, out, err) = proleg(&[
        "data",
        "export",
        data_s,
        "--x",
        "stepcount",
        "--series",
        "Robot_Data/y_pos,PatternGenerator_sinusoidal/Angle[4]",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("wrote 100 rows x 3 columns"), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("stepcount,Robot_Data/y_pos,PatternGenerator_sinusoidal/Angle[4]")
    );
    assert_eq!(lines.next().unwrap().split(',').next(), Some("10"));
    assert_eq!(lines.count(), 99);
    // A missing file is a one-line error naming it.
    let (ok, _, err) = proleg(&["data", "info", "nope.data.xml"]);
    assert!(!ok);
    assert!(
        err.contains("nope.data.xml") && err.contains("cannot open"),
        "{err}"
    );
}

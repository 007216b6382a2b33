//! Data files (thesis B.8): a recorded run reads back exactly, the thesis's own
//! listing parses, a cut file reads up to its last complete round, and export picks the
//! asked columns.

mod common;

use std::path::Path;

use proleg::control::load_simulation;
use proleg::data::export::{SeriesSelector, XAxis, export};
use proleg::data::read::{DataEvent, info, read_file};
use proleg::sim::datalog::DataSettings;
use proleg::sim::{BuildOptions, Simulator};

/// Records `seconds` of experiment 2 (sine + adaptive, tactile pads) into `file`; returns
/// the simulator (its ring buffers hold every frame).
fn record(file: &Path, seconds: f64, round_frames: usize) -> Simulator {
    let sim = load_simulation(common::root().join("configs/experiment2_adaptive.simulation.xml"))
        .unwrap();
    let mut s = Simulator::new(
        &sim,
        &BuildOptions {
            robots: 1,
            seed: 3,
            record: false,
            ..Default::default()
        },
    )
    .unwrap();
    let settings = DataSettings {
        every: 2,
        ring_frames: 100_000,
        round_frames,
    };
    s.record_to(file, settings).unwrap();
    s.run_for(seconds);
    s
}

#[test]
fn a_recorded_run_reads_back_exactly() {
    let dir = common::scratch("round_trip");
    let file = dir.join("run.data.xml");
    let mut s = record(&file, 1.5, 200);
    let rounds = s.finish_data().unwrap();
    let log = s.data(0).unwrap();
    assert_eq!(log.samples(), 750);
    assert_eq!(rounds, 4, "750 samples in rounds of 200");
    let names: Vec<&str> = log.handlers.iter().map(|h| h.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "PatternGenerator_sinusoidal",
            "Global_Adaptive_Touch",
            "tactile",
            "Robot_Data"
        ]
    );
    let mut seen = vec![0usize; log.handlers.len()];
    let mut header = Vec::new();
    let got = read_file(&file, |e| match e {
        DataEvent::Header(h) => header = h.to_vec(),
        DataEvent::Frame(f) => {
            let (meta, values) = log.rings[f.handler].get(seen[f.handler]).unwrap();
            assert_eq!(f.meta, meta);
            assert_eq!(
                f.values, values,
                "{} frame {}",
                log.handlers[f.handler].name, meta.index
            );
            seen[f.handler] += 1;
        }
    })
    .unwrap();
    assert_eq!(header, log.handlers);
    assert!(!got.cut);
    assert_eq!(got.rounds, 4);
    assert_eq!(seen, vec![750; 4]);
    assert_eq!(got.first_simtime_ms, Some(2.0));
    assert_eq!(got.last_simtime_ms, Some(1500.0));
    // The robot data is real: the robot moved and the servos did work.
    let robot = log.ring("Robot_Data").unwrap();
    let spec = &log.handlers[3];
    let (_, last) = robot.get(robot.len() - 1).unwrap();
    let energy = last[spec.offset(spec.find("energy").unwrap())];
    assert!(energy > 0.0, "energy {energy}");
}

#[test]
fn the_thesis_listing_b8_parses() {
    let file = common::thesis().join("data/B.8.data.xml");
    let mut angles = Vec::new();
    let i = read_file(&file, |e| {
        if let DataEvent::Frame(f) = e
            && f.handler == 1
        {
            angles.push(f.values[0]);
        }
    })
    .unwrap();
    let names: Vec<&str> = i.handlers.iter().map(|h| h.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "Global_Adaptive_Touch",
            "PatternGenerator_sinusoidal",
            "tactile",
            "Robot_Data"
        ]
    );
    assert_eq!(i.handlers[3].series.len(), 13, "16 types less the 3 stamps");
    assert_eq!(
        i.handlers[1].series,
        ["Angle", "Time", "Phase_Difference", "Frequency"]
    );
    assert_eq!(i.frames, vec![2, 2, 0, 2]);
    assert_eq!(angles, vec![5.80648, 11.3934]);
    assert_eq!(
        (i.first_simtime_ms, i.last_simtime_ms),
        (Some(30.0), Some(61.0))
    );
    assert!(!i.cut);
}

#[test]
fn a_cut_file_reads_up_to_its_last_complete_round() {
    let dir = common::scratch("cut");
    let file = dir.join("run.data.xml");
    let mut s = record(&file, 1.0, 100);
    s.finish_data().unwrap();
    let whole = std::fs::read(&file).unwrap();
    let full = info(&file).unwrap();
    assert_eq!(full.rounds, 5);
    // Cut in the middle of the last round, as a kill -9 during its write would.
    let text = String::from_utf8(whole).unwrap();
    let last_round = text.rfind("<round number=\"4\"").unwrap();
    let cut_at = last_round + (text.len() - last_round) / 2;
    let cut = dir.join("cut.data.xml");
    std::fs::write(&cut, &text.as_bytes()[..cut_at]).unwrap();
    let i = info(&cut).unwrap();
    assert!(i.cut);
    assert_eq!(i.rounds, 4);
    assert_eq!(i.frames, vec![400; 4]);
    // Cut right after a round: complete rounds, but no end tag.
    let after = text.rfind("</round>").unwrap() + "</round>\n".len();
    std::fs::write(&cut, &text.as_bytes()[..after]).unwrap();
    let i = info(&cut).unwrap();
    assert!(i.cut);
    assert_eq!(i.rounds, 5);
    // Cut inside the header: nothing to read, said plainly.
    std::fs::write(&cut, &text.as_bytes()[..60]).unwrap();
    let e = info(&cut).unwrap_err();
    assert!(e.to_string().contains("Header"), "{e}");
}

#[test]
fn export_writes_the_chosen_columns() {
    let dir = common::scratch("export");
    let file = dir.join("run.data.xml");
    let mut s = record(&file, 0.5, 60);
    s.finish_data().unwrap();
    let log = s.data(0).unwrap();
    let wanted =
        SeriesSelector::parse_list("Robot_Data/y_pos,PatternGenerator_sinusoidal/Angle[1..2]")
            .unwrap();
    let mut out = Vec::new();
    let stats = export(&file, XAxis::StepCount, &wanted, '\t', &mut out).unwrap();
    assert_eq!((stats.rows, stats.columns), (250, 3));
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "stepcount\tRobot_Data/y_pos\tPatternGenerator_sinusoidal/Angle[1]\tPatternGenerator_sinusoidal/Angle[2]"
    );
    let robot = log.ring("Robot_Data").unwrap();
    let sine = log.ring("PatternGenerator_sinusoidal").unwrap();
    let y = log.handlers[3].offset(log.handlers[3].find("y_pos").unwrap());
    for (k, line) in lines.enumerate() {
        let cols: Vec<f64> = line.split('\t').map(|c| c.parse().unwrap()).collect();
        let (m, r) = robot.get(k).unwrap();
        let (_, a) = sine.get(k).unwrap();
        assert_eq!(cols, vec![m.step as f64, r[y], a[1], a[2]]);
    }
    // Bad selections name what exists.
    for (bad, says) in [
        ("Robot/y_pos", "Robot_Data"),
        ("Robot_Data/ypos", "y_pos"),
        ("PatternGenerator_sinusoidal/Angle[2..7]", "5 parts"),
    ] {
        let w = SeriesSelector::parse_list(bad).unwrap();
        let e = export(&file, XAxis::SimTime, &w, ',', &mut Vec::new()).unwrap_err();
        assert!(e.to_string().contains(says), "{bad}: {e}");
    }
    assert!(matches!(
        SeriesSelector::parse("Robot_Data"),
        Err(proleg::data::export::SelectError::Shape(_))
    ));
    assert!(matches!(
        SeriesSelector::parse("A/b[3..1]"),
        Err(proleg::data::export::SelectError::EmptyRange { .. })
    ));
}

#[test]
fn a_file_that_is_not_data_is_refused_with_its_line() {
    let dir = common::scratch("not_data");
    let file = dir.join("x.xml");
    std::fs::write(
        &file,
        "<?xml version=\"1.0\"?>\n\n<simulation>\n</simulation>\n",
    )
    .unwrap();
    let e = info(&file).unwrap_err();
    assert_eq!(e.line, Some(3));
    assert!(e.message.contains("dataRoot"), "{e}");
    let e = info(&dir.join("missing.xml")).unwrap_err();
    assert!(e.to_string().contains("cannot open"), "{e}");
}

#[test]
fn plot_writes_a_png_of_the_asked_size() {
    let dir = common::scratch("plot");
    let file = dir.join("run.data.xml");
    let mut s = record(&file, 0.5, 100);
    s.finish_data().unwrap();
    let png = dir.join("angles.png");
    let wanted = SeriesSelector::parse_list(
        "PatternGenerator_sinusoidal/Angle[0..2],Robot_Data/real_joint_positions[0]",
    )
    .unwrap();
    let stats = proleg::data::plot::plot(&file, XAxis::SimTime, &wanted, &png, (640, 360)).unwrap();
    assert_eq!((stats.rows, stats.series), (250, 4));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let be =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    assert_eq!((be(16), be(20)), (640, 360), "IHDR width and height");
    // A bad selection is an error, and no image is left behind.
    let bad = dir.join("bad.png");
    let w = SeriesSelector::parse_list("Robot_Data/nope").unwrap();
    let e = proleg::data::plot::plot(&file, XAxis::SimTime, &w, &bad, (640, 360))
        .expect_err("no such series");
    assert_eq!(e.file, file, "the error names the data file read: {e}");
    assert!(e.message.contains("no series \"nope\""), "{e}");
    assert!(!bad.exists());
}

#[test]
fn a_stamp_that_is_not_a_number_is_a_warning_with_its_line_and_the_frame_is_kept() {
    // A malformed `index` or `realtime` was read as 0 without a word.
    let dir = common::scratch("bad-stamp");
    let text = std::fs::read_to_string(common::thesis().join("data/B.8.data.xml")).unwrap();
    let bad = text.replacen(
        "<Frame index=\"1\" realtime=\"1361368880632\"",
        "<Frame index=\"one\" realtime=\"1361368880632\"",
        1,
    );
    assert_ne!(bad, text);
    let file = dir.join("bad.data.xml");
    std::fs::write(&file, &bad).unwrap();
    let mut indices = Vec::new();
    let i = read_file(&file, |e| {
        if let DataEvent::Frame(f) = e
            && f.handler == 0
        {
            indices.push(f.meta.index);
        }
    })
    .unwrap();
    assert_eq!(i.frames, vec![2, 2, 0, 2], "every frame kept");
    assert_eq!(indices, vec![0, 0]);
    assert_eq!(
        i.warnings,
        ["line 26: <Frame> index=\"one\" is not a number; read as 0"]
    );
}

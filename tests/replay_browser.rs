//! The 3D replay page for real: `proleg run --html` writes it, headless Chromium opens it
//! from `file://` with every network request refused, and WebGL draws it in software. The
//! robot is drawn (pixels differ from the scene without it; frame 0 from a later frame),
//! scrubbing puts every body where the stream holds it, two runs share one timeline side
//! by side or overlaid, and a label with markup shows as text.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::browser::Browser;
use proleg::playback::encode::{self, QUATERNION_SCALE};

/// Runs `proleg run ARGS` and returns its output, failing on a non-zero status.
fn proleg_run(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_proleg"))
        .arg("run")
        .args(args)
        .output()
        .expect("proleg runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "proleg run {args:?}: {text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

fn config(name: &str) -> String {
    common::root()
        .join("configs")
        .join(name)
        .display()
        .to_string()
}

/// The streams inlined in the page `page`.
fn page_streams(page: &Path) -> Vec<serde_json::Value> {
    common::page_streams(&std::fs::read_to_string(page).expect("the page"))
}

/// A browser that can reach nothing: every request goes to a proxy that is not there.
fn offline(name: &str) -> Browser {
    Browser::with_args(
        name,
        &[
            "--proxy-server=127.0.0.1:9",
            "--proxy-bypass-list=<-loopback>",
        ],
    )
}

fn file_url(p: &Path) -> String {
    format!("file://{}", p.display())
}

/// Opens `page` and waits until the viewer is ready, paused at `t`.
fn open(b: &Browser, page: &Path, t: f64) {
    b.goto(&file_url(page));
    b.wait_for("!!(window.prolegReplay && window.prolegReplay.ready)");
    b.eval(&format!(
        "(window.prolegReplay.pause(), window.prolegReplay.seek({t}), true)"
    ));
}

/// How many of the first view's pixels differ by more than a little between two reads
/// of it taken by `js_between` (the page's canvas read back through a 2D canvas).
const PIXELS: &str = "(() => {
  const c = document.querySelector('.replay-view canvas');
  const t = document.createElement('canvas');
  t.width = 160; t.height = 90;
  const g = t.getContext('2d');
  g.drawImage(c, 0, 0, 160, 90);
  return Array.from(g.getImageData(0, 0, 160, 90).data);
})()";

fn pixels(b: &Browser) -> Vec<i64> {
    b.eval(PIXELS)
        .as_array()
        .expect("pixels")
        .iter()
        .map(|v| v.as_i64().unwrap_or(0))
        .collect()
}

fn differing(a: &[i64], b: &[i64]) -> usize {
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| (0..3).map(|i| (p[i] - q[i]).abs()).sum::<i64>() > 24)
        .count()
}

fn scratch_page(test: &str, name: &str) -> PathBuf {
    common::scratch(test).join(name)
}

#[test]
fn the_replay_draws_the_robot_and_scrubs_to_the_streams_poses() {
    let page = scratch_page("replay_browser_single", "demo.html");
    let printed = proleg_run(&[
        &config("demo.simulation.xml"),
        "--duration",
        "4",
        "--html",
        &page.display().to_string(),
    ]);
    assert!(printed.contains("3D replay"), "{printed}");
    let streams = page_streams(&page);
    let s = &streams[0];
    let b = offline("replay_single");
    open(&b, &page, 0.0);
    // Nothing fetched: the page holds everything.
    assert_eq!(b.eval("performance.getEntriesByType('resource').length"), 0);

    // The robot is drawn: hiding the moving bodies changes pixels, and so does time.
    let with = pixels(&b);
    b.eval("(window.prolegReplay.showBodies(false), true)");
    let without = pixels(&b);
    b.eval("(window.prolegReplay.showBodies(true), window.prolegReplay.setFollow(false), true)");
    let robot = differing(&with, &without);
    assert!(robot > 40, "only {robot} pixels show the robot");
    b.eval("(window.prolegReplay.seek(3.5), true)");
    let later = pixels(&b);
    let moved = differing(&pixels_at_zero(&b), &later);
    assert!(
        moved > 20,
        "frame 0 and 3.5 s differ in {moved} pixels only"
    );

    // Scrubbing puts each body at the stream's pose for that frame.
    let dt = s["frame_seconds"].as_f64().unwrap();
    let frames = s["frames"].as_u64().unwrap() as usize;
    let moving = common::moving_bodies(s);
    let positions = encode::decode(s["positions"].as_str().unwrap(), f32::from_le_bytes).unwrap();
    let rotations = encode::decode(s["rotations"].as_str().unwrap(), i16::from_le_bytes).unwrap();
    for frame in [1, frames / 3, frames - 1] {
        b.eval(&format!(
            "(window.prolegReplay.seek({}), true)",
            frame as f64 * dt
        ));
        for body in 0..moving {
            let drawn = b.eval(&format!("window.prolegReplay.pose(0, {body})"));
            let k = frame * moving + body;
            for i in 0..3 {
                let got = drawn["position"][i].as_f64().unwrap();
                let want = f64::from(positions[3 * k + i]);
                assert!(
                    (got - want).abs() < 1e-6,
                    "frame {frame} body {body}: {got} vs {want}"
                );
            }
            let q: Vec<f64> = (0..4)
                .map(|i| drawn["quaternion"][i].as_f64().unwrap())
                .collect();
            let w: Vec<f64> = (0..4)
                .map(|i| f64::from(rotations[4 * k + i]) / QUATERNION_SCALE)
                .collect();
            let n = w.iter().map(|c| c * c).sum::<f64>().sqrt();
            let dot: f64 = (0..4).map(|i| q[i] * w[i] / n).sum();
            assert!(
                dot.abs() > 1.0 - 1e-9,
                "frame {frame} body {body}: {q:?} vs {w:?}"
            );
        }
    }
}

fn pixels_at_zero(b: &Browser) -> Vec<i64> {
    let now = b.eval("window.prolegReplay.time()").as_f64().unwrap_or(0.0);
    b.eval("(window.prolegReplay.seek(0), true)");
    let p = pixels(b);
    b.eval(&format!("(window.prolegReplay.seek({now}), true)"));
    p
}

#[test]
fn two_runs_share_one_timeline_side_by_side_or_overlaid() {
    let page = scratch_page("replay_browser_two", "two.html");
    proleg_run(&[
        &config("demo.simulation.xml"),
        "--duration",
        "2",
        "--html",
        &page.display().to_string(),
        "--compare",
        &config("cpg_gait.simulation.xml"),
    ]);
    let b = offline("replay_two");
    open(&b, &page, 1.0);
    assert_eq!(b.eval("window.prolegReplay.replays"), 2);
    assert_eq!(b.eval("window.prolegReplay.views()"), 2);
    assert_eq!(
        b.eval("document.querySelectorAll('.replay-view canvas').length"),
        2
    );
    // One timeline: both robots are posed for the same time.
    let p0 = b.eval("window.prolegReplay.pose(0, 0)");
    let p1 = b.eval("window.prolegReplay.pose(1, 0)");
    assert!(p0.is_object() && p1.is_object(), "{p0} {p1}");
    b.eval("(window.prolegReplay.setOverlay(true), true)");
    assert_eq!(b.eval("window.prolegReplay.views()"), 1);
    assert!(b.eval("window.prolegReplay.pose(1, 0)").is_object());
}

#[test]
fn a_label_with_markup_shows_as_text() {
    let sim = proleg::control::load_simulation(common::root().join("configs/demo.simulation.xml"))
        .unwrap();
    let registry = proleg::control::ModuleRegistry::standard();
    let mut simulator =
        proleg::sim::Simulator::with_registry(&sim, &Default::default(), &registry).unwrap();
    let settings = proleg::sim::EpisodeSettings::new(
        &simulator,
        0.5,
        proleg::config::fitness::Fitness::Displacement,
    );
    let mut episode = proleg::sim::Episode::begin(&simulator, settings).unwrap();
    let recording = proleg::playback::Recording {
        fps: 30.0,
        label: "<img src=x onerror=window.owned=1></script><b>run</b>".into(),
    };
    let out =
        proleg::playback::record_episode(&sim, &mut simulator, &mut episode, &recording, None)
            .unwrap();
    let page = scratch_page("replay_browser_markup", "markup.html");
    proleg::playback::page::write_standalone(&page, &[&out.stream]).unwrap();
    let b = offline("replay_markup");
    open(&b, &page, 0.0);
    assert_eq!(b.eval("document.querySelectorAll('img, b').length"), 0);
    assert_eq!(b.eval("window.owned === undefined"), true);
    let shown = b.eval("document.querySelector('.replay-label .label').textContent");
    assert_eq!(shown.as_str(), Some(recording.label.as_str()));
}

/// Frames the page draws per second while playing at 1x, measured in the page over 3 s.
fn playback_rate(b: &Browser) -> f64 {
    b.eval("(window.prolegReplay.seek(0), window.prolegReplay.play(), window.rateFrom = [performance.now(), window.prolegReplay.framesDrawn()], true)");
    b.wait_up_to(
        "performance.now() - window.rateFrom[0] > 3000",
        std::time::Duration::from_secs(30),
    );
    b.eval("(window.prolegReplay.framesDrawn() - window.rateFrom[1]) * 1000 / (performance.now() - window.rateFrom[0])")
        .as_f64()
        .unwrap_or(0.0)
}

/// The figures and screenshots of docs/replay.md: page and stream sizes for 30 s and
/// 90 s of the demo snake and of experiment 2, the playback frame rate in this Chromium,
/// and the viewer single, side by side, and on a generated height field.
#[test]
#[ignore = "figures for docs/replay.md: cargo test --release --test replay_browser -- --ignored --nocapture"]
fn replay_figures() {
    let dir = common::scratch("replay_figures");
    let images = common::root().join("docs");
    for (name, cfg) in [
        ("demo", "demo.simulation.xml"),
        ("experiment 2", "experiment2_adaptive.simulation.xml"),
    ] {
        for seconds in ["30", "90"] {
            let page = dir.join(format!("{}-{seconds}.html", name.replace(' ', "")));
            let start = std::time::Instant::now();
            proleg_run(&[
                &config(cfg),
                "--duration",
                seconds,
                "--html",
                &page.display().to_string(),
            ]);
            let wall = start.elapsed().as_secs_f64();
            let text = std::fs::read_to_string(&page).unwrap();
            let streams = page_streams(&page);
            let stream = serde_json::to_string(&streams[0]).unwrap().len();
            eprintln!(
                "{name} {seconds} s: stream {:.2} MB, page {:.2} MB, {} frames, recorded and written in {wall:.2} s",
                stream as f64 / 1e6,
                text.len() as f64 / 1e6,
                streams[0]["frames"]
            );
        }
    }
    let b = Browser::with_args("replay_figures", &["--proxy-server=127.0.0.1:9"]);
    open(&b, &dir.join("demo-90.html"), 0.0);
    eprintln!(
        "playback of the demo's 90 s: {:.1} frames/s",
        playback_rate(&b)
    );
    b.eval("(window.prolegReplay.pause(), window.prolegReplay.seek(12), true)");
    b.screenshot(&images.join("replay-single.png"));

    // Two controllers on a held-out course: the tuned sine and the learned residual.
    let two = dir.join("steps.html");
    proleg_run(&[
        &config("learned/steps_medium_sine.simulation.xml"),
        "--duration",
        "20",
        "--html",
        &two.display().to_string(),
        "--compare",
        &config("learned/steps_medium.simulation.xml"),
    ]);
    open(&b, &two, 15.0);
    b.screenshot(&images.join("replay-side-by-side.png"));

    // A generated height field (hills, medium).
    let root = common::root().join("configs");
    std::fs::write(
        dir.join("hills.env.xml"),
        "<Environment><Terrain family=\"hills\" difficulty=\"0.5\" seed=\"101\"/></Environment>",
    )
    .unwrap();
    let sim = std::fs::read_to_string(root.join("learned/steps_medium_sine.simulation.xml"))
        .unwrap()
        .replace("../robots/", &format!("{}/robots/", root.display()))
        .replace(
            "steps_medium_sine.actuation.xml",
            &format!("{}/learned/steps_medium_sine.actuation.xml", root.display()),
        )
        .replace("steps_medium_101.env.xml", "hills.env.xml");
    std::fs::write(dir.join("hills.simulation.xml"), sim).unwrap();
    let hills = dir.join("hills.html");
    proleg_run(&[
        &dir.join("hills.simulation.xml").display().to_string(),
        "--duration",
        "20",
        "--html",
        &hills.display().to_string(),
    ]);
    open(&b, &hills, 10.0);
    b.screenshot(&images.join("replay-hills.png"));
}

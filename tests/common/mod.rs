//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod browser;
pub mod driven;
pub mod hosts;
pub mod optimize;
pub mod pg;
pub mod shared_run;
pub mod window;

use std::path::{Path, PathBuf};

/// Emulated servos' hidden dynamics for calibration tests: none of them the robot file's.
pub const HIDDEN_SERVOS: proleg::robot_io::emulator::servo::ServoDynamics =
    proleg::robot_io::emulator::servo::ServoDynamics {
        speed_deg_s: 150.0,
        gain: 25.0,
        dead_band_deg: 0.8,
        latency_s: 0.03,
        noise_deg: 0.1,
        backlash_deg: 0.0,
    };

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file below `dir` whose name ends with `suffix`, sorted.
pub fn files_ending(dir: &Path, suffix: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.to_string_lossy().ends_with(suffix) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The thesis fixtures folder.
pub fn thesis() -> PathBuf {
    root().join("tests/fixtures/thesis")
}

/// A fresh scratch folder for one test (under the target folder, removed first).
pub fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-scratch").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A plugin workspace of its own in `ws`: the workspace manifest and the API crate, as in
/// `plugins/` (for `plugin new`, the module library's Compile).
pub fn plugin_workspace(ws: &Path) {
    let root = root();
    std::fs::create_dir_all(ws.join("api/src")).expect("plugin workspace");
    std::fs::copy(root.join("plugins/Cargo.toml"), ws.join("Cargo.toml")).expect("manifest");
    for f in ["Cargo.toml", "src/lib.rs"] {
        std::fs::copy(root.join("plugins/api").join(f), ws.join("api").join(f)).expect("api");
    }
}

/// Runs the `proleg` binary in the repository root: success, stdout, stderr.
pub fn proleg(args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_proleg"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Whether the MuJoCo engine can run here: its library loads. Without it a MuJoCo test
/// prints why and passes, unless `PROLEG_REQUIRE_MUJOCO` is set (scripts/test sets it after
/// installing the library), where a missing library fails the test.
pub fn mujoco_here(test: &str) -> bool {
    match proleg::sim::engine::mujoco::library::library() {
        Ok(_) => true,
        Err(e) if std::env::var_os("PROLEG_REQUIRE_MUJOCO").is_some() => {
            panic!("{test}: MuJoCo is required here: {e}")
        }
        Err(e) => {
            eprintln!("{test}: skipped, {e}");
            false
        }
    }
}

/// The archive line `proleg results` prints for a store's MAP-Elites run.
pub fn archive_line(store: &Path) -> String {
    let (ok, out, err) = proleg(&["results", &store.display().to_string()]);
    assert!(ok, "{err}");
    out.lines()
        .find(|l| l.contains(" archive: "))
        .map(|l| l.to_string())
        .unwrap_or_else(|| panic!("no archive line in {out}"))
}

/// `proleg optimize CONFIG --max-evals EVALS --duration SECONDS --quiet --store STORE`,
/// then `extra`.
pub fn optimize(
    config: &str,
    (evals, seconds): (&str, &str),
    store: &Path,
    extra: &[&str],
) -> (bool, String, String) {
    let store = store.display().to_string();
    let mut a = vec![
        "optimize",
        config,
        "--max-evals",
        evals,
        "--duration",
        seconds,
        "--quiet",
        "--store",
        &store,
    ];
    a.extend(extra);
    proleg(&a)
}

/// A simulation of the course-tuned sine (experiment 2) on a flat floor whose far edge is
/// `edge` m ahead of the origin along the robot's heading (+y): it falls off the end.
pub fn floor_ending_at(dir: &Path, edge: f64) -> proleg::config::Simulation {
    let configs = root().join("configs");
    let env = dir.join(format!("edge{edge}.env.xml"));
    let half = (edge + 2.0) / 2.0;
    std::fs::write(
        &env,
        format!(
            r#"<Environment>
  <KinBody name="floor">
    <Body type="static">
      <Translation>0 {} -0.003</Translation>
      <Geom type="box"><extents>1 {half} 0.003</extents><friction>0.5</friction></Geom>
    </Body>
  </KinBody>
</Environment>
"#,
            edge - half
        ),
    )
    .unwrap();
    let sim = simulation_file(
        &dir.join(format!("edge{edge}.simulation.xml")),
        [
            &configs.join("robots/tactile5p.robot.xml"),
            &configs.join("actuation/tactile5p_sine_tuned.actuation.xml"),
            &env,
        ],
        15.0,
    );
    proleg::control::load_simulation(&sim).unwrap()
}

/// Writes a single-run simulation file at `path` of `[robot, actuation, environment]` for
/// `duration` s (1 ms steps, seed 1, paced at real time in a window); returns `path`.
pub fn simulation_file(path: &Path, [robot, actuation, env]: [&Path; 3], duration: f64) -> PathBuf {
    let text = format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<simulation>
  <robot>{}</robot>
  <actuation>{}</actuation>
  <environment>{}</environment>
  <simulationProperties>
    <mode>Single Run Simulation</mode>
    <accuracy>30</accuracy>
    <stepWidth>0.001</stepWidth>
    <duration>{duration}</duration>
    <seed>1</seed>
    <realtimeFactor>1</realtimeFactor>
  </simulationProperties>
</simulation>
"#,
        robot.display(),
        actuation.display(),
        env.display()
    );
    std::fs::write(path, text).expect("simulation file");
    path.to_path_buf()
}

/// The rows of an exported evaluations table (`proleg results --export`), each the fields of
/// `columns` joined by spaces, found by the header's names.
pub fn table_columns(tsv: &str, columns: &[&str]) -> Vec<String> {
    let mut lines = tsv.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split('\t').collect();
    let at: Vec<usize> = columns
        .iter()
        .map(|c| {
            header
                .iter()
                .position(|h| h == c)
                .unwrap_or_else(|| panic!("no column {c} in {header:?}"))
        })
        .collect();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            let picked: Vec<&str> = at
                .iter()
                .map(|&i| f.get(i).copied().unwrap_or(""))
                .collect();
            picked.join(" ")
        })
        .collect()
}

/// The pose streams a 3D replay page (`proleg run --html`) holds inlined.
pub fn page_streams(page: &str) -> Vec<serde_json::Value> {
    let open = "<script id=\"replay-streams\" type=\"application/json\">";
    let start = page.find(open).expect("the streams' element") + open.len();
    let end = start + page[start..].find("</script>").expect("its end");
    serde_json::from_str(&page[start..end]).expect("the streams are JSON")
}

/// How many of a pose stream's bodies move (those each frame holds a pose of).
pub fn moving_bodies(stream: &serde_json::Value) -> usize {
    stream["scene"]["bodies"]
        .as_array()
        .expect("the scene's bodies")
        .iter()
        .filter(|b| b["moves"] == true)
        .count()
}

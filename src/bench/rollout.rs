//! MuJoCo's own speed on the same scenario, measured in the same run as proleg's pipeline
//! on MuJoCo: the scenario exported with the MJCF mapping (its servos as position
//! actuators), the servo targets proleg's run gave every step as the control sequence, and
//! `mujoco.rollout` (Python's `mujoco` 4.0.0, one thread) timed on them by
//! `scripts/mujoco_rollout.py`. The interpreter is `PROLEG_PYTHON` (scripts/test sets it
//! to its virtual environment), else `python3`.

use std::path::PathBuf;
use std::process::Command;

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::sim::engine::mujoco::MujocoSettings;
use crate::sim::engine::mujoco::mjcf::{MjcfOptions, Servos, mjcf};

use super::{Figure, world_of};

/// The script, carried in the binary so the bench runs from any folder.
const SCRIPT: &str = include_str!("../../scripts/mujoco_rollout.py");

/// MuJoCo's rollout of `sim` for `seconds`, steps per second (one thread).
pub fn rollout_rate(sim: &Simulation, seconds: f64) -> Result<f64, String> {
    let mut s = world_of(sim, 1, &ModuleRegistry::standard(), None)?;
    let steps = (seconds / s.clock().dt).round() as u64;
    let mut controls = String::new();
    for _ in 0..steps {
        s.run_steps(1);
        let targets = s.servo_targets(0).map_err(|e| e.to_string())?;
        let row: Vec<String> = targets.iter().map(|t| t.to_radians().to_string()).collect();
        controls.push_str(&row.join("\t"));
        controls.push('\n');
    }
    let doc = mjcf(
        sim,
        &MjcfOptions {
            robots: 1,
            servos: Servos::Position,
            settings: MujocoSettings::default(),
        },
    )
    .map_err(|e| e.to_string())?;
    let dir = std::env::temp_dir().join(format!("proleg-rollout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let files = [
        ("model.xml", doc.xml.as_str()),
        ("controls.tsv", controls.as_str()),
        ("mujoco_rollout.py", SCRIPT),
    ];
    for (name, text) in files {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    let python =
        std::env::var_os("PROLEG_PYTHON").map_or_else(|| PathBuf::from("python3"), PathBuf::from);
    let out = Command::new(&python)
        .arg(dir.join("mujoco_rollout.py"))
        .arg(dir.join("model.xml"))
        .arg(dir.join("controls.tsv"))
        .output()
        .map_err(|e| format!("{}: {e}", python.display()));
    if let Err(e) = std::fs::remove_dir_all(&dir) {
        eprintln!("warning: {}: {e}", dir.display());
    }
    let out = out?;
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().last().unwrap_or("no output");
        return Err(format!(
            "{} scripts/mujoco_rollout.py: {last}",
            python.display()
        ));
    }
    text.split(':')
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|n| n.parse::<f64>().ok())
        .ok_or_else(|| format!("unreadable rollout figure: {text}"))
}

/// The line comparing proleg's pipeline on MuJoCo (`pipeline`, one robot) with MuJoCo's
/// rollout of the same scenario.
pub fn compare(sim: &Simulation, seconds: f64, pipeline: &Figure) -> String {
    match rollout_rate(sim, seconds) {
        Ok(rate) => format!(
            "MuJoCo's own mujoco.rollout on the exported scenario: {rate:.0} steps/s; proleg's pipeline on MuJoCo: {:.2}x rollout per core",
            pipeline.robot_steps_per_s() / rate
        ),
        Err(e) => format!("MuJoCo's own mujoco.rollout: not measured ({e})"),
    }
}

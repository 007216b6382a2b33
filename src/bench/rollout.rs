//! MuJoCo's own speed on the same scenario, measured in the same run as proleg's pipeline
//! on MuJoCo by `mujoco.rollout` (Python's `mujoco` 4.0.0, one thread, timed by
//! `scripts/mujoco_rollout.py`) on the export of its MJCF mapping (`proleg export mjcf`):
//! servos as position actuators, driven by the servo targets proleg's run gave every
//! step. (The engine's own model cannot be rolled out alone: its servos' target speeds
//! are set between `mj_step1` and `mj_step2`, which `mujoco.rollout` does not expose.)
//!
//! The interpreter is `PROLEG_PYTHON` (scripts/test sets it to its virtual environment),
//! else `python3`.

use std::path::PathBuf;
use std::process::Command;

use crate::config::Simulation;
use crate::control::ModuleRegistry;
use crate::sim::engine::mjcf_export;

use super::world_of;

/// Why MuJoCo's rollout could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum RolloutError {
    /// The scenario does not build or run.
    #[error("{0}")]
    Scenario(String),
    /// The model or its controls could not be written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The interpreter failed or is missing.
    #[error("{python} scripts/mujoco_rollout.py: {message}")]
    Python {
        /// The interpreter.
        python: PathBuf,
        /// Its last line of errors, or why it did not start.
        message: String,
    },
    /// The script printed no figure.
    #[error("unreadable rollout figure: {0}")]
    Unreadable(String),
}

/// The script, carried in the binary so the bench runs from any folder.
const SCRIPT: &str = include_str!("../../scripts/mujoco_rollout.py");

/// What a run of `sim` commanded every step: the servo targets (rad), as TSV rows.
fn targets(sim: &Simulation, seconds: f64) -> Result<String, RolloutError> {
    let mut s = world_of(sim, 1, &ModuleRegistry::standard(), None)
        .map_err(|e| RolloutError::Scenario(e.to_string()))?;
    let steps = (seconds / s.clock().dt).round() as u64;
    let mut targets = String::new();
    for _ in 0..steps {
        s.run_steps(1);
        let row = s
            .servo_targets(0)
            .map_err(|e| RolloutError::Scenario(e.to_string()))?;
        let cells: Vec<String> = row.iter().map(|v| v.to_radians().to_string()).collect();
        targets.push_str(&cells.join("\t"));
        targets.push('\n');
    }
    Ok(targets)
}

/// MuJoCo's rollout of `model` driven by `controls`, steps per second (one thread).
fn rollout_rate(model: &str, controls: &str) -> Result<f64, RolloutError> {
    let dir = std::env::temp_dir().join(format!("proleg-rollout-{}", std::process::id()));
    let io = |path: &std::path::Path| {
        let path = path.to_path_buf();
        move |source| RolloutError::Io { path, source }
    };
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    let files = [
        ("model.xml", model),
        ("controls.tsv", controls),
        ("mujoco_rollout.py", SCRIPT),
    ];
    for (name, text) in files {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(io(&p))?;
    }
    let python =
        std::env::var_os("PROLEG_PYTHON").map_or_else(|| PathBuf::from("python3"), PathBuf::from);
    let out = Command::new(&python)
        .arg(dir.join("mujoco_rollout.py"))
        .arg(dir.join("model.xml"))
        .arg(dir.join("controls.tsv"))
        .output()
        .map_err(|e| RolloutError::Python {
            python: python.clone(),
            message: e.to_string(),
        });
    if let Err(e) = std::fs::remove_dir_all(&dir) {
        eprintln!("warning: {}: {e}", dir.display());
    }
    let out = out?;
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().last().unwrap_or("no output");
        return Err(RolloutError::Python {
            python,
            message: last.to_string(),
        });
    }
    text.split(':')
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|n| n.parse::<f64>().ok())
        .ok_or_else(|| RolloutError::Unreadable(text.to_string()))
}

/// The export of `sim` (position servos).
fn export(sim: &Simulation) -> Result<String, RolloutError> {
    mjcf_export(sim)
        .map(|m| m.xml)
        .map_err(|e| RolloutError::Scenario(e.to_string()))
}

/// Rollout rate of the export, steps per second.
pub fn rollout_rate_of_export(sim: &Simulation, seconds: f64) -> Result<f64, RolloutError> {
    rollout_rate(&export(sim)?, &targets(sim, seconds)?)
}

/// proleg's pipeline over the rollouts' window (from the start, no warm-up: the rollouts
/// start there too), best of [`super::REPEATS`], robot-steps per second.
fn pipeline_from_start(sim: &Simulation, seconds: f64) -> Result<f64, RolloutError> {
    let mut best: f64 = 0.0;
    for _ in 0..super::REPEATS {
        let mut s = world_of(sim, 1, &ModuleRegistry::standard(), None)
            .map_err(|e| RolloutError::Scenario(e.to_string()))?;
        let steps = (seconds / s.clock().dt).round() as u64;
        let t = std::time::Instant::now();
        s.run_steps(steps);
        best = best.max(steps as f64 / t.elapsed().as_secs_f64());
    }
    Ok(best)
}

/// The lines comparing proleg's pipeline on MuJoCo with MuJoCo's rollouts of the same
/// scenario over the same simulated window.
pub fn compare(sim: &Simulation, seconds: f64) -> String {
    let ours = match pipeline_from_start(sim, seconds) {
        Ok(r) => r,
        Err(e) => return format!("MuJoCo's own mujoco.rollout: not measured ({e})"),
    };
    match rollout_rate_of_export(sim, seconds) {
        Ok(export) => format!(
            "the first {seconds} s against MuJoCo's own mujoco.rollout (1 thread, same run): proleg's pipeline {ours:.0} steps/s;\n  rollout of the exported scenario (position servos, no sensors, no kernel) {export:.0} steps/s: proleg {:.2}x of it per core",
            ours / export
        ),
        Err(e) => format!("MuJoCo's own mujoco.rollout: not measured ({e})"),
    }
}

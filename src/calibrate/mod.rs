//! Servo identification from recordings (`proleg calibrate`): a recording's desired joint
//! positions are replayed through the servo model ([`replay`]: the simulator's servo law on
//! a joint held in the air), and its gain, top speed, dead band and latency are fitted to
//! the recorded real positions by CMA-ES ([`fit`]), shared by all joints or per joint. The
//! report gives each parameter before (the robot file's) and after with its spread over
//! several fits, the RMS tracking error per joint before and after, and a parameter the
//! recording cannot tell is reported as such. The calibrated robot file is the robot file
//! with the fitted values set on its joints; [`check`] shows what the calibration buys on a
//! recorded gait.
//! [`recording`] reads the recording to calibrate against; [`plot`] draws the calibration's
//! picture; [`error`] says why a calibration cannot be done.

pub mod check;
pub mod error;
pub mod fit;
pub mod plot;
pub mod recording;
pub mod replay;

use std::path::{Path, PathBuf};

use crate::config::Simulation;
use crate::config::robot::write_robot_file;
use crate::config::sensor::SensorSource;
use crate::config::source::{FsSource, relative_path, resolve_include};
use crate::sim::servo::DEFAULT_SERVO_GAIN;
pub use error::CalibrateError;
use fit::{GroupFit, Identified, fit_group, group_rms};
pub use recording::MIN_SAMPLES;
use recording::Recording;
use replay::ServoModel;

/// How to calibrate.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrateOptions {
    /// One model per joint instead of one for all.
    pub per_joint: bool,
    /// Fits from different seeds (their spread is the confidence).
    pub runs: u32,
    /// Seed of the first fit.
    pub seed: u64,
}

/// What a calibration found.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationReport {
    /// The data file.
    pub file: PathBuf,
    /// Seconds and samples recorded.
    pub seconds: f64,
    /// Samples.
    pub samples: usize,
    /// The robot file's models, per joint.
    pub before: Vec<ServoModel>,
    /// The fits (one group, or one per joint).
    pub groups: Vec<GroupFit>,
    /// RMS tracking error (degrees) per joint with the robot file's models.
    pub rms_before: Vec<f64>,
    /// RMS tracking error (degrees) per joint with the fitted models.
    pub rms_after: Vec<f64>,
}

impl CalibrationReport {
    /// The fitted model of `joint` (the robot file's where the fit cannot tell a value).
    pub fn after(&self, joint: usize) -> ServoModel {
        let before = self.before[joint];
        let Some(g) = self.groups.iter().find(|g| g.joints.contains(&joint)) else {
            return before;
        };
        ServoModel {
            gain: g.gain.value().unwrap_or(before.gain),
            max_vel_deg_s: g.max_vel_deg_s.value().unwrap_or(before.max_vel_deg_s),
            dead_band_deg: g.dead_band_deg.value().unwrap_or(before.dead_band_deg),
            latency_s: g.latency_s.value().unwrap_or(before.latency_s),
        }
    }
}

/// The robot file's servo model of each joint of `sim`.
pub fn models_of(sim: &Simulation) -> Vec<ServoModel> {
    sim.robot
        .joints
        .iter()
        .map(|j| ServoModel {
            gain: j.servo_gain.unwrap_or(DEFAULT_SERVO_GAIN),
            max_vel_deg_s: j.max_vel.to_degrees(),
            dead_band_deg: j.dead_band_deg,
            latency_s: j.latency_s,
        })
        .collect()
}

/// `sim`'s joint count, when `rec` recorded as many joints (else the error naming both).
pub fn of_this_robot(rec: &Recording, sim: &Simulation) -> Result<usize, CalibrateError> {
    let expected = sim.robot.joints.len();
    if rec.joints() != expected {
        return Err(CalibrateError::JointCount {
            file: rec.file.clone(),
            found: rec.joints(),
            robot: sim.robot.name.clone(),
            expected,
        });
    }
    Ok(expected)
}

/// Fits `sim`'s servo models to `rec`.
pub fn calibrate(
    rec: &Recording,
    sim: &Simulation,
    o: &CalibrateOptions,
) -> Result<CalibrationReport, CalibrateError> {
    let expected = of_this_robot(rec, sim)?;
    if rec.times.len() < MIN_SAMPLES {
        return Err(CalibrateError::TooShort {
            file: rec.file.clone(),
            samples: rec.times.len(),
            seconds: rec.seconds(),
        });
    }
    let before = models_of(sim);
    let groups: Vec<Vec<usize>> = if o.per_joint {
        (0..expected).map(|j| vec![j]).collect()
    } else {
        vec![(0..expected).collect()]
    };
    let groups: Vec<GroupFit> = groups
        .iter()
        .map(|joints| fit_group(rec, joints, o.runs, o.seed))
        .collect();
    let mut report = CalibrationReport {
        file: rec.file.clone(),
        seconds: rec.seconds(),
        samples: rec.times.len(),
        before,
        groups,
        rms_before: Vec::new(),
        rms_after: Vec::new(),
    };
    for j in 0..expected {
        report
            .rms_before
            .push(group_rms(rec, &[j], &report.before[j]));
        let after = report.after(j);
        report.rms_after.push(group_rms(rec, &[j], &after));
    }
    Ok(report)
}

/// `sim`'s robot file with the calibrated servo values of `report` on its joints (the
/// identified ones), headed by a comment naming the recording, as it is written in the
/// folder `dir` (its includes named from there).
pub fn calibrated_robot_file(
    sim: &Simulation,
    report: &CalibrationReport,
    dir: &Path,
) -> Result<String, CalibrateError> {
    let mut file = sim.files.robot.clone();
    let here = |written: &mut String| {
        if let Some(found) = resolve_include(&FsSource, &sim.robot.file, written) {
            *written = relative_path(dir, &found);
        }
    };
    for inc in &mut file.kinbody.includes {
        here(&mut inc.file);
    }
    for s in file.sensors.iter_mut().chain(&mut file.kinbody.sensors) {
        if let SensorSource::File { path, .. } = &mut s.source {
            here(path);
        }
    }
    for (j, joint) in sim.robot.joints.iter().enumerate() {
        let written = file
            .kinbody
            .joints
            .iter_mut()
            .find(|k| k.name == joint.name)
            .ok_or_else(|| CalibrateError::JointElsewhere {
                joint: joint.name.clone(),
            })?;
        let Some(g) = report.groups.iter().find(|g| g.joints.contains(&j)) else {
            continue;
        };
        let round = |v: f64| (v * 1e4).round() / 1e4;
        if let Some(v) = g.gain.value() {
            written.servo_gain = Some(round(v));
        }
        if let Some(v) = g.max_vel_deg_s.value() {
            written.max_vel = Some(round(v.to_radians()));
        }
        if let Some(v) = g.dead_band_deg.value() {
            written.servo_dead_band = (v > 0.0).then_some(round(v));
        }
        if let Some(v) = g.latency_s.value() {
            written.servo_latency = (v > 0.0).then_some(round(v));
        }
    }
    let text = write_robot_file(&file);
    let comment = format!(
        "<!-- Servos calibrated by proleg calibrate from {} ({:.1} s, {} samples): RMS tracking error {} deg before, {} deg after. -->\n",
        report.file.display(),
        report.seconds,
        report.samples,
        mean(&report.rms_before),
        mean(&report.rms_after)
    );
    Ok(match text.split_once('\n') {
        Some((decl, rest)) if decl.starts_with("<?xml") => format!("{decl}\n{comment}{rest}"),
        _ => format!("{comment}{text}"),
    })
}

/// The mean of `v`, to 3 decimals, as text.
fn mean(v: &[f64]) -> String {
    format!("{:.3}", v.iter().sum::<f64>() / v.len().max(1) as f64)
}

impl std::fmt::Display for CalibrationReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{}: {:.1} s, {} samples",
            self.file.display(),
            self.seconds,
            self.samples
        )?;
        for g in &self.groups {
            let names: Vec<String> = g.joints.iter().map(|j| format!("J{}", j + 1)).collect();
            writeln!(f, "joints {}:", names.join(" "))?;
            let before = self.before[g.joints[0]];
            let row =
                |f: &mut std::fmt::Formatter<'_>, name: &str, b: f64, id: &Identified| match id {
                    Identified::Value { value, spread } => {
                        writeln!(
                            f,
                            "  {name:<22} {b:>10.4} -> {value:>10.4} (+- {spread:.4})"
                        )
                    }
                    Identified::Unidentifiable(why) => {
                        writeln!(f, "  {name:<22} {b:>10.4} -> not identifiable: {why}")
                    }
                };
            row(f, "gain (1/s)", before.gain, &g.gain)?;
            row(
                f,
                "top speed (deg/s)",
                before.max_vel_deg_s,
                &g.max_vel_deg_s,
            )?;
            row(f, "dead band (deg)", before.dead_band_deg, &g.dead_band_deg)?;
            row(f, "latency (s)", before.latency_s, &g.latency_s)?;
            writeln!(
                f,
                "  {:<22} not identifiable: {}",
                "max torque (N m)",
                fit::Unidentifiable::NoLoad
            )?;
        }
        writeln!(f, "RMS tracking error (deg) per joint, before -> after:")?;
        for (j, (b, a)) in self.rms_before.iter().zip(&self.rms_after).enumerate() {
            writeln!(f, "  J{:<3} {b:>8.3} -> {a:>8.3}", j + 1)?;
        }
        Ok(())
    }
}

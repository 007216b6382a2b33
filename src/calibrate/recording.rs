//! A recording to calibrate against: the desired and the real joint positions of a data
//! file (`Robot_Data/desired_joint_positions`, `Robot_Data/real_joint_positions`, as
//! `proleg robot` and simulations record them), per joint, with their sample times.

use std::path::{Path, PathBuf};

use crate::calibrate::error::CalibrateError;
use crate::data::export::{SeriesSelector, XAxis, for_each_row};

/// Fewest samples a recording needs.
pub const MIN_SAMPLES: usize = 50;

/// The series a calibration reads.
pub const DESIRED: &str = "Robot_Data/desired_joint_positions";
/// The measured positions.
pub const REAL: &str = "Robot_Data/real_joint_positions";

/// Desired and real joint angles over time.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The data file.
    pub file: PathBuf,
    /// Sample times (s).
    pub times: Vec<f64>,
    /// Desired angles (degrees), per joint, per sample.
    pub desired: Vec<Vec<f64>>,
    /// Real angles (degrees), per joint, per sample.
    pub real: Vec<Vec<f64>>,
}

impl Recording {
    /// Recorded joints.
    pub fn joints(&self) -> usize {
        self.desired.len()
    }

    /// Seconds from the first sample to the last.
    pub fn seconds(&self) -> f64 {
        match (self.times.first(), self.times.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// The median time between samples (s): the bus's read-back cycle as recorded.
    pub fn sample_period(&self) -> f64 {
        let mut gaps: Vec<f64> = self.times.windows(2).map(|w| w[1] - w[0]).collect();
        gaps.sort_by(f64::total_cmp);
        gaps.get(gaps.len() / 2).copied().unwrap_or(0.0)
    }

    /// Times the desired angle of `joint` turns back (its direction changes): each shows
    /// the servo's lag once.
    pub fn reversals(&self, joint: usize) -> usize {
        let d = &self.desired[joint];
        let mut last = 0.0_f64;
        let mut count = 0;
        for w in d.windows(2) {
            let step = w[1] - w[0];
            if step.abs() < 1e-9 {
                continue;
            }
            if last != 0.0 && step.signum() != last.signum() {
                count += 1;
            }
            last = step;
        }
        count
    }
}

/// Reads the desired and real joint positions of `path`.
pub fn read_recording(path: &Path) -> Result<Recording, CalibrateError> {
    let wanted = [DESIRED, REAL].map(|s| {
        SeriesSelector::parse(s).unwrap_or_else(|_| SeriesSelector {
            handler: String::new(),
            series: s.to_string(),
            parts: None,
        })
    });
    let mut times = Vec::new();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let (_, _, columns) = for_each_row(path, XAxis::SimTime, &wanted, |_, t, row| {
        times.push(t);
        rows.push(row.to_vec());
        Ok(())
    })?;
    let desired_cols = columns
        .iter()
        .filter(|c| c.title.starts_with(DESIRED))
        .count();
    let real_cols = columns.len() - desired_cols;
    if real_cols == 0 || desired_cols != real_cols {
        return Err(CalibrateError::Series {
            file: path.to_path_buf(),
            desired: desired_cols,
            real: real_cols,
        });
    }
    let joints = desired_cols;
    let series = |offset: usize| -> Vec<Vec<f64>> {
        (0..joints)
            .map(|j| rows.iter().map(|r| r[offset + j]).collect())
            .collect()
    };
    Ok(Recording {
        file: path.to_path_buf(),
        times,
        desired: series(0),
        real: series(joints),
    })
}

//! Fitting the servo model to a recording: CMA-ES (`optimize::cmaes`) minimizes the RMS
//! difference between the replayed and the recorded angles over gain, top speed, dead
//! band and latency, from several seeds; the best fit is the estimate and the spread of the
//! runs' fits its confidence. A parameter the recording does not excite is reported as
//! unidentifiable, never as a number: the latency needs goals that turn back often enough
//! to show the lag (ten full swings per joint), and every parameter must change the replay
//! measurably when it moves off its fit (a likelihood-ratio test: with Gaussian residuals,
//! `n ln(SSE'/SSE)` above the 0.1 % point of chi-square with one degree of freedom).

use crate::calibrate::recording::Recording;
use crate::calibrate::replay::{ServoModel, replay, rms};
use crate::optimize::cmaes::CmaEs;

/// Reversals of the goal a recording needs per joint to show the latency (ten full
/// swings).
pub const MIN_REVERSALS: usize = 20;

/// The likelihood ratio a parameter moved off its fit must reach for the recording to
/// identify it: chi-square with one degree of freedom at p = 0.001.
const LIKELIHOOD_RATIO: f64 = 10.83;

/// Fits per group of joints.
const GENERATIONS: usize = 150;

/// A fitted parameter: its value and spread, or why the recording cannot tell it.
#[derive(Debug, Clone, PartialEq)]
pub enum Identified {
    /// The best fit and the standard deviation of the runs' fits.
    Value {
        /// The estimate.
        value: f64,
        /// The spread over the fits from several seeds.
        spread: f64,
    },
    /// Not identifiable from this recording.
    Unidentifiable(Unidentifiable),
}

impl Identified {
    /// The value, when identified.
    pub fn value(&self) -> Option<f64> {
        match self {
            Identified::Value { value, .. } => Some(*value),
            Identified::Unidentifiable(_) => None,
        }
    }
}

/// Why a parameter cannot be identified.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Unidentifiable {
    /// The goals turn back too rarely to show the lag.
    #[error(
        "the recording is too short for the latency: its goals turn back {found} times per joint on average, at least {needed} needed"
    )]
    TooFewReversals {
        /// Reversals per joint found.
        found: usize,
        /// Needed.
        needed: usize,
    },
    /// Moving the parameter does not change the replay (e.g. the goals never ask for the
    /// top speed).
    #[error(
        "the recording does not depend on it (moved off its fit, the replay fits no worse beyond chance)"
    )]
    NoEffect,
    /// A joint held in the air carries no load.
    #[error("a servo held in the air carries no load: the torque limit is not in the recording")]
    NoLoad,
}

/// The fit of one group of joints (all joints sharing one model, or one joint).
#[derive(Debug, Clone, PartialEq)]
pub struct GroupFit {
    /// The joints (indices).
    pub joints: Vec<usize>,
    /// Gain (1/s).
    pub gain: Identified,
    /// Top speed (degrees/s).
    pub max_vel_deg_s: Identified,
    /// Dead band (degrees).
    pub dead_band_deg: Identified,
    /// Latency (s).
    pub latency_s: Identified,
}

/// The model of `x` (CMA-ES's search coordinates, each of order 1).
fn model_of(x: &[f64]) -> ServoModel {
    ServoModel {
        gain: (60.0 * x[0].clamp(-5.0, 5.0).exp()).clamp(1.0, 5000.0),
        max_vel_deg_s: (300.0 * x[1].clamp(-5.0, 5.0).exp()).clamp(5.0, 10_000.0),
        dead_band_deg: x[2].abs().min(10.0),
        latency_s: (0.02 * x[3].abs()).min(0.5),
    }
}

/// The RMS (degrees) of `model` replayed against the recorded angles of `joints`.
pub fn group_rms(rec: &Recording, joints: &[usize], model: &ServoModel) -> f64 {
    let mut sum = 0.0;
    for &j in joints {
        let start = rec.real[j].first().copied().unwrap_or(0.0);
        let sim = replay(model, &rec.times, &rec.desired[j], start);
        sum += rms(&sim, &rec.real[j]).powi(2);
    }
    (sum / joints.len().max(1) as f64).sqrt()
}

/// The best model of each of `runs` CMA-ES searches (seeds from `seed`) for `joints`, with
/// its RMS error.
fn fit_runs(rec: &Recording, joints: &[usize], runs: u32, seed: u64) -> Vec<(f64, ServoModel)> {
    let objective = |x: &[f64]| group_rms(rec, joints, &model_of(x));
    let mut fits: Vec<(f64, ServoModel)> = Vec::with_capacity(runs as usize);
    for r in 0..runs.max(1) {
        let mut es = CmaEs::new(vec![0.0, 0.0, 0.2, 0.5], 0.6, 10, seed + u64::from(r));
        let mut best = (f64::INFINITY, model_of(&[0.0, 0.0, 0.2, 0.5]));
        for _ in 0..GENERATIONS {
            let points = es.ask();
            let values: Vec<f64> = points.iter().map(|p| objective(p.as_slice())).collect();
            for (p, v) in points.iter().zip(&values) {
                if *v < best.0 {
                    best = (*v, model_of(p.as_slice()));
                }
            }
            es.tell(&points, &values);
            if es.spread() < 1e-6 {
                break;
            }
        }
        fits.push(best);
    }
    fits
}

/// Fits one model for `joints` from `runs` seeds starting at `seed`; each parameter is
/// identified when moving it changes the fit significantly (a likelihood ratio).
pub fn fit_group(rec: &Recording, joints: &[usize], runs: u32, seed: u64) -> GroupFit {
    let fits = fit_runs(rec, joints, runs, seed);
    let (best_rms, model) = fits
        .iter()
        .copied()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((f64::INFINITY, model_of(&[0.0; 4])));
    let spread = |f: fn(&ServoModel) -> f64| {
        let n = fits.len() as f64;
        let mean = fits.iter().map(|(_, m)| f(m)).sum::<f64>() / n;
        (fits.iter().map(|(_, m)| (f(m) - mean).powi(2)).sum::<f64>() / n).sqrt()
    };
    let samples = (rec.times.len() * joints.len()) as f64;
    let sensitive = |moved: ServoModel| {
        let ratio = (group_rms(rec, joints, &moved) / best_rms.max(1e-12)).powi(2);
        samples * ratio.ln() > LIKELIHOOD_RATIO
    };
    let judge = |value: f64, spread: f64, moved: ServoModel| {
        if sensitive(moved) {
            Identified::Value { value, spread }
        } else {
            Identified::Unidentifiable(Unidentifiable::NoEffect)
        }
    };
    // Per joint, on average: joints driven slowly show the dead band, fast ones the lag.
    let reversals = joints.iter().map(|&j| rec.reversals(j)).sum::<usize>() / joints.len().max(1);
    let period = rec.sample_period().max(0.001);
    GroupFit {
        joints: joints.to_vec(),
        gain: judge(
            model.gain,
            spread(|m| m.gain),
            ServoModel {
                gain: model.gain * 1.3,
                ..model
            },
        ),
        max_vel_deg_s: judge(
            model.max_vel_deg_s,
            spread(|m| m.max_vel_deg_s),
            ServoModel {
                max_vel_deg_s: model.max_vel_deg_s * 0.7,
                ..model
            },
        ),
        dead_band_deg: judge(
            model.dead_band_deg,
            spread(|m| m.dead_band_deg),
            ServoModel {
                dead_band_deg: model.dead_band_deg + 0.5,
                ..model
            },
        ),
        latency_s: if reversals < MIN_REVERSALS {
            Identified::Unidentifiable(Unidentifiable::TooFewReversals {
                found: reversals,
                needed: MIN_REVERSALS,
            })
        } else {
            judge(
                model.latency_s,
                spread(|m| m.latency_s),
                ServoModel {
                    latency_s: model.latency_s + period,
                    ..model
                },
            )
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine sweep from 0.3 to 1.5 Hz, 40 degrees, sampled every 10 ms, for `seconds`,
    /// followed by `truth` on every joint.
    fn recording(truth: &ServoModel, seconds: f64, joints: usize) -> Recording {
        let times: Vec<f64> = (0..=(seconds * 100.0) as usize)
            .map(|k| k as f64 * 0.01)
            .collect();
        let desired: Vec<f64> = times
            .iter()
            .map(|t| {
                let f = 0.3 + 1.2 * t / seconds;
                40.0 * (std::f64::consts::TAU * f * t).sin()
            })
            .collect();
        let real = replay(truth, &times, &desired, 0.0);
        Recording {
            file: "synthetic".into(),
            times,
            desired: vec![desired; joints],
            real: vec![real; joints],
        }
    }

    #[test]
    fn hidden_parameters_are_recovered_and_a_short_recording_keeps_the_latency_unknown() {
        let truth = ServoModel {
            gain: 25.0,
            max_vel_deg_s: 150.0,
            dead_band_deg: 0.8,
            latency_s: 0.03,
        };
        let fit = fit_group(&recording(&truth, 20.0, 1), &[0], 3, 1);
        let near = |id: &Identified, want: f64, tol: f64| {
            let v = id.value().unwrap_or(f64::NAN);
            assert!((v - want).abs() <= tol, "{v} against {want}");
        };
        near(&fit.gain, 25.0, 2.5);
        near(&fit.max_vel_deg_s, 150.0, 15.0);
        near(&fit.dead_band_deg, 0.8, 0.08);
        near(&fit.latency_s, 0.03, 0.01);
        let short = fit_group(&recording(&truth, 3.0, 1), &[0], 1, 1);
        assert!(
            matches!(
                short.latency_s,
                Identified::Unidentifiable(Unidentifiable::TooFewReversals { .. })
            ),
            "{:?}",
            short.latency_s
        );
    }
}

//! The servo model a calibration fits, replayed on a recording: the simulator's servo law
//! ([`servo_velocity`]) moving a joint held in the air (no load) toward the goals it sees
//! after its latency, integrated in 0.5-ms steps, never past its goal — the same motion
//! model the emulated servos use. The goals between two samples are interpolated linearly
//! (the control loop sends one every step; the recording keeps one every few).

use crate::sim::servo::servo_velocity;

/// Longest integration step (s).
const SUBSTEP: f64 = 0.0005;

/// One servo's model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoModel {
    /// Proportional gain (1/s).
    pub gain: f64,
    /// Top speed (degrees/s).
    pub max_vel_deg_s: f64,
    /// Angle error left uncorrected (degrees).
    pub dead_band_deg: f64,
    /// How long a goal takes to act (s).
    pub latency_s: f64,
}

/// The angles (degrees) the model servo holds at `times` when the goals `desired`
/// (interpolated between samples) drive it from `start`.
pub fn replay(model: &ServoModel, times: &[f64], desired: &[f64], start: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(times.len());
    let Some(&t0) = times.first() else {
        return out;
    };
    let mut angle = start;
    let mut t = t0;
    // The last goal written at or before a time (its index), for times that only grow.
    let mut goal_at = 0usize;
    for &until in times {
        while t < until - 1e-12 {
            let h = SUBSTEP.min(until - t);
            t += h;
            let seen_time = t - model.latency_s;
            while goal_at + 1 < times.len() && times[goal_at + 1] <= seen_time + 1e-12 {
                goal_at += 1;
            }
            let goal = if seen_time < t0 {
                start
            } else {
                interpolated(times, desired, goal_at, seen_time)
            };
            let error = goal - angle;
            let v = servo_velocity(model.gain, model.max_vel_deg_s, model.dead_band_deg, error);
            let step = v * h;
            angle += if step.abs() > error.abs() {
                error
            } else {
                step
            };
        }
        out.push(angle);
    }
    out
}

/// The goal at `time`, between sample `i` (at or before it) and the next.
fn interpolated(times: &[f64], desired: &[f64], i: usize, time: f64) -> f64 {
    match (times.get(i + 1), desired.get(i + 1)) {
        (Some(&t1), Some(&d1)) if t1 > times[i] => {
            let w = ((time - times[i]) / (t1 - times[i])).clamp(0.0, 1.0);
            desired[i] + w * (d1 - desired[i])
        }
        _ => desired[i],
    }
}

/// Root mean square (degrees) of the differences of two series.
pub fn rms(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return 0.0;
    }
    let s: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    (s / n as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_is_followed_at_top_speed_then_exponentially_and_late() {
        let times: Vec<f64> = (0..=100).map(|k| f64::from(k) * 0.01).collect();
        let desired: Vec<f64> = times
            .iter()
            .map(|t| if *t >= 0.1 { 30.0 } else { 0.0 })
            .collect();
        let model = ServoModel {
            gain: 20.0,
            max_vel_deg_s: 100.0,
            dead_band_deg: 0.0,
            latency_s: 0.05,
        };
        let a = replay(&model, &times, &desired, 0.0);
        // Nothing moves before the step has passed the latency (0.1 + 0.05 s).
        assert!(a[14].abs() < 1e-9, "{}", a[14]);
        // Then (the goal ramping in over its last 10-ms sample) 100 deg/s while the error
        // is above 5 degrees: about 11 degrees at 0.25 s.
        assert!(a[25] > 10.0 && a[25] < 11.5, "{}", a[25]);
        assert!(a[100] > 29.9 && a[100] <= 30.0, "{}", a[100]);
    }
}

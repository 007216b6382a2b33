//! What every pattern generator gets besides its own equations (thesis 5.2.1, listing
//! A.2), as a helper it embeds rather than a base class: estimates of each joint's
//! frequency and of the phase difference to its tail-side neighbour, measured from the
//! module's own output, and Gaussian white noise for starting states.
//!
//! Estimates come from upward crossings of each joint's output through its centre (the
//! module's offset): the time between two crossings of a joint is its period; the time
//! between a joint's crossing and its neighbour's last one, as a fraction of the period,
//! is the phase difference (degrees, in (-180, 180], positive when the joint lags).

use crate::config::module_types::ParamDescriptor;
use crate::control::module::InternalData;
use crate::rng::SimRng;

/// The amplitude parameter every pattern generator has.
pub const AMPLITUDE_PARAM: ParamDescriptor = ParamDescriptor {
    name: "Amplitude",
    aliases: &[],
    unit: "deg",
    default: 40.0,
    min: 0.0,
    max: 90.0,
    help: "amplitude of the joint's oscillation",
};
/// The frequency parameter of the pattern generators that accept 0 Hz (a frozen wave).
pub const FREQUENCY_PARAM: ParamDescriptor = ParamDescriptor {
    name: "Frequency",
    aliases: &[],
    unit: "Hz",
    default: 1.0,
    min: 0.0,
    max: 10.0,
    help: "frequency 1/T of the wave",
};
/// The offset parameter every pattern generator has.
pub const OFFSET_PARAM: ParamDescriptor = ParamDescriptor {
    name: "Offset",
    aliases: &[],
    unit: "deg",
    default: 0.0,
    min: -90.0,
    max: 90.0,
    help: "offset added to the oscillation",
};
/// The commanded lag of a joint behind its tail-side neighbour.
pub const PHASE_DIFFERENCE_PARAM: ParamDescriptor = ParamDescriptor {
    name: "Phase_Difference",
    aliases: &["Phase difference", "Phase lag", "Phase"],
    unit: "deg",
    default: 55.0,
    min: -180.0,
    max: 180.0,
    help: "phase lag of a joint behind its tail-side neighbour (> 0: crawl head first)",
};

/// Frequency and phase-difference estimation per joint.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternExtras {
    prev: Vec<f64>,
    started: bool,
    last_crossing: Vec<Option<f64>>,
    period: Vec<Option<f64>>,
    frequency: Vec<f64>,
    phase_difference: Vec<f64>,
}

impl PatternExtras {
    /// Extras for `joints` joints, at rest.
    pub fn new(joints: usize) -> Self {
        PatternExtras {
            prev: vec![0.0; joints],
            started: false,
            last_crossing: vec![None; joints],
            period: vec![None; joints],
            frequency: vec![0.0; joints],
            phase_difference: vec![0.0; joints],
        }
    }

    /// Forgets every estimate.
    pub fn reset(&mut self) {
        let n = self.prev.len();
        *self = PatternExtras::new(n);
    }

    /// Takes the output `out` (degrees) computed for time `time`, with the joints' centres
    /// `centre` (their offsets), one step `dt` after the previous call.
    pub fn observe(&mut self, time: f64, dt: f64, out: &[f64], centre: impl Fn(usize) -> f64) {
        if !self.started {
            self.prev.copy_from_slice(out);
            self.started = true;
            return;
        }
        for (j, &cur) in out.iter().enumerate() {
            let c = centre(j);
            let (a, b) = (self.prev[j] - c, cur - c);
            if a < 0.0 && b >= 0.0 {
                let t = time - dt + dt * (-a / (b - a));
                if let Some(last) = self.last_crossing[j] {
                    let period = t - last;
                    if period > 0.0 {
                        self.period[j] = Some(period);
                        self.frequency[j] = 1.0 / period;
                    }
                }
                self.last_crossing[j] = Some(t);
                if j > 0
                    && let (Some(n), Some(period)) = (self.last_crossing[j - 1], self.period[j - 1])
                {
                    let lag = 360.0 * (t - n) / period;
                    self.phase_difference[j] = wrap_degrees(lag);
                }
            }
            self.prev[j] = cur;
        }
    }

    /// Writes the estimates into two series of a module's logged data.
    pub fn log(&self, data: &mut InternalData, frequency_series: usize, phase_series: usize) {
        data.series_mut(frequency_series)
            .copy_from_slice(&self.frequency);
        data.series_mut(phase_series)
            .copy_from_slice(&self.phase_difference);
    }

    /// Estimated frequency (Hz) per joint; 0 until two crossings were seen.
    pub fn frequency(&self) -> &[f64] {
        &self.frequency
    }

    /// Estimated lag (degrees) of each joint behind its tail-side neighbour; joint 0: 0.
    pub fn phase_difference(&self) -> &[f64] {
        &self.phase_difference
    }
}

/// An angle in degrees wrapped to (-180, 180].
pub fn wrap_degrees(a: f64) -> f64 {
    let w = a.rem_euclid(360.0);
    if w > 180.0 { w - 360.0 } else { w }
}

/// Fills `state` with Gaussian white noise of standard deviation `sigma`.
pub fn gaussian_noise(rng: &mut SimRng, sigma: f64, state: &mut [f64]) {
    for s in state {
        *s = sigma * rng.gaussian();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_a_known_wave() {
        let mut e = PatternExtras::new(3);
        let dt = 0.001;
        let (f, lag, offset) = (0.8, 40.0_f64, 5.0);
        let mut out = [0.0; 3];
        for k in 0..5000 {
            let t = k as f64 * dt;
            for (j, o) in out.iter_mut().enumerate() {
                *o = 20.0 * (std::f64::consts::TAU * f * t - (j as f64 * lag).to_radians()).sin()
                    + offset;
            }
            e.observe(t, dt, &out, |_| offset);
        }
        for j in 0..3 {
            assert!((e.frequency()[j] - f).abs() < 1e-3, "{:?}", e.frequency());
        }
        assert!(
            (e.phase_difference()[1] - lag).abs() < 0.1,
            "{:?}",
            e.phase_difference()
        );
        assert!(
            (e.phase_difference()[2] - lag).abs() < 0.1,
            "{:?}",
            e.phase_difference()
        );
    }

    #[test]
    fn wraps_and_noise_is_seeded() {
        assert_eq!(wrap_degrees(190.0), -170.0);
        assert_eq!(wrap_degrees(-180.0), 180.0);
        let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
        gaussian_noise(&mut SimRng::new(3), 0.1, &mut a);
        gaussian_noise(&mut SimRng::new(3), 0.1, &mut b);
        assert_eq!(a, b);
        assert!(a.iter().any(|v| *v != 0.0));
    }
}

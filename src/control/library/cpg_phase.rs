//! `PatternGenerator_cpg_phase`: a chain of coupled phase oscillators with amplitude and
//! offset convergence (Ijspeert's CPG model, thesis 3.3.2 and its reference [32]):
//!
//! ```text
//! θ̇_i = 2π f_i + Σ_{j = i±1} w sin(θ_j − θ_i − ϕ_ij)
//! r̈_i = a (a/4 (A_i − r_i) − ṙ_i)        ẍ_i = a (a/4 (O_i − x_i) − ẋ_i)
//! φ_i = x_i + r_i sin θ_i
//! ```
//!
//! with ϕ_{i,i−1} = Δϕ_i and ϕ_{i,i+1} = −Δϕ_{i+1}: as for the sine generator, joint i lags
//! its tail-side neighbour by its `Phase_Difference`. Amplitude and offset follow their
//! targets as critically damped second-order systems, so parameter changes (from the GUI,
//! a gamepad or an optimizer) give smooth transitions. Phases start from Gaussian white
//! noise of `Noise` radians (seeded); `distort` kicks a joint's phase to study recovery.

use std::f64::consts::TAU;

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::control::pattern::{
    AMPLITUDE_PARAM, FREQUENCY_PARAM, OFFSET_PARAM, PHASE_DIFFERENCE_PARAM, PatternExtras,
    gaussian_noise,
};
use crate::rng::SimRng;

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const PHASE_DIFFERENCE: usize = 2;
const OFFSET: usize = 3;
const COUPLING: usize = 4;
const CONVERGENCE: usize = 5;
const NOISE: usize = 6;

const PARAMETERS: &[ParamDescriptor] = &[
    AMPLITUDE_PARAM,
    FREQUENCY_PARAM,
    PHASE_DIFFERENCE_PARAM,
    OFFSET_PARAM,
    ParamDescriptor {
        name: "Coupling",
        aliases: &["Weight"],
        unit: "1/s",
        default: 5.0,
        min: 0.0,
        max: 100.0,
        help: "coupling weight w between neighbours",
    },
    ParamDescriptor {
        name: "Convergence",
        aliases: &["Gain"],
        unit: "1/s",
        default: 20.0,
        min: 0.1,
        max: 500.0,
        help: "rate a at which amplitude and offset follow their targets",
    },
    ParamDescriptor {
        name: "Noise",
        aliases: &[],
        unit: "rad",
        default: 0.5,
        min: 0.0,
        max: 3.2,
        help: "standard deviation of the starting phases",
    },
];

const SERIES: &[&str] = &[
    "Angle",
    "Phase",
    "Amplitude_state",
    "Offset_state",
    "Frequency",
    "Phase_Difference",
];

/// The type's descriptor.
pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "PatternGenerator_cpg_phase",
        summary: "coupled phase-oscillator chain (Ijspeert)",
        parameters: PARAMETERS,
        series: SERIES,
        sensing: false,
        network: false,
    }
}

/// The phase-oscillator chain.
#[derive(Debug, Clone)]
pub struct CpgPhase {
    core: ModuleCore,
    theta: Vec<f64>,
    r: Vec<f64>,
    dr: Vec<f64>,
    x: Vec<f64>,
    dx: Vec<f64>,
    dtheta: Vec<f64>,
    extras: PatternExtras,
}

impl CpgPhase {
    /// A module for `joints` connected joints, its parameters at their defaults.
    pub fn new(joints: usize) -> Self {
        CpgPhase {
            core: ModuleCore::new(descriptor(), joints),
            theta: vec![0.0; joints],
            r: vec![0.0; joints],
            dr: vec![0.0; joints],
            x: vec![0.0; joints],
            dx: vec![0.0; joints],
            dtheta: vec![0.0; joints],
            extras: PatternExtras::new(joints),
        }
    }

    /// Kicks joint `joint`'s phase by `degrees` (distortion injection).
    pub fn kick(&mut self, joint: usize, degrees: f64) {
        if let Some(t) = self.theta.get_mut(joint) {
            *t += degrees.to_radians();
        }
    }
}

impl ActuationModule for CpgPhase {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, rng: &mut SimRng) {
        let sigma = self.core.params.get(NOISE, 0);
        gaussian_noise(rng, sigma, &mut self.theta);
        for v in [
            &mut self.r,
            &mut self.dr,
            &mut self.x,
            &mut self.dx,
            &mut self.dtheta,
        ] {
            v.fill(0.0);
        }
        self.extras.reset();
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        let p = &self.core.params;
        let n = out.len();
        let dt = ctx.dt;
        // Phase velocities from the current phases (coupling to both neighbours).
        for i in 0..n {
            let w = p.get(COUPLING, i);
            let mut d = TAU * p.get(FREQUENCY, i);
            if i > 0 {
                d += w
                    * (self.theta[i - 1] - self.theta[i] - p.get(PHASE_DIFFERENCE, i).to_radians())
                        .sin();
            }
            if i + 1 < n {
                d += w
                    * (self.theta[i + 1] - self.theta[i]
                        + p.get(PHASE_DIFFERENCE, i + 1).to_radians())
                    .sin();
            }
            self.dtheta[i] = d;
        }
        for (i, o) in out.iter_mut().enumerate() {
            let a = p.get(CONVERGENCE, i);
            // Semi-implicit Euler: velocities first, then positions.
            self.dr[i] += dt * a * (a / 4.0 * (p.get(AMPLITUDE, i) - self.r[i]) - self.dr[i]);
            self.r[i] += dt * self.dr[i];
            self.dx[i] += dt * a * (a / 4.0 * (p.get(OFFSET, i) - self.x[i]) - self.dx[i]);
            self.x[i] += dt * self.dx[i];
            self.theta[i] = (self.theta[i] + dt * self.dtheta[i]).rem_euclid(TAU);
            *o = self.x[i] + self.r[i] * self.theta[i].sin();
        }
        let x = &self.x;
        self.extras.observe(ctx.time, dt, out, |j| x[j]);
        let data = &mut self.core.data;
        data.series_mut(0).copy_from_slice(out);
        for (d, t) in data.series_mut(1).iter_mut().zip(&self.theta) {
            *d = t.to_degrees();
        }
        data.series_mut(2).copy_from_slice(&self.r);
        data.series_mut(3).copy_from_slice(&self.x);
        self.extras.log(data, 4, 5);
    }

    /// Kicks the joint's phase by `amount` degrees.
    fn perturb(&mut self, joint: usize, amount: f64) -> bool {
        self.kick(joint, amount);
        joint < self.theta.len()
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(m: &mut CpgPhase, from: usize, steps: usize, dt: f64) -> Vec<Vec<f64>> {
        crate::control::module::drive(m, from, steps, dt)
    }

    #[test]
    fn converges_to_the_commanded_phase_lag_from_noise() {
        let mut m = CpgPhase::new(5);
        m.core.params.set(PHASE_DIFFERENCE, None, 55.0).unwrap();
        m.core.params.set(AMPLITUDE, None, 30.0).unwrap();
        m.reset(&mut SimRng::new(42));
        let start: Vec<f64> = m.theta.clone();
        assert!(start.iter().any(|t| *t != 0.0), "noise start");
        run(&mut m, 0, 10_000, 0.001);
        let pd = m.extras.phase_difference();
        for (j, d) in pd.iter().enumerate().skip(1) {
            assert!((d - 55.0).abs() < 1.0, "joint {j}: {d} deg, all {pd:?}");
        }
        for f in m.extras.frequency() {
            assert!((f - 1.0).abs() < 0.01, "{f}");
        }
        assert!(m.r.iter().all(|r| (r - 30.0).abs() < 0.01), "{:?}", m.r);
    }

    #[test]
    fn same_seed_same_start_other_seed_other_start() {
        let mut a = CpgPhase::new(4);
        let mut b = CpgPhase::new(4);
        a.reset(&mut SimRng::new(1));
        b.reset(&mut SimRng::new(1));
        assert_eq!(a.theta, b.theta);
        b.reset(&mut SimRng::new(2));
        assert_ne!(a.theta, b.theta);
    }

    #[test]
    fn parameter_changes_are_smooth_and_a_kick_recovers() {
        let mut m = CpgPhase::new(3);
        m.reset(&mut SimRng::new(7));
        let dt = 0.001;
        let settled = run(&mut m, 0, 5000, dt);
        m.core.params.set(AMPLITUDE, None, 60.0).unwrap();
        m.core.params.set(OFFSET, None, 10.0).unwrap();
        let after = run(&mut m, 5000, 3000, dt);
        // No jump: the largest change in one step stays near the wave's own slope
        // (2π f A = 0.38 deg/ms at 60 deg) instead of leaping by the 30 deg change.
        let mut prev = settled.last().unwrap().clone();
        let mut worst: f64 = 0.0;
        for row in &after {
            for (a, b) in row.iter().zip(&prev) {
                worst = worst.max((a - b).abs());
            }
            prev = row.clone();
        }
        assert!(worst < 0.6, "largest step {worst} deg");
        assert!(
            m.r.iter().all(|r| (r - 60.0).abs() < 0.05)
                && m.x.iter().all(|x| (x - 10.0).abs() < 0.05)
        );
        m.kick(1, 90.0);
        run(&mut m, 8000, 8000, dt);
        let pd = m.extras.phase_difference();
        assert!(
            (pd[1] - 55.0).abs() < 1.0 && (pd[2] - 55.0).abs() < 1.0,
            "{pd:?}"
        );
    }
}

//! `PatternGenerator_sinusoidal`: φ_i(t) = A_i sin(2π f_i t + ϕ_i) + O_i (thesis eq. 3.1,
//! table 3.1), parameters uniform or per joint.
//!
//! Joint i lags joint 0 by the sum of the `Phase_Difference` values of joints 1..=i, so
//! with a uniform value ϕ_i = -i·Δϕ (joint 0 is the first joint of the mask, the tail in
//! the ready robots): with Δϕ > 0 the wave runs from the tail to the head, and a pitching
//! chain crawls head first; a negative Δϕ reverses both. The time term is integrated per joint (θ_i += 2π f_i δ), so
//! changing the frequency while running bends the wave smoothly instead of jumping.

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::control::pattern::{
    AMPLITUDE_PARAM, FREQUENCY_PARAM, OFFSET_PARAM, PHASE_DIFFERENCE_PARAM, PatternExtras,
};
use crate::rng::SimRng;

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const PHASE_DIFFERENCE: usize = 2;
const OFFSET: usize = 3;

const PARAMETERS: &[ParamDescriptor] = &[
    AMPLITUDE_PARAM,
    FREQUENCY_PARAM,
    PHASE_DIFFERENCE_PARAM,
    OFFSET_PARAM,
];

/// The type's descriptor.
pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "PatternGenerator_sinusoidal",
        summary: "sine travelling wave (eq. 3.1)",
        parameters: PARAMETERS,
        series: &["Angle", "Phase", "Frequency", "Phase_Difference"],
        sensing: false,
        network: false,
    }
}

/// The sine generator.
#[derive(Debug, Clone)]
pub struct Sinusoidal {
    core: ModuleCore,
    /// Integrated 2π f t per joint (radians).
    theta: Vec<f64>,
    /// Frequency and phase-difference estimates from the output (thesis A.2).
    extras: PatternExtras,
}

impl Sinusoidal {
    /// A module for `joints` connected joints, its parameters at their defaults.
    pub fn new(joints: usize) -> Self {
        Sinusoidal {
            core: ModuleCore::new(descriptor(), joints),
            theta: vec![0.0; joints],
            extras: PatternExtras::new(joints),
        }
    }
}

impl ActuationModule for Sinusoidal {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, _rng: &mut SimRng) {
        self.theta.fill(0.0);
        self.extras.reset();
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        let ModuleCore {
            params: p, data, ..
        } = &mut self.core;
        let mut lead = 0.0;
        for (j, angle) in out.iter_mut().enumerate() {
            if j > 0 {
                lead -= p.get(PHASE_DIFFERENCE, j).to_radians();
            }
            let phase = self.theta[j] + lead;
            *angle = p.get(AMPLITUDE, j) * phase.sin() + p.get(OFFSET, j);
            data.series_mut(1)[j] = phase.to_degrees().rem_euclid(360.0);
            self.theta[j] = (self.theta[j] + std::f64::consts::TAU * p.get(FREQUENCY, j) * ctx.dt)
                .rem_euclid(std::f64::consts::TAU);
        }
        data.series_mut(0).copy_from_slice(out);
        self.extras
            .observe(ctx.time, ctx.dt, out, |j| p.get(OFFSET, j));
        self.extras.log(data, 2, 3);
    }

    /// Shifts the joint's phase by `amount` degrees (it keeps the shift: no coupling).
    fn perturb(&mut self, joint: usize, amount: f64) -> bool {
        self.theta
            .get_mut(joint)
            .map(|t| *t += amount.to_radians())
            .is_some()
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(m: &mut Sinusoidal, steps: usize, dt: f64) -> Vec<Vec<f64>> {
        crate::control::module::drive(m, 0, steps, dt)
    }

    #[test]
    fn follows_equation_3_1() {
        let mut m = Sinusoidal::new(3);
        m.core.params.set(AMPLITUDE, None, 30.0).unwrap();
        m.core.params.set(FREQUENCY, None, 0.5).unwrap();
        m.core.params.set(PHASE_DIFFERENCE, None, 90.0).unwrap();
        m.core.params.set(OFFSET, Some(2), 5.0).unwrap();
        let dt = 0.001;
        let out = run(&mut m, 1001, dt);
        for (k, row) in out.iter().enumerate() {
            let t = k as f64 * dt;
            for (j, v) in row.iter().enumerate() {
                let offset = if j == 2 { 5.0 } else { 0.0 };
                let expected = 30.0
                    * (std::f64::consts::PI * t - (j as f64) * std::f64::consts::FRAC_PI_2).sin()
                    + offset;
                assert!(
                    (v - expected).abs() < 1e-9,
                    "step {k} joint {j}: {v} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn individual_amplitudes_and_reset() {
        let mut m = Sinusoidal::new(2);
        m.core.params.set_all(AMPLITUDE, &[10.0, 0.0]).unwrap();
        let out = run(&mut m, 300, 0.001);
        assert!(out.iter().all(|r| r[1] == 0.0));
        assert!(out.iter().any(|r| r[0] > 9.9));
        m.reset(&mut SimRng::new(0));
        let again = run(&mut m, 300, 0.001);
        assert_eq!(out, again);
    }

    #[test]
    fn bad_values_are_refused() {
        let mut m = Sinusoidal::new(2);
        use crate::control::module::ParamError;
        assert!(matches!(
            m.core.params.set(AMPLITUDE, None, f64::NAN),
            Err(ParamError::NotFinite { .. })
        ));
        assert!(matches!(
            m.core.params.set(AMPLITUDE, None, 120.0),
            Err(ParamError::OutOfRange { value: 120.0, .. })
        ));
        assert!(matches!(
            m.core.params.set(AMPLITUDE, Some(2), 10.0),
            Err(ParamError::JointOutOfRange {
                joint: 2,
                joints: 2
            })
        ));
        assert!(matches!(
            m.core.params.set_all(AMPLITUDE, &[1.0]),
            Err(ParamError::WrongCount {
                given: 1,
                joints: 2,
                ..
            })
        ));
    }

    #[test]
    fn estimates_its_own_frequency_and_phase_difference() {
        let mut m = Sinusoidal::new(4);
        m.core.params.set(FREQUENCY, None, 1.5).unwrap();
        m.core.params.set(PHASE_DIFFERENCE, None, 40.0).unwrap();
        run(&mut m, 3000, 0.001);
        let d = m.internal_data();
        assert!(
            d.series(2).iter().all(|f| (f - 1.5).abs() < 0.01),
            "{:?}",
            d.series(2)
        );
        assert!(
            d.series(3)[1..].iter().all(|p| (p - 40.0).abs() < 0.5),
            "{:?}",
            d.series(3)
        );
    }
}

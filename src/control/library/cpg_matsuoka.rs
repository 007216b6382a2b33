//! `PatternGenerator_cpg_matsuoka`: a chain of Matsuoka half-centre oscillators (thesis
//! 3.3.2 and its reference [41]), one per joint: two mutually inhibiting neurons with
//! self-adaptation,
//!
//! ```text
//! τ u̇_e = −u_e − β v_e − w y_f + s − c y_f'     τ_a v̇_e = −v_e + y_e     y = max(0, u)
//! τ u̇_f = −u_f − β v_f − w y_e + s − c y_e'     τ_a v̇_f = −v_f + y_f
//! φ = O + A (y_e − y_f) / K
//! ```
//!
//! where `'` marks the tail-side neighbour's neurons (joint 0 has none): the inhibitory
//! coupling `c` turns the chain into a travelling wave whose lag between neighbours
//! emerges from the dynamics; it is estimated and logged as `Phase_Difference`.
//! β = 2.5, w = 2.5, τ_a = 2τ and s = 1 are fixed; τ is set from the commanded frequency,
//! and K (the oscillator's own peak) scales the output to the commanded amplitude. Both
//! the natural period in units of τ and K are measured once from an uncoupled oscillator.

use std::sync::OnceLock;

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::control::pattern::{AMPLITUDE_PARAM, OFFSET_PARAM, PatternExtras, gaussian_noise};
use crate::rng::SimRng;

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const OFFSET: usize = 2;
const COUPLING: usize = 3;
const NOISE: usize = 4;

const BETA: f64 = 2.5;
const W: f64 = 2.5;
const ADAPTATION_RATIO: f64 = 2.0;
const TONIC: f64 = 1.0;

const PARAMETERS: &[ParamDescriptor] = &[
    AMPLITUDE_PARAM,
    ParamDescriptor {
        name: "Frequency",
        aliases: &[],
        unit: "Hz",
        default: 1.0,
        min: 0.05,
        max: 10.0,
        help: "oscillation frequency",
    },
    OFFSET_PARAM,
    ParamDescriptor {
        name: "Coupling",
        aliases: &["Weight"],
        unit: "",
        default: 1.0,
        min: 0.0,
        max: 5.0,
        help: "inhibition from the tail-side neighbour (0: independent joints)",
    },
    ParamDescriptor {
        name: "Noise",
        aliases: &[],
        unit: "",
        default: 0.1,
        min: 0.0,
        max: 1.0,
        help: "standard deviation of the starting neuron states",
    },
];

const SERIES: &[&str] = &[
    "Angle",
    "Extensor",
    "Flexor",
    "Frequency",
    "Phase_Difference",
];

/// The type's descriptor.
pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "PatternGenerator_cpg_matsuoka",
        summary: "Matsuoka mutual-inhibition oscillator chain",
        parameters: PARAMETERS,
        series: SERIES,
        sensing: false,
        network: false,
    }
}

/// State of one half-centre oscillator: membrane potentials and adaptations.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Neurons {
    ue: f64,
    uf: f64,
    ve: f64,
    vf: f64,
}

impl Neurons {
    fn ye(&self) -> f64 {
        self.ue.max(0.0)
    }

    fn yf(&self) -> f64 {
        self.uf.max(0.0)
    }

    /// One explicit Euler step of `h` (in units of τ) with extra inputs to e and f.
    fn step(&mut self, h: f64, extra_e: f64, extra_f: f64) {
        let (ye, yf) = (self.ye(), self.yf());
        let due = -self.ue - BETA * self.ve - W * yf + TONIC + extra_e;
        let duf = -self.uf - BETA * self.vf - W * ye + TONIC + extra_f;
        let dve = (-self.ve + ye) / ADAPTATION_RATIO;
        let dvf = (-self.vf + yf) / ADAPTATION_RATIO;
        self.ue += h * due;
        self.uf += h * duf;
        self.ve += h * dve;
        self.vf += h * dvf;
    }
}

/// The uncoupled oscillator's period (in units of τ) and output peak, measured once.
fn calibration() -> (f64, f64) {
    static CAL: OnceLock<(f64, f64)> = OnceLock::new();
    *CAL.get_or_init(|| {
        let h = 0.001;
        let mut n = Neurons {
            ue: 0.1,
            ..Neurons::default()
        };
        let (mut prev, mut crossings, mut peak) = (0.0, Vec::new(), 0.0f64);
        for k in 0..200_000 {
            n.step(h, 0.0, 0.0);
            let y = n.ye() - n.yf();
            if k > 50_000 {
                peak = peak.max(y.abs());
                if prev < 0.0 && y >= 0.0 {
                    crossings.push(k as f64 * h);
                }
            }
            prev = y;
        }
        let period = match (crossings.first(), crossings.last()) {
            (Some(a), Some(b)) if crossings.len() > 1 => (b - a) / (crossings.len() - 1) as f64,
            _ => 1.0,
        };
        (period, peak.max(1e-9))
    })
}

/// The Matsuoka chain.
#[derive(Debug, Clone)]
pub struct CpgMatsuoka {
    core: ModuleCore,
    neurons: Vec<Neurons>,
    noise: Vec<f64>,
    extras: PatternExtras,
}

impl CpgMatsuoka {
    /// A module for `joints` connected joints, its parameters at their defaults.
    pub fn new(joints: usize) -> Self {
        CpgMatsuoka {
            core: ModuleCore::new(descriptor(), joints),
            neurons: vec![Neurons::default(); joints],
            noise: vec![0.0; 2 * joints],
            extras: PatternExtras::new(joints),
        }
    }
}

impl ActuationModule for CpgMatsuoka {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, rng: &mut SimRng) {
        gaussian_noise(rng, self.core.params.get(NOISE, 0), &mut self.noise);
        for (n, pair) in self.neurons.iter_mut().zip(self.noise.chunks(2)) {
            *n = Neurons {
                ue: pair[0],
                uf: pair[1],
                ve: 0.0,
                vf: 0.0,
            };
        }
        self.extras.reset();
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        let (period, peak) = calibration();
        let p = &self.core.params;
        // Joints are updated from the tail: each sees its neighbour's outputs of this step.
        for (i, o) in out.iter_mut().enumerate() {
            let tau = 1.0 / (p.get(FREQUENCY, i) * period);
            let (extra_e, extra_f) = match i.checked_sub(1).and_then(|k| self.neurons.get(k)) {
                Some(prev) => {
                    let c = p.get(COUPLING, i);
                    (-c * prev.yf(), -c * prev.ye())
                }
                None => (0.0, 0.0),
            };
            let n = &mut self.neurons[i];
            n.step(ctx.dt / tau, extra_e, extra_f);
            *o = p.get(OFFSET, i) + p.get(AMPLITUDE, i) * (n.ye() - n.yf()) / peak;
        }
        self.extras
            .observe(ctx.time, ctx.dt, out, |j| p.get(OFFSET, j));
        let data = &mut self.core.data;
        data.series_mut(0).copy_from_slice(out);
        for (i, n) in self.neurons.iter().enumerate() {
            data.series_mut(1)[i] = n.ye();
            data.series_mut(2)[i] = n.yf();
        }
        self.extras.log(data, 3, 4);
    }

    /// Adds `amount` (in units of the tonic input) to the joint's extensor potential.
    fn perturb(&mut self, joint: usize, amount: f64) -> bool {
        self.neurons
            .get_mut(joint)
            .map(|n| n.ue += amount)
            .is_some()
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(m: &mut CpgMatsuoka, steps: usize, dt: f64) -> Vec<Vec<f64>> {
        crate::control::module::drive(m, 0, steps, dt)
    }

    #[test]
    fn oscillates_at_the_commanded_frequency_and_amplitude() {
        for f in [0.5, 1.0, 2.0] {
            let mut m = CpgMatsuoka::new(1);
            m.core.params.set(FREQUENCY, None, f).unwrap();
            m.core.params.set(AMPLITUDE, None, 25.0).unwrap();
            m.reset(&mut SimRng::new(3));
            let out = run(&mut m, 20_000, 0.001);
            let measured = m.extras.frequency()[0];
            assert!(
                (measured - f).abs() / f < 0.05,
                "commanded {f} Hz, measured {measured} Hz"
            );
            let peak = out[10_000..].iter().map(|r| r[0].abs()).fold(0.0, f64::max);
            eprintln!("commanded {f} Hz / 25 deg: measured {measured:.4} Hz, {peak:.2} deg");
            assert!((peak - 25.0).abs() < 2.5, "amplitude {peak} deg at {f} Hz");
        }
    }

    #[test]
    fn coupling_makes_a_steady_travelling_wave() {
        let mut m = CpgMatsuoka::new(4);
        m.reset(&mut SimRng::new(9));
        run(&mut m, 15_000, 0.001);
        let early = m.extras.phase_difference().to_vec();
        run(&mut m, 5_000, 0.001);
        let late = m.extras.phase_difference().to_vec();
        eprintln!("lags after 15 s {early:?}, after 20 s {late:?}");
        for j in 1..4 {
            assert!(late[j].abs() > 5.0, "neighbours in step: {late:?}");
            assert!(
                (late[j] - early[j]).abs() < 2.0,
                "lag drifts: {early:?} -> {late:?}"
            );
        }
    }

    #[test]
    fn noise_start_is_seeded() {
        let (mut a, mut b) = (CpgMatsuoka::new(3), CpgMatsuoka::new(3));
        a.reset(&mut SimRng::new(5));
        b.reset(&mut SimRng::new(5));
        assert_eq!(run(&mut a, 500, 0.001), run(&mut b, 500, 0.001));
        b.reset(&mut SimRng::new(6));
        a.reset(&mut SimRng::new(5));
        assert_ne!(run(&mut a, 500, 0.001), run(&mut b, 500, 0.001));
    }
}

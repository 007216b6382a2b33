//! `Square_wave`: a travelling square wave. Each joint switches between +A and -A (plus
//! an offset) as its phase passes 0 and π; `Sharpness` rounds the edges (a tanh of the
//! sine), so the servos are not asked for an infinitely fast step. With a phase
//! difference between joints it is a "bang-bang" version of the sine gait that lifts
//! and pushes with the whole amplitude for most of the cycle.

use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module, helpers};

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const PHASE_DIFFERENCE: usize = 2;
const OFFSET: usize = 3;
const SHARPNESS: usize = 4;

#[derive(Clone)]
struct SquareWave {
    /// Per joint: the integrated 2π f t (radians).
    theta: Vec<f64>,
}

/// tanh(k sin φ) / tanh(k): a sine for small k, a square wave for large k.
fn rounded_square(phase: f64, sharpness: f64) -> f64 {
    (sharpness * phase.sin()).tanh() / sharpness.tanh()
}

impl Module for SquareWave {
    const NAME: &'static str = "Square_wave";
    const SUMMARY: &'static str = "travelling square wave with rounded edges";
    const PARAMETERS: &'static [Param] = &[
        Param::new("Amplitude", 30.0, 0.0, 90.0).unit("deg"),
        Param::new("Frequency", 0.5, 0.0, 5.0).unit("Hz"),
        Param::new("Phase_Difference", 90.0, -360.0, 360.0).unit("deg"),
        Param::new("Offset", 0.0, -90.0, 90.0).unit("deg"),
        Param::new("Sharpness", 4.0, 0.1, 50.0).help("edge steepness: 0.1 ~ sine, 50 ~ square"),
    ];
    const SERIES: &'static [&'static str] = &["Angle", "Phase"];

    fn new(joints: usize) -> Self {
        SquareWave {
            theta: vec![0.0; joints],
        }
    }

    fn reset(&mut self, _seed: u64) {
        self.theta.fill(0.0);
    }

    fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {
        let mut lead = 0.0;
        for (j, angle) in out.iter_mut().enumerate() {
            if j > 0 {
                lead -= p.get(PHASE_DIFFERENCE, j).to_radians();
            }
            let phase = helpers::wrap_tau(self.theta[j] + lead);
            *angle =
                p.get(AMPLITUDE, j) * rounded_square(phase, p.get(SHARPNESS, j)) + p.get(OFFSET, j);
            data.set(0, j, *angle);
            data.set(1, j, phase.to_degrees());
            self.theta[j] = helpers::wrap_tau(
                self.theta[j] + std::f64::consts::TAU * p.get(FREQUENCY, j) * ctx.dt,
            );
        }
    }
}

export_module!(SquareWave);

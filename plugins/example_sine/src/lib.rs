//! `Plugin_sine`: the standard sine generator (thesis eq. 3.1) as a plugin, computed
//! exactly like the built-in `PatternGenerator_sinusoidal` (same arithmetic, so the same
//! configuration gives the same trajectory). It is the benchmark of plugin overhead.

use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module, helpers};

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const PHASE_DIFFERENCE: usize = 2;
const OFFSET: usize = 3;

/// Per joint: the integrated 2π f t (radians).
#[derive(Clone)]
struct Sine {
    theta: Vec<f64>,
}

impl Module for Sine {
    const NAME: &'static str = "Plugin_sine";
    const SUMMARY: &'static str = "sine travelling wave (eq. 3.1), as a plugin";
    const PARAMETERS: &'static [Param] = &[
        Param::new("Amplitude", 30.0, 0.0, 90.0).unit("deg"),
        Param::new("Frequency", 1.0, 0.0, 10.0).unit("Hz"),
        Param::new("Phase_Difference", 90.0, -360.0, 360.0)
            .unit("deg")
            .help("lag of each joint behind the previous one"),
        Param::new("Offset", 0.0, -90.0, 90.0).unit("deg"),
    ];
    const SERIES: &'static [&'static str] = &["Angle", "Phase"];

    fn new(joints: usize) -> Self {
        Sine {
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
            let phase = self.theta[j] + lead;
            *angle = p.get(AMPLITUDE, j) * phase.sin() + p.get(OFFSET, j);
            data.set(0, j, *angle);
            data.set(1, j, phase.to_degrees().rem_euclid(360.0));
            self.theta[j] = helpers::wrap_tau(
                self.theta[j] + std::f64::consts::TAU * p.get(FREQUENCY, j) * ctx.dt,
            );
        }
    }

    fn perturb(&mut self, joint: usize, amount: f64) -> bool {
        self.theta
            .get_mut(joint)
            .map(|t| *t += amount.to_radians())
            .is_some()
    }
}

export_module!(Sine);

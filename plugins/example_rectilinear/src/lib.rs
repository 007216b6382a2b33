//! `Rectilinear`: a caterpillar-style rectilinear gait for pitch joints. A single hump —
//! one period of a sine, compressed into the fraction `Duty` of the cycle — travels from
//! the tail to the head while the rest of the body lies flat on the ground, like the
//! wave of contraction of a caterpillar or the rectilinear gait of a snake. With
//! `Duty` = 1 it is the ordinary sine wave; smaller values keep more of the body in
//! contact with the ground (more grip, fewer joints moving at a time).

use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module, helpers};

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const PHASE_DIFFERENCE: usize = 2;
const DUTY: usize = 3;

#[derive(Clone)]
struct Rectilinear {
    /// The integrated 2π f t (radians), shared by all joints (the wave's clock).
    theta: f64,
}

/// The hump at phase φ ∈ [0, 2π): sin(φ / duty) inside the first `duty` of the cycle.
fn hump(phase: f64, duty: f64) -> f64 {
    let width = std::f64::consts::TAU * duty;
    if phase < width {
        (phase / duty).sin()
    } else {
        0.0
    }
}

impl Module for Rectilinear {
    const NAME: &'static str = "Rectilinear";
    const SUMMARY: &'static str = "caterpillar-style travelling hump (rectilinear gait)";
    const PARAMETERS: &'static [Param] = &[
        Param::new("Amplitude", 40.0, 0.0, 90.0).unit("deg"),
        Param::new("Frequency", 0.5, 0.0, 5.0).unit("Hz"),
        Param::new("Phase_Difference", 60.0, -360.0, 360.0)
            .unit("deg")
            .help("how far the hump has moved on at the next joint"),
        Param::new("Duty", 0.5, 0.05, 1.0).help("fraction of the cycle a joint is in the hump"),
    ];
    const SERIES: &'static [&'static str] = &["Angle", "Phase"];

    fn new(_joints: usize) -> Self {
        Rectilinear { theta: 0.0 }
    }

    fn reset(&mut self, _seed: u64) {
        self.theta = 0.0;
    }

    fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {
        let mut lead = 0.0;
        for (j, angle) in out.iter_mut().enumerate() {
            if j > 0 {
                lead -= p.get(PHASE_DIFFERENCE, j).to_radians();
            }
            let phase = helpers::wrap_tau(self.theta + lead);
            *angle = p.get(AMPLITUDE, j) * hump(phase, p.get(DUTY, j));
            data.set(0, j, *angle);
            data.set(1, j, phase.to_degrees());
        }
        let f = p.row(FREQUENCY).first().copied().unwrap_or(0.0);
        self.theta = helpers::wrap_tau(self.theta + std::f64::consts::TAU * f * ctx.dt);
    }

    fn perturb(&mut self, _joint: usize, amount: f64) -> bool {
        self.theta += amount.to_radians();
        true
    }
}

export_module!(Rectilinear);

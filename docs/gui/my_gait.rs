//! `MyGait`: a travelling sine whose amplitude grows smoothly from 0 over the first
//! `Ramp` seconds — written in the module editor for docs/gui_module_library.png.

use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module, helpers};

const AMPLITUDE: usize = 0;
const FREQUENCY: usize = 1;
const RAMP: usize = 2;
const SERIES_PHASE: usize = 0;

#[derive(Clone)]
struct MyGait {
    theta: f64,
}

/// 0 → 1 smoothly over [0, 1].
fn smooth(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

impl Module for MyGait {
    const NAME: &'static str = "MyGait";
    const SUMMARY: &'static str = "sine wave with a soft start";
    const PARAMETERS: &'static [Param] = &[
        Param::new("Amplitude", 40.0, 0.0, 90.0).unit("deg"),
        Param::new("Frequency", 1.0, 0.0, 5.0).unit("Hz"),
        Param::new("Ramp", 2.0, 0.1, 10.0).unit("s"),
    ];
    const SERIES: &'static [&'static str] = &["Phase"];

    fn new(_joints: usize) -> Self {
        MyGait { theta: 0.0 }
    }

    fn reset(&mut self, _seed: u64) {
        self.theta = 0.0;
    }

    fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {
        for (j, angle) in out.iter_mut().enumerate() {
            let phase = self.theta - 55f64.to_radians() * j as f64;
            let gain = smooth(ctx.time / p.get(RAMP, j));
            *angle = gain * p.get(AMPLITUDE, j) * phase.sin();
            data.set(SERIES_PHASE, j, phase.to_degrees());
        }
        let f = p.get(FREQUENCY, 0);
        self.theta = helpers::wrap_tau(self.theta + std::f64::consts::TAU * f * ctx.dt);
    }
}

export_module!(MyGait);

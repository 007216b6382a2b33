//! `Panicky`: a sine that panics once the simulated time passes `Panic_Time`.

use proleg_plugin_api::{Context, Data, Module, Param, Params, export_module};

#[derive(Clone)]
struct Panicky;

impl Module for Panicky {
    const NAME: &'static str = "Panicky";
    const PARAMETERS: &'static [Param] = &[
        Param::new("Amplitude", 30.0, 0.0, 90.0),
        Param::new("Panic_Time", 0.5, 0.0, 100.0),
    ];
    const SERIES: &'static [&'static str] = &["Angle"];

    fn new(_joints: usize) -> Self {
        Panicky
    }

    fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {
        for (j, o) in out.iter_mut().enumerate() {
            if ctx.time >= p.get(1, j) {
                panic!("deliberate failure at t = {:.3} s", ctx.time);
            }
            *o = p.get(0, j) * (std::f64::consts::TAU * ctx.time - j as f64).sin();
            data.set(0, j, *o);
        }
    }
}

export_module!(Panicky);

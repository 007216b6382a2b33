//! Throughput figures of the reference scenario (`proleg bench`, `cargo bench`): the
//! experiment-1 robot (snake5p) on the flat floor with the uniform 40° / 55° sine, 1 ms
//! steps, on either engine. Measures the engine's step alone, the full pipeline (sense,
//! kernel, servos, physics, clock; recording off: the configuration `optimize` uses, one
//! robot per world and per core), the pipeline recording every data handler at every step
//! into a data file, and batches of robots sharing one world; on MuJoCo also MuJoCo's own
//! `mujoco.rollout` on the exported scenario in the same run ([`rollout`]). Each figure is
//! the best of [`REPEATS`] fresh worlds after one simulated second of warm-up: the machines
//! here are shared VMs whose speed varies from run to run.
//! - [`compare`]: `proleg compare`, one configuration on both engines; [`compare_plot`]: its
//!   picture
//! - [`convergence`]: the accuracy gate, a configuration's distance from a converged reference
//! - [`error`]: why a benchmark, the gate or a comparison gave no figures
//! - [`modules`]: the overhead of one module type in the kernel (`--module NAME`)
//! - [`physics_checks`]: physical checks with known answers (`proleg check-physics`);
//!   [`terrain_checks`]: the same on terrain made of meshes and height fields
//! - [`rollout`]: MuJoCo's own `mujoco.rollout` on the exported scenario
//! - [`stages`]: each stage's share of a step (`--stages`)
//! - [`suite`]: every task of a suite's rate beside the flat floor's (`--suite`)

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

pub mod compare;
pub mod compare_plot;
pub mod convergence;
pub mod error;
pub mod modules;
pub mod physics_checks;
pub mod rollout;
pub mod stages;
pub mod suite;
pub mod terrain_checks;

use crate::config::Simulation;
use crate::config::simulation::EngineKind;
use crate::control::{ModuleRegistry, load_simulation};
use crate::data::store::DataStore;
use crate::sim::datalog::DataSettings;
use crate::sim::engine::EngineSettings;
use crate::sim::{BuildOptions, EngineChoice, Simulator};

pub use error::BenchError;

/// Repetitions of each figure; the fastest counts.
pub const REPEATS: usize = 3;

/// One measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// What was measured.
    pub label: String,
    /// Robots sharing the world.
    pub robots: usize,
    /// Steps run.
    pub steps: u64,
    /// Step width (s).
    pub dt: f64,
    /// Wall-clock seconds.
    pub wall: f64,
}

impl Figure {
    /// Robot-steps per wall second.
    pub fn robot_steps_per_s(&self) -> f64 {
        self.robots as f64 * self.steps as f64 / self.wall
    }

    /// Simulated seconds per wall second (each robot of a batch advances that fast).
    pub fn realtime_factor(&self) -> f64 {
        self.steps as f64 * self.dt / self.wall
    }
}

/// A world of `robots` copies of `sim`'s robot, modules made by `registry`, on the engine
/// and settings given (`None`: the simulation's engine, production settings).
pub(crate) fn world_of(
    sim: &Simulation,
    robots: usize,
    registry: &ModuleRegistry,
    settings: Option<EngineSettings>,
) -> Result<Simulator, BenchError> {
    Ok(Simulator::with_registry(
        sim,
        &BuildOptions {
            robots,
            seed: 1,
            record: false,
            engine: settings.map_or(EngineChoice::Production(sim.engine()), EngineChoice::Tuned),
            ..Default::default()
        },
        registry,
    )?)
}

/// Best of [`REPEATS`]: each repetition builds a fresh world of `sim` with `physics`, warms
/// up for one simulated second, then `measure` steps it for `seconds` and returns the wall
/// time.
fn best(
    sim: &Simulation,
    settings: EngineSettings,
    robots: usize,
    seconds: f64,
    label: &str,
    measure: impl Fn(&mut Simulator, u64) -> f64,
) -> Result<Figure, BenchError> {
    let mut fastest: Option<Figure> = None;
    for _ in 0..REPEATS {
        let mut s = world_of(sim, robots, &ModuleRegistry::standard(), Some(settings))?;
        let dt = s.clock().dt;
        s.run_steps((1.0 / dt).round() as u64);
        let steps = (seconds / dt).round() as u64;
        let wall = measure(&mut s, steps);
        if fastest.as_ref().is_none_or(|f| wall < f.wall) {
            fastest = Some(Figure {
                label: label.to_string(),
                robots,
                steps,
                dt,
                wall,
            });
        }
    }
    fastest.ok_or(BenchError::NoRepetition)
}

/// The full pipeline with `robots` robots in one world.
pub fn pipeline(
    sim: &Simulation,
    settings: EngineSettings,
    robots: usize,
    seconds: f64,
) -> Result<Figure, BenchError> {
    best(
        sim,
        settings,
        robots,
        seconds,
        &format!("pipeline, {robots} robot(s)/world"),
        |s, steps| {
            let t = Instant::now();
            s.run_steps(steps);
            t.elapsed().as_secs_f64()
        },
    )
}

/// The engine's step alone on the same world, the servo motors holding their last command: the
/// robot barely moves (its bodies may even sleep), so this is a floor for the physics cost,
/// not the same motion as the pipeline's rows.
pub fn physics_only(
    sim: &Simulation,
    settings: EngineSettings,
    seconds: f64,
) -> Result<Figure, BenchError> {
    best(
        sim,
        settings,
        1,
        seconds,
        &format!("{} step, motors held, 1 robot", sim.engine()),
        |s, steps| {
            let t = Instant::now();
            s.step_engine_only(steps);
            t.elapsed().as_secs_f64()
        },
    )
}

/// The full pipeline, one robot, recording every data handler at every step into a data
/// file (the background writer included: the time runs until the file is closed).
/// Returns the figure and the file size in bytes.
pub fn recording(
    sim: &Simulation,
    settings: EngineSettings,
    seconds: f64,
) -> Result<(Figure, u64), BenchError> {
    let file = std::env::temp_dir().join(format!("proleg-bench-{}.data.xml", std::process::id()));
    let size = std::cell::Cell::new(0);
    let fig = best(
        sim,
        settings,
        1,
        seconds,
        "pipeline + data file, 1 robot",
        |s, steps| {
            let Ok(handlers) = s.data_handlers(0) else {
                return f64::INFINITY;
            };
            let t = Instant::now();
            let Ok(store) = DataStore::create(&file, handlers) else {
                return f64::INFINITY;
            };
            s.enable_data(DataSettings::default(), Some(store));
            s.run_steps(steps);
            if s.finish_data().is_err() {
                return f64::INFINITY;
            }
            let wall = t.elapsed().as_secs_f64();
            size.set(std::fs::metadata(&file).map(|m| m.len()).unwrap_or(0));
            wall
        },
    )?;
    let _ = std::fs::remove_file(&file);
    if !fig.wall.is_finite() {
        return Err(BenchError::Recording { file });
    }
    Ok((fig, size.get()))
}

/// Every figure, formatted for the terminal; `overrides` change the robot's production
/// physics settings (rapier's `key=value,...`, see [`EngineSettings::of`]).
pub fn report(
    config: &Path,
    seconds: f64,
    batches: &[usize],
    overrides: &str,
    engine: Option<EngineKind>,
) -> Result<String, BenchError> {
    let sim = load_simulation(config)?.with_engine(engine);
    let settings = EngineSettings::of(&sim, overrides)?;
    let raw = physics_only(&sim, settings, seconds)?;
    let (rec, size) = recording(&sim, settings, seconds)?;
    let mut figs = vec![pipeline(&sim, settings, 1, seconds)?, rec.clone()];
    let most = crate::sim::engine::max_robots(sim.engine());
    for b in batches.iter().filter(|b| **b > 1) {
        figs.push(pipeline(&sim, settings, (*b).min(most), seconds)?);
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "reference scenario: {}, {seconds} s simulated per figure (best of {REPEATS}), 1 core",
        config.display()
    );
    let engine_settings = world_of(&sim, 1, &ModuleRegistry::standard(), Some(settings))?
        .engine()
        .settings();
    let _ = writeln!(out, "physics: {engine_settings}");
    let _ = writeln!(
        out,
        "{:<34} {:>16} {:>12} {:>16}",
        "",
        "robot-steps/s",
        "real-time",
        format!("vs {} only", sim.engine())
    );
    let raw_rate = raw.robot_steps_per_s();
    for f in std::iter::once(&raw).chain(&figs) {
        let rate = f.robot_steps_per_s();
        let _ = writeln!(
            out,
            "{:<34} {:>16.0} {:>11.1}x {:>15.2}x",
            f.label,
            rate,
            f.realtime_factor(),
            rate / raw_rate
        );
    }
    let _ = writeln!(
        out,
        "recording every handler at every step: {:.1}% slower than the pipeline alone; {:.1} MB per simulated minute",
        (rec.wall / figs[0].wall - 1.0) * 100.0,
        size as f64 / 1e6 * 60.0 / seconds
    );
    if sim.engine() == EngineKind::Mujoco {
        let _ = writeln!(out, "{}", rollout::compare(&sim, seconds));
    }
    let batched = figs[2..]
        .iter()
        .map(Figure::robot_steps_per_s)
        .fold(0.0, f64::max);
    let _ = writeln!(
        out,
        "against the throughput targets (set for the demo; experiment 2's is real time): one robot {:.0}% of {TARGET_ONE_ROBOT:.0} robot-steps/s, batched {:.0}% of {TARGET_BATCHED:.0}, real time {:.1}x against {TARGET_EXPERIMENT2_REALTIME:.0}x",
        100.0 * figs[0].robot_steps_per_s() / TARGET_ONE_ROBOT,
        100.0 * batched / TARGET_BATCHED,
        figs[0].realtime_factor()
    );
    Ok(out)
}

/// The throughput target for one robot on the reference scenario (robot-steps/s, one
/// core), set for the demo when the pipeline was tuned.
pub const TARGET_ONE_ROBOT: f64 = 130_000.0;
/// ... for robots sharing a world.
pub const TARGET_BATCHED: f64 = 160_000.0;
/// ... and experiment 2's real-time factor.
pub const TARGET_EXPERIMENT2_REALTIME: f64 = 40.0;

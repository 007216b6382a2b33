//! `proleg bench --stages`: each stage's share of the step on the reference scenario, per
//! engine (rapier, and MuJoCo where its library is), from [`StageTimerPlugin`]'s stamps
//! around every stage. The stamps cost ~8 clock reads per step, so the absolute step time
//! printed is a little above `proleg bench`'s; the shares are what this measures.

use std::fmt;
use std::path::Path;

use bevy::app::PluginGroup;

use crate::config::simulation::EngineKind;
use crate::control::{ModuleRegistry, load_simulation_in};
use crate::sim::{BuildOptions, SimError, SimPlugins, SimSystems, Simulator, StageTimerPlugin};

/// Why the stage figures could not be made.
#[derive(Debug, thiserror::Error)]
pub enum StagesError {
    /// The scenario does not load.
    #[error("{0}")]
    Config(#[from] crate::config::ConfigError),
    /// Its world cannot be built on an engine.
    #[error("{engine}: {source}")]
    Sim {
        /// The engine.
        engine: EngineKind,
        /// Why.
        source: SimError,
    },
}

/// The stage shares of one engine.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineStages {
    /// The engine.
    pub engine: EngineKind,
    /// Steps timed.
    pub steps: u64,
    /// Seconds per stage over those steps, in [`SimSystems::ALL`]'s order.
    pub seconds: [f64; SimSystems::ALL.len()],
}

impl EngineStages {
    /// Microseconds per step, all stages.
    pub fn step_us(&self) -> f64 {
        self.seconds.iter().sum::<f64>() / self.steps.max(1) as f64 * 1e6
    }
}

/// Every engine's stage shares.
#[derive(Debug, Clone, PartialEq)]
pub struct StagesReport {
    /// The scenario.
    pub config: String,
    /// Simulated seconds timed per engine (after one second of warm-up).
    pub seconds: f64,
    /// One row per engine measured.
    pub engines: Vec<EngineStages>,
}

/// Times the stages of `config` for `seconds` (after one simulated second of warm-up) on
/// rapier, and on MuJoCo when its library is present.
pub fn report(
    config: &Path,
    seconds: f64,
    registry: &ModuleRegistry,
) -> Result<StagesReport, StagesError> {
    let sim = load_simulation_in(config, registry)?;
    let mut engines = Vec::new();
    for engine in crate::sim::engine::ready_engines() {
        engines.push(time_stages(&sim, engine, seconds, registry)?);
    }
    Ok(StagesReport {
        config: config.display().to_string(),
        seconds,
        engines,
    })
}

fn time_stages(
    sim: &crate::config::Simulation,
    engine: EngineKind,
    seconds: f64,
    registry: &ModuleRegistry,
) -> Result<EngineStages, StagesError> {
    let opts = BuildOptions {
        record: false,
        engine: engine.into(),
        ..Default::default()
    };
    let stages = SimPlugins.build().add(StageTimerPlugin);
    let mut s = Simulator::with_stages(sim, &opts, registry, stages)
        .map_err(|source| StagesError::Sim { engine, source })?;
    let dt = sim.files.simulation.properties.step_width;
    s.run_steps((1.0 / dt).round() as u64);
    let before = s.stage_times().cloned().unwrap_or_default();
    s.run_steps((seconds / dt).round().max(1.0) as u64);
    let after = s.stage_times().cloned().unwrap_or_default();
    let mut spent = after.seconds;
    for (t, b) in spent.iter_mut().zip(before.seconds) {
        *t -= b;
    }
    Ok(EngineStages {
        engine,
        steps: after.steps - before.steps,
        seconds: spent,
    })
}

impl fmt::Display for StagesReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "stage shares of one step: {}, {} s simulated per engine, 1 core",
            self.config, self.seconds
        )?;
        write!(f, "{:<10}", "stage")?;
        for e in &self.engines {
            write!(f, " {:>19}", e.engine.to_string())?;
        }
        writeln!(f)?;
        for (k, stage) in SimSystems::ALL.iter().enumerate() {
            write!(f, "{:<10}", stage.name())?;
            for e in &self.engines {
                let total: f64 = e.seconds.iter().sum::<f64>().max(1e-12);
                let share = e.seconds[k] / total * 100.0;
                let us = e.seconds[k] / e.steps.max(1) as f64 * 1e6;
                write!(f, " {share:>6.1} % {us:>6.2} us")?;
            }
            writeln!(f)?;
        }
        write!(f, "{:<10}", "step")?;
        for e in &self.engines {
            write!(f, " {:>6} % {:>6.2} us", "100.0", e.step_us())?;
        }
        writeln!(f)
    }
}

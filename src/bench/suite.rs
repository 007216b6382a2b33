//! `proleg bench --suite SUITE`: how fast every task of a suite runs — simulated seconds
//! per wall second on one core, the robot of the bench's simulation on the task's first
//! test course — on each engine, beside the flat floor's rate: what a suite run and
//! training on it cost, course by course.

use std::fmt;
use std::path::Path;

use crate::bench::{BenchError, pipeline};
use crate::config::simulation::EngineKind;
use crate::control::ModuleRegistry;
use crate::sim::engine::EngineSettings;

/// The rate the suite's tasks must keep (simulated seconds per wall second, one core).
pub const TARGET_RATE: f64 = 25.0;

/// One task's rate on one engine.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskRate {
    /// The task.
    pub task: String,
    /// The engine.
    pub engine: EngineKind,
    /// Simulated seconds per wall second.
    pub rate: f64,
    /// The flat floor's rate on the same engine, measured just before the task's.
    pub flat: f64,
}

/// Every task's rates.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteRates {
    /// The suite's name.
    pub suite: String,
    /// One row per task and engine.
    pub rows: Vec<TaskRate>,
}

/// Measures every task of the suite at `suite` on every engine here, `seconds` each (best
/// of the bench's repetitions), each beside a measurement of the flat floor taken just
/// before it.
pub fn rates(
    config: &Path,
    suite: &Path,
    seconds: f64,
    registry: &ModuleRegistry,
) -> Result<SuiteRates, BenchError> {
    let sim = crate::control::load_simulation_in(config, registry)?;
    let file = crate::config::suite::load_suite(&crate::config::FsSource, suite)?;
    let mut rows = Vec::new();
    for engine in crate::sim::engine::ready_engines() {
        for task in &file.tasks {
            // The flat floor again beside each task: a machine whose speed drifts over the
            // minutes of a run (these VMs: up to 40 %) moves both figures alike.
            let flat = pipeline(&sim, EngineSettings::production(&sim, engine), 1, seconds)?;
            let seed = task.test.first().copied().unwrap_or(1);
            let world = sim
                .on_course(task, seed, suite)
                .map_err(|e| BenchError::Suite(Box::new(e.into())))?;
            let settings = EngineSettings::production(&world, engine);
            let f = pipeline(&world, settings, 1, seconds)?;
            rows.push(TaskRate {
                task: task.name.clone(),
                engine,
                rate: f.realtime_factor(),
                flat: flat.realtime_factor(),
            });
        }
    }
    Ok(SuiteRates {
        suite: file.name,
        rows,
    })
}

impl fmt::Display for SuiteRates {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "suite {}: simulated s per wall s on one core (target >= {TARGET_RATE}x)",
            self.suite
        )?;
        writeln!(
            f,
            "{:<16} {:<7} {:>9} {:>9} {:>8}",
            "task", "engine", "rate", "flat", "vs flat"
        )?;
        for r in &self.rows {
            writeln!(
                f,
                "{:<16} {:<7} {:>8.1}x {:>8.1}x {:>7.2}{}",
                r.task,
                r.engine.name(),
                r.rate,
                r.flat,
                r.rate / r.flat,
                if r.rate < TARGET_RATE {
                    "  below target"
                } else {
                    ""
                }
            )?;
        }
        let slowest = self
            .rows
            .iter()
            .map(|r| r.rate)
            .fold(f64::INFINITY, f64::min);
        writeln!(f, "slowest task: {slowest:.1}x")
    }
}

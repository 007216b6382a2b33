//! `proleg compare`: a simulation run on each engine and measured the same way
//! ([`crate::bench::compare`]), printed side by side, with a PNG of the paths and joints.

use std::fmt;
use std::path::PathBuf;

use crate::bench::compare::{CompareError, Comparison, compare};
use crate::bench::compare_plot::plot_comparison;
use crate::config::error::ConfigError;
use crate::config::simulation::EngineKind;
use crate::control::{ModuleRegistry, load_simulation_in};

/// Command-line options of `proleg compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// A `*.simulation.xml` file.
    pub config: PathBuf,
    /// The engines, comma-separated (default: rapier,mujoco).
    #[arg(long, value_delimiter = ',', default_value = "rapier,mujoco")]
    pub engines: Vec<EngineKind>,
    /// Simulated seconds on each engine (default: the file's duration).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Draw both centre-of-mass paths (top view) and the joint angles into this PNG.
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// Why `proleg compare` failed.
#[derive(Debug, thiserror::Error)]
pub enum CompareCommandError {
    /// The configuration does not load.
    #[error("{0}")]
    Config(#[from] ConfigError),
    /// The runs or the plot failed.
    #[error("{0}")]
    Compare(#[from] CompareError),
}

/// What `proleg compare` measured, and the PNG it wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareReport {
    /// The runs, measured.
    pub comparison: Comparison,
    /// The PNG written, if asked for.
    pub plot: Option<PathBuf>,
}

/// Runs the comparison the options ask for.
pub fn run(
    a: &CompareArgs,
    registry: &ModuleRegistry,
) -> Result<CompareReport, CompareCommandError> {
    let sim = load_simulation_in(&a.config, registry)?;
    let duration = a
        .duration
        .unwrap_or(sim.files.simulation.properties.duration);
    let comparison = compare(&sim, &a.engines, duration, registry)?;
    if let Some(png) = &a.plot {
        plot_comparison(&comparison, png, (1400, 600))?;
    }
    Ok(CompareReport {
        comparison,
        plot: a.plot.clone(),
    })
}

impl fmt::Display for CompareReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(out, "{}", self.comparison)?;
        if let Some(p) = &self.plot {
            writeln!(out, "paths and joint angles drawn into {}", p.display())?;
        }
        Ok(())
    }
}

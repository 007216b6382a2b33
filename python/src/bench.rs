//! What `python -m proleg.bench` needs of the library: `proleg bench`'s one-core pipeline
//! figure for a simulation file, and the MJCF `proleg export mjcf` writes (the plain
//! Gymnasium environment it is compared with).

use std::path::PathBuf;

use proleg::bench::pipeline;
use proleg::control::load_simulation_in;
use proleg::interop::mjcf::export_mjcf;
use proleg::sim::engine::EngineSettings;
use pyo3::prelude::*;

use crate::errors::{config_error, other};
use crate::simulation::engine;

/// `proleg bench`'s pipeline figure: robot-steps per wall second of one robot in one
/// world on one core (best of three), `seconds` simulated each, on `engine`.
#[pyfunction]
#[pyo3(signature = (path, engine_name=None, seconds=10.0))]
pub fn pipeline_rate(
    py: Python<'_>,
    path: PathBuf,
    engine_name: Option<&str>,
    seconds: f64,
) -> PyResult<f64> {
    let kind = engine(engine_name)?;
    let sim = load_simulation_in(&path, crate::modules::registry(py)?)
        .map_err(|e| config_error(&e))?
        .with_engine(kind);
    let settings = EngineSettings::production(&sim, sim.engine());
    let fig = py
        .detach(|| pipeline(&sim, settings, 1, seconds))
        .map_err(other)?;
    Ok(fig.robot_steps_per_s())
}

/// Writes `path`'s simulation as MJCF to `out` (position servos, `proleg export mjcf`).
#[pyfunction]
pub fn export_mjcf_file(py: Python<'_>, path: PathBuf, out: PathBuf) -> PyResult<()> {
    let sim =
        load_simulation_in(&path, crate::modules::registry(py)?).map_err(|e| config_error(&e))?;
    export_mjcf(&sim, &out).map_err(other)?;
    Ok(())
}

//! What `python -m proleg.bench` needs of the library: `proleg bench`'s one-core pipeline
//! figure for a simulation file, and the MJCF `proleg export mjcf` writes (the plain
//! Gymnasium environment it is compared with).

use std::path::PathBuf;

use proleg::bench::pipeline;
use proleg::control::load_simulation_in;
use proleg::gym::course::{CourseCache, Courses};
use proleg::interop::mjcf::export_mjcf;
use proleg::sim::engine::EngineSettings;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{config_error, gym_error, other};
use crate::simulation::engine;

/// `proleg bench`'s pipeline figure: robot-steps per wall second of one robot in one
/// world on one core (best of three), `seconds` simulated each, on `engine`. With a
/// suite task's options (`terrain`, `difficulty`, `suite`, `terrain_seed`: the
/// environments' keywords), on the course the environments would meet first (the given
/// `terrain_seed`, else the one drawn for episode seed 0).
#[pyfunction]
#[pyo3(signature = (path, engine_name=None, seconds=10.0, **options))]
pub fn pipeline_rate(
    py: Python<'_>,
    path: PathBuf,
    engine_name: Option<&str>,
    seconds: f64,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<f64> {
    let kind = engine(engine_name)?;
    let (opts, _) = crate::options::read(options, false)?;
    let sim = load_simulation_in(&path, crate::modules::registry(py)?)
        .map_err(|e| config_error(&e))?
        .with_engine(kind);
    let sim = match opts.course().map_err(gym_error)? {
        None => sim,
        Some(course) => {
            let courses = Courses::new(&course, CourseCache::default()).map_err(gym_error)?;
            let on_course = py.detach(|| courses.world(&sim, courses.pick(0)));
            on_course.map_err(gym_error)?.as_ref().clone()
        }
    };
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

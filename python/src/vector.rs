//! `VecEnv`: N environments stepped inside Rust on a thread pool with the interpreter
//! detached (`proleg::gym::VecEnv`); the Gymnasium `VectorEnv` and the Stable-Baselines3
//! adapter of the Python part wrap it.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use proleg::gym::{Autoreset, Lane};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::gym_error;
use crate::simulation::{exit_name, load_file};

/// N environments of one simulation file, stepped on `threads` threads.
#[pyclass(module = "proleg._native")]
pub struct VecEnv {
    envs: Option<proleg::gym::VecEnv>,
}

impl VecEnv {
    fn envs(&mut self) -> PyResult<&mut proleg::gym::VecEnv> {
        self.envs
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("the vector environment is closed"))
    }

    fn envs_ref(&self) -> PyResult<&proleg::gym::VecEnv> {
        self.envs
            .as_ref()
            .ok_or_else(|| PyRuntimeError::new_err("the vector environment is closed"))
    }

    /// The observations as an (n, obs_len) array (a copy).
    fn observations<'py>(
        py: Python<'py>,
        v: &proleg::gym::VecEnv,
        fin: bool,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let data = if fin {
            v.final_observations()
        } else {
            v.observations()
        };
        PyArray1::from_slice(py, data).reshape([v.lanes().len(), v.obs_len()])
    }
}

/// A lane field as an array.
fn column<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    lanes: &[Lane],
    pick: impl Fn(&Lane) -> T,
) -> Bound<'py, PyArray1<T>> {
    PyArray1::from_iter(py, lanes.iter().map(pick))
}

#[pymethods]
impl VecEnv {
    /// `num_envs` environments over the simulation file `path`; the keyword options are
    /// `proleg.ENV_OPTIONS`' (the library's, with their defaults, `threads` and
    /// `autoreset` among them).
    #[new]
    #[pyo3(signature = (path, num_envs, **options))]
    fn new(
        py: Python<'_>,
        path: PathBuf,
        num_envs: usize,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<VecEnv> {
        let (opts, vec) = crate::options::read(options, true)?;
        let registry = crate::modules::registry(py)?;
        let envs = py
            .detach(|| {
                proleg::gym::VecEnv::new(
                    load_file(&path, registry)?,
                    registry,
                    &opts,
                    num_envs,
                    vec,
                )
            })
            .map_err(gym_error)?;
        Ok(VecEnv { envs: Some(envs) })
    }

    /// Environments.
    #[getter]
    fn num_envs(&self) -> PyResult<usize> {
        Ok(self.envs_ref()?.lanes().len())
    }

    /// When a finished episode restarts: `next_step`, `same_step` or `disabled`.
    #[getter]
    fn autoreset(&self) -> PyResult<&'static str> {
        Ok(self.envs_ref()?.autoreset().name())
    }

    /// Threads of the pool.
    #[getter]
    fn threads(&self) -> PyResult<usize> {
        Ok(self.envs_ref()?.threads())
    }

    /// Values per action of one environment.
    #[getter]
    fn action_len(&self) -> PyResult<usize> {
        Ok(self.envs_ref()?.action_len())
    }

    /// Values per observation of one environment.
    #[getter]
    fn obs_len(&self) -> PyResult<usize> {
        Ok(self.envs_ref()?.obs_len())
    }

    /// The name of every observation index.
    #[getter]
    fn observation_names(&self) -> PyResult<Vec<String>> {
        Ok(self.envs_ref()?.envs()[0].layout().names())
    }

    /// Environment steps per episode.
    #[getter]
    fn max_steps(&self) -> PyResult<u64> {
        Ok(self.envs_ref()?.envs()[0].max_steps())
    }

    /// Physics steps per environment step.
    #[getter]
    fn steps_per_action(&self) -> PyResult<u64> {
        Ok(self.envs_ref()?.envs()[0].steps_per_action())
    }

    /// Seconds per environment step.
    #[getter]
    fn control_period(&self) -> PyResult<f64> {
        Ok(self.envs_ref()?.envs()[0].options().control_period)
    }

    /// Resets the environments `mask` selects (all by default), environment i with
    /// `seed + i`; returns the observations (n, obs_len) and the info arrays.
    #[pyo3(signature = (seed=None, mask=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
        mask: Option<PyReadonlyArray1<'py, bool>>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyDict>)> {
        let mask = mask.as_ref().map(|m| m.as_slice()).transpose()?;
        let envs = self.envs()?;
        py.detach(|| envs.reset(seed, mask)).map_err(gym_error)?;
        let obs = VecEnv::observations(py, envs, false)?;
        Ok((obs, infos(py, envs)?))
    }

    /// One step of every environment with its row of `actions` (n, action_len); returns
    /// observations, rewards, terminated, truncated and the info arrays.
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<(
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyDict>,
    )> {
        let actions = actions.as_slice()?;
        let envs = self.envs()?;
        py.detach(|| envs.step(actions)).map_err(gym_error)?;
        let lanes = envs.lanes();
        Ok((
            VecEnv::observations(py, envs, false)?,
            column(py, lanes, |l| l.reward),
            column(py, lanes, |l| l.terminated),
            column(py, lanes, |l| l.truncated),
            infos(py, envs)?,
        ))
    }

    /// Frees the worlds and the pool; closing twice is fine.
    fn close(&mut self) {
        self.envs = None;
    }
}

/// The info arrays: `time`, `score`, `energy`, `exit`, `reset`; with same-step autoreset
/// `final_obs` and its mask `_final_obs`; on a suite task `terrain_seed`, its mask and
/// `running_terrain_seed`.
fn infos<'py>(py: Python<'py>, envs: &proleg::gym::VecEnv) -> PyResult<Bound<'py, PyDict>> {
    let lanes = envs.lanes();
    let d = PyDict::new(py);
    d.set_item("time", column(py, lanes, |l| l.info.time))?;
    d.set_item("score", column(py, lanes, |l| l.info.score))?;
    d.set_item("energy", column(py, lanes, |l| l.info.energy))?;
    let exits: Vec<&str> = lanes.iter().map(|l| exit_name(&l.info)).collect();
    d.set_item("exit", exits)?;
    d.set_item("reset", column(py, lanes, |l| l.reset))?;
    if envs.autoreset() == Autoreset::SameStep {
        d.set_item("final_obs", VecEnv::observations(py, envs, true)?)?;
        d.set_item("_final_obs", column(py, lanes, |l| l.has_final))?;
    }
    if lanes.iter().any(|l| l.info.terrain_seed.is_some()) {
        // The episode's course (the ended one's, when it ended this step) and the running
        // one's (a same-step reset's new course).
        d.set_item(
            "terrain_seed",
            column(py, lanes, |l| l.info.terrain_seed.unwrap_or(0)),
        )?;
        d.set_item(
            "_terrain_seed",
            column(py, lanes, |l| l.info.terrain_seed.is_some()),
        )?;
        let running = envs.envs().iter().map(|e| e.terrain_seed().unwrap_or(0));
        d.set_item("running_terrain_seed", PyArray1::from_iter(py, running))?;
    }
    Ok(d)
}

//! `proleg.load` and its `Simulation` (a world to step and read), and the single
//! environment `Env` the Gymnasium class wraps.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{PyArray1, PyReadonlyArray1};
use proleg::config::simulation::EngineKind;
use proleg::control::{ModuleRegistry, load_simulation_in};
use proleg::gym::{GymError, StepInfo, Transition};
use proleg::sim::{BuildOptions, RunSummary, SimError, Simulator};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{config_error, gym_error, sim_error};

/// Reads an engine's name (`None`: the file's).
pub fn engine(name: Option<&str>) -> PyResult<Option<EngineKind>> {
    name.map(|n| {
        EngineKind::parse(n).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown engine \"{n}\": give \"rapier\" or \"mujoco\""
            ))
        })
    })
    .transpose()
}

/// Loads a simulation file with `registry`'s module types (the process's: standard and
/// plugins, [`crate::modules::registry`]).
pub fn load_file(
    path: &PathBuf,
    registry: &ModuleRegistry,
) -> Result<Arc<proleg::config::Simulation>, GymError> {
    Ok(Arc::new(load_simulation_in(path, registry)?))
}

/// Loads a simulation file (its includes resolved as `proleg run` resolves them) and
/// builds its world on `engine` ("rapier" or "mujoco"; default: the file's), seeded with
/// `seed` (default: the file's).
#[pyfunction]
#[pyo3(signature = (path, engine=None, seed=None))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    engine: Option<&str>,
    seed: Option<u64>,
) -> PyResult<Simulation> {
    let kind = self::engine(engine)?;
    let registry = crate::modules::registry(py)?;
    let sim = py
        .detach(|| load_simulation_in(&path, registry))
        .map_err(|e| config_error(&e))?;
    let sim = Arc::new(sim.with_engine(kind));
    let world = py
        .detach(|| Simulation::build(&sim, seed, registry))
        .map_err(sim_error)?;
    Ok(Simulation {
        sim,
        world: Some(world),
    })
}

/// A loaded simulation's world: step it, read its state, change its modules.
#[pyclass(module = "proleg._native")]
pub struct Simulation {
    sim: Arc<proleg::config::Simulation>,
    world: Option<Simulator>,
}

impl Simulation {
    /// The world of `sim` seeded with `seed` (default: the file's), its modules made from
    /// `registry`'s types (plugins too).
    fn build(
        sim: &proleg::config::Simulation,
        seed: Option<u64>,
        registry: &ModuleRegistry,
    ) -> Result<Simulator, SimError> {
        let seed = seed.unwrap_or(sim.files.simulation.properties.seed);
        let opts = BuildOptions {
            seed,
            ..Default::default()
        };
        Simulator::with_registry(sim, &opts, registry)
    }

    fn world(&self) -> PyResult<&Simulator> {
        self.world
            .as_ref()
            .ok_or_else(|| PyRuntimeError::new_err("the simulation is closed"))
    }

    fn world_mut(&mut self) -> PyResult<&mut Simulator> {
        self.world
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("the simulation is closed"))
    }
}

/// A run's summary as a dict.
fn summary<'py>(py: Python<'py>, s: &RunSummary) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("steps", s.steps)?;
    d.set_item("sim_time", s.sim_time)?;
    d.set_item("wall_time", s.wall_time)?;
    d.set_item("realtime_factor", s.realtime_factor)?;
    d.set_item("start_com", s.start_com.to_vec())?;
    d.set_item("end_com", s.end_com.to_vec())?;
    d.set_item("displacement", s.displacement)?;
    d.set_item("mean_speed", s.mean_speed)?;
    Ok(d)
}

#[pymethods]
impl Simulation {
    /// The simulation file.
    #[getter]
    fn file(&self) -> String {
        self.sim.file.display().to_string()
    }

    /// The engine stepping the world ("rapier" or "mujoco").
    #[getter]
    fn engine(&self) -> PyResult<&'static str> {
        Ok(self.world()?.engine_kind().name())
    }

    /// The step width (s).
    #[getter]
    fn dt(&self) -> PyResult<f64> {
        Ok(self.world()?.clock().dt)
    }

    /// Simulated seconds so far.
    #[getter]
    fn time(&self) -> PyResult<f64> {
        Ok(self.world()?.clock().time())
    }

    /// Steps so far.
    #[getter]
    fn step_count(&self) -> PyResult<u64> {
        Ok(self.world()?.clock().step)
    }

    /// The file's duration (s).
    #[getter]
    fn duration(&self) -> f64 {
        self.sim.files.simulation.properties.duration
    }

    /// Runs `n` steps.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let world = self.world_mut()?;
        py.detach(|| world.run_steps(n));
        Ok(())
    }

    /// Runs for `seconds` (default: the file's duration) and returns the run's summary
    /// (steps, times, real-time factor, centre of mass at start and end, displacement).
    #[pyo3(signature = (seconds=None))]
    fn run<'py>(&mut self, py: Python<'py>, seconds: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        let seconds = seconds.unwrap_or(self.duration());
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(PyValueError::new_err(format!(
                "seconds = {seconds}: give zero or a positive number"
            )));
        }
        let world = self.world_mut()?;
        let s = py.detach(|| world.run_for(seconds));
        summary(py, &s)
    }

    /// Builds the world anew with `seed` (default: the file's).
    #[pyo3(signature = (seed=None))]
    fn reset(&mut self, py: Python<'_>, seed: Option<u64>) -> PyResult<()> {
        let (sim, registry) = (&self.sim, crate::modules::registry(py)?);
        let fresh = py
            .detach(|| Simulation::build(sim, seed, registry))
            .map_err(sim_error)?;
        self.world = Some(fresh);
        Ok(())
    }

    /// Joint angles of robot `robot` (degrees).
    #[pyo3(signature = (robot=0))]
    fn joint_angles<'py>(
        &self,
        py: Python<'py>,
        robot: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.joint_field(py, robot, |j| j.angle)
    }

    /// Joint speeds of robot `robot` (degrees per second).
    #[pyo3(signature = (robot=0))]
    fn joint_speeds<'py>(
        &self,
        py: Python<'py>,
        robot: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.joint_field(py, robot, |j| j.velocity)
    }

    /// Torques the servos applied in the last step (N·m).
    #[pyo3(signature = (robot=0))]
    fn joint_torques<'py>(
        &self,
        py: Python<'py>,
        robot: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.joint_field(py, robot, |j| j.torque)
    }

    /// The servo targets the last step drove (degrees).
    #[pyo3(signature = (robot=0))]
    fn joint_targets<'py>(
        &self,
        py: Python<'py>,
        robot: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let t = self.world()?.servo_targets(robot).map_err(sim_error)?;
        Ok(PyArray1::from_vec(py, t))
    }

    /// Each tactile pad, debounced (True: pressed).
    #[pyo3(signature = (robot=0))]
    fn pads<'py>(&self, py: Python<'py>, robot: usize) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let s = self.world()?.sensors(robot).map_err(sim_error)?;
        Ok(PyArray1::from_slice(py, &s.tactile))
    }

    /// Each laser's ranges (m), one array per laser.
    #[pyo3(signature = (robot=0))]
    fn laser<'py>(
        &self,
        py: Python<'py>,
        robot: usize,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        let s = self.world()?.sensors(robot).map_err(sim_error)?;
        Ok(s.laser
            .iter()
            .map(|l| PyArray1::from_slice(py, l))
            .collect())
    }

    /// Centre of mass (m, z up).
    #[pyo3(signature = (robot=0))]
    fn com<'py>(&self, py: Python<'py>, robot: usize) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let c = self.world()?.com(robot).map_err(sim_error)?;
        Ok(PyArray1::from_slice(py, &c))
    }

    /// Tail-to-head heading in the ground plane (degrees from +x).
    #[pyo3(signature = (robot=0))]
    fn heading(&self, robot: usize) -> PyResult<f64> {
        self.world()?.heading(robot).map_err(sim_error)
    }

    /// Joules the servos put out so far.
    #[pyo3(signature = (robot=0))]
    fn energy(&self, robot: usize) -> PyResult<f64> {
        Ok(self.world()?.energy(robot).map_err(sim_error)?.joules)
    }

    /// The robot's modules: (type name, driven joints) per actuator, in file order.
    #[pyo3(signature = (robot=0))]
    fn modules(&self, robot: usize) -> PyResult<Vec<(String, Vec<usize>)>> {
        let k = self.world()?.kernel(robot).map_err(sim_error)?;
        Ok(k.actuators()
            .iter()
            .map(|a| {
                (
                    a.module.descriptor().type_name.to_string(),
                    a.joints.clone(),
                )
            })
            .collect())
    }

    /// Parameter `name` of actuator `actuator` at robot joint `joint` (its first joint by
    /// default).
    #[pyo3(signature = (actuator, name, joint=None, robot=0))]
    fn parameter(
        &self,
        actuator: usize,
        name: &str,
        joint: Option<usize>,
        robot: usize,
    ) -> PyResult<f64> {
        let k = self.world()?.kernel(robot).map_err(sim_error)?;
        k.parameter(actuator, name, joint)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Sets parameter `name` of actuator `actuator` at robot joint `joint` (every joint it
    /// drives by default), from the next step on; refused (ValueError) out of its range or
    /// not a number.
    #[pyo3(signature = (actuator, name, value, joint=None, robot=0))]
    fn set_parameter(
        &mut self,
        actuator: usize,
        name: &str,
        value: f64,
        joint: Option<usize>,
        robot: usize,
    ) -> PyResult<()> {
        self.world_mut()?
            .set_parameter(robot, actuator, name, joint, value)
            .map_err(sim_error)
    }

    /// Makes the servos follow `angles` (degrees, one per joint) instead of the modules;
    /// `None` gives the joints back to the modules.
    #[pyo3(signature = (angles, robot=0))]
    fn set_joint_targets(
        &mut self,
        angles: Option<PyReadonlyArray1<'_, f64>>,
        robot: usize,
    ) -> PyResult<()> {
        let world = self.world_mut()?;
        let joints = world.kernel(robot).map_err(sim_error)?.joints();
        let angles = match angles {
            None => None,
            Some(a) => {
                let v = a.as_slice()?.to_vec();
                if v.len() != joints {
                    return Err(PyValueError::new_err(format!(
                        "angles has {} values, expected {joints}",
                        v.len()
                    )));
                }
                if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                    return Err(PyValueError::new_err(format!(
                        "angles[{i}] is {x}: angles must be finite numbers"
                    )));
                }
                Some(v)
            }
        };
        world.set_joint_override(robot, angles).map_err(sim_error)
    }

    /// Frees the world; any later call raises RuntimeError.
    fn close(&mut self) {
        self.world = None;
    }

    fn __repr__(&self) -> String {
        format!("<proleg.Simulation {}>", self.sim.file.display())
    }
}

impl Simulation {
    fn joint_field<'py>(
        &self,
        py: Python<'py>,
        robot: usize,
        pick: impl Fn(&proleg::sim::servo::JointState) -> f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let states = self.world()?.joint_states(robot).map_err(sim_error)?;
        Ok(PyArray1::from_iter(py, states.iter().map(pick)))
    }
}

/// An episode's figures as a dict (`time`, `score`, `energy`, `exit`, and on a suite
/// task `terrain_seed`).
pub fn info_dict<'py>(py: Python<'py>, i: &StepInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("time", i.time)?;
    d.set_item("score", i.score)?;
    d.set_item("energy", i.energy)?;
    d.set_item("exit", exit_name(i))?;
    if let Some(seed) = i.terrain_seed {
        d.set_item("terrain_seed", seed)?;
    }
    Ok(d)
}

/// How the robot left the world ("" when it did not).
pub fn exit_name(i: &StepInfo) -> &'static str {
    match i.exit {
        None => "",
        Some(proleg::sim::WorldExit::Left(_)) => "left_world",
        Some(proleg::sim::WorldExit::Diverged) => "diverged",
    }
}

/// One environment over a simulation file (the Gymnasium class `proleg.ProlegEnv` wraps
/// it): actions and observations are float64 arrays.
#[pyclass(module = "proleg._native")]
pub struct Env {
    env: Option<proleg::gym::Env>,
    obs: Vec<f64>,
}

impl Env {
    /// The environment, for the renderer that draws its world.
    pub fn inner_mut(&mut self) -> PyResult<&mut proleg::gym::Env> {
        self.env()
    }

    fn env(&mut self) -> PyResult<&mut proleg::gym::Env> {
        self.env
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("the environment is closed"))
    }

    fn env_ref(&self) -> PyResult<&proleg::gym::Env> {
        self.env
            .as_ref()
            .ok_or_else(|| PyRuntimeError::new_err("the environment is closed"))
    }
}

#[pymethods]
impl Env {
    /// An environment over the simulation file `path`; the keyword options are
    /// `proleg.ENV_OPTIONS`' (the library's, with their defaults).
    #[new]
    #[pyo3(signature = (path, **options))]
    fn new(py: Python<'_>, path: PathBuf, options: Option<&Bound<'_, PyDict>>) -> PyResult<Env> {
        let (opts, _) = crate::options::read(options, false)?;
        let registry = crate::modules::registry(py)?;
        let env = py
            .detach(|| proleg::gym::Env::new(load_file(&path, registry)?, registry.clone(), opts))
            .map_err(gym_error)?;
        let obs = vec![0.0; env.layout().len()];
        Ok(Env {
            env: Some(env),
            obs,
        })
    }

    /// Values per action.
    #[getter]
    fn action_len(&self) -> PyResult<usize> {
        Ok(self.env_ref()?.action_len())
    }

    /// Values per observation.
    #[getter]
    fn obs_len(&self) -> PyResult<usize> {
        Ok(self.env_ref()?.layout().len())
    }

    /// The name of every observation index.
    #[getter]
    fn observation_names(&self) -> PyResult<Vec<String>> {
        Ok(self.env_ref()?.layout().names())
    }

    /// Seconds per environment step.
    #[getter]
    fn control_period(&self) -> PyResult<f64> {
        Ok(self.env_ref()?.options().control_period)
    }

    /// Environment steps per episode (then it is truncated).
    #[getter]
    fn max_steps(&self) -> PyResult<u64> {
        Ok(self.env_ref()?.max_steps())
    }

    /// Physics steps per environment step.
    #[getter]
    fn steps_per_action(&self) -> PyResult<u64> {
        Ok(self.env_ref()?.steps_per_action())
    }

    /// The engine ("rapier" or "mujoco").
    #[getter]
    fn engine(&self) -> PyResult<&'static str> {
        Ok(self.env_ref()?.world().engine_kind().name())
    }

    /// The simulation file.
    #[getter]
    fn file(&self) -> PyResult<String> {
        Ok(self.env_ref()?.simulation().file.display().to_string())
    }

    /// Starts an episode; returns its first observation and info.
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyDict>)> {
        let mut obs = std::mem::take(&mut self.obs);
        let env = self.env()?;
        let r = py.detach(|| env.reset(seed, &mut obs));
        self.obs = obs;
        let info = r.map_err(gym_error)?;
        Ok((PyArray1::from_slice(py, &self.obs), info_dict(py, &info)?))
    }

    /// One step with `action` (float64, one value in [-1, 1] per joint; clipped).
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        action: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        f64,
        bool,
        bool,
        Bound<'py, PyDict>,
    )> {
        let action = action.as_slice()?;
        let mut obs = std::mem::take(&mut self.obs);
        let env = self.env()?;
        let r: Result<Transition, GymError> = py.detach(|| env.step(action, &mut obs));
        self.obs = obs;
        let t = r.map_err(gym_error)?;
        Ok((
            PyArray1::from_slice(py, &self.obs),
            t.reward,
            t.terminated,
            t.truncated,
            info_dict(py, &t.info)?,
        ))
    }

    /// The running episode's frames so far (all of them once it ended) for the browser's
    /// 3D replay, titled `label` (else the file, episode and seed); the environment records
    /// them when made with `replay_fps`.
    #[pyo3(signature = (label=None))]
    fn replay(&self, py: Python<'_>, label: Option<&str>) -> PyResult<crate::replay::Replay> {
        let env = self.env_ref()?;
        py.detach(|| env.replay(label))
            .map(crate::replay::Replay::new)
            .map_err(gym_error)
    }

    /// Robot 0's centre of mass now (m).
    fn com<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let c = self.env_ref()?.world().com(0).map_err(sim_error)?;
        Ok(PyArray1::from_slice(py, &c))
    }

    /// Frees the world; closing twice is fine, any other later call raises RuntimeError.
    fn close(&mut self) {
        self.env = None;
    }
}

//! Loading a whole simulation: the simulation file and everything it includes, parsed,
//! cross-checked (masks against the robot, modules against the registry, optimizer
//! parameters against the actuation) and resolved into models the simulation uses.
//! - [`robot`], [`actuation`], [`environment`], [`optimizer`]: each file's resolved model
//! - [`flatten`]: a `<KinBody>` and its part files as one list of bodies, joints and sensors
//! - [`physical`]: a robot's physical validation (masses, inertias, limits)

pub mod actuation;
pub mod environment;
pub mod flatten;
pub mod optimizer;
pub mod physical;
pub mod robot;

use std::path::{Path, PathBuf};

use crate::config::actuation::{ActuationFile, parse_actuation_file};
use crate::config::courses::{self, CoursesSpec, TrainCourse, TrainCourses};
use crate::config::environment::{EnvironmentFile, parse_environment_file};
use crate::config::error::{ConfigError, ConfigResult, ErrorKind, Pos};
use crate::config::module_types::ModuleTypes;
use crate::config::optimizer::{OptimizerFile, parse_optimizer_file};
use crate::config::robot::{RobotFile, parse_robot_file};
use crate::config::simulation::{Mode, SimulationFile, parse_simulation_file};
use crate::config::source::{FileSource, normalize};
use crate::config::suite::{Task, parse_suite_file};

pub use actuation::{ActuationModel, ModuleInstance, ParamAssignment, WeightsFile};
pub use environment::{EnvBody, EnvironmentModel, course_environment};
pub use optimizer::{OptimizedParameter, OptimizerModel};
pub use robot::{
    JointOrientation, JointServo, Link, RobotJoint, RobotModel, RobotSensor, ServoMap,
};

/// The files of a simulation as written (what an editor changes and saves).
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationFiles {
    /// The simulation file.
    pub simulation: SimulationFile,
    /// The robot file.
    pub robot: RobotFile,
    /// The actuation file.
    pub actuation: ActuationFile,
    /// The environment file, if any.
    pub environment: Option<EnvironmentFile>,
    /// The optimizer file, if any.
    pub optimizer: Option<OptimizerFile>,
}

/// A fully loaded and checked simulation.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// The simulation file.
    pub file: PathBuf,
    /// The files as written.
    pub files: SimulationFiles,
    /// The robot, resolved.
    pub robot: RobotModel,
    /// The actuation, checked against the robot and the module types.
    pub actuation: ActuationModel,
    /// The environment, resolved.
    pub environment: EnvironmentModel,
    /// The optimizer settings, in an optimization mode.
    pub optimizer: Option<OptimizerModel>,
    /// Things that load but look unintended.
    pub warnings: Vec<String>,
}

impl Simulation {
    /// The parsed mesh of a resolved `trimesh` file name (robot or environment), read once
    /// when the simulation was loaded.
    pub fn mesh(&self, file: &str) -> Option<&std::sync::Arc<crate::config::mesh::TriMesh>> {
        self.robot
            .meshes
            .get(file)
            .or_else(|| self.environment.meshes.get(file))
    }

    /// The physics engine that steps this simulation (`<physicsEngine>`, rapier by default).
    pub fn engine(&self) -> crate::config::simulation::EngineKind {
        self.files.simulation.properties.engine
    }

    /// This simulation on `engine` instead of the one its file names (`--engine`); `None`
    /// keeps the file's.
    pub fn with_engine(mut self, engine: Option<crate::config::simulation::EngineKind>) -> Self {
        if let Some(e) = engine {
            self.files.simulation.properties.engine = e;
        }
        self
    }

    /// This controller on `task`'s course of terrain seed `seed`, for the task's duration:
    /// its robot, control and physics properties, started where its own environment
    /// starts the robot. `suite` is the suite file (what errors name).
    pub fn on_course(&self, task: &Task, seed: u64, suite: &Path) -> ConfigResult<Simulation> {
        let mut sim = self.clone();
        sim.environment = course_environment(task, &self.environment, seed, suite)?;
        sim.files.simulation.properties.duration = task.duration;
        Ok(sim)
    }
}

fn read_top(src: &dyn FileSource, path: &Path) -> ConfigResult<String> {
    src.read(path).map_err(|e| {
        ConfigError::new(
            path,
            Pos::new(0, 0),
            ErrorKind::MissingFile,
            format!("cannot read the simulation file: {e}"),
        )
        .caused_by(e)
    })
}

/// Reads, parses and resolves one included file.
fn include<T>(
    src: &dyn FileSource,
    from: &Path,
    written: &str,
    pos: Pos,
    what: &str,
    parse: fn(&str, &str) -> ConfigResult<T>,
) -> ConfigResult<(PathBuf, T)> {
    let path = flatten::find_file(src, from, written, pos, what)?;
    let text = flatten::read_file(src, &path, from, pos)?;
    let parsed =
        parse(&path.display().to_string(), &text).map_err(|e| e.included_from(from, pos))?;
    Ok((path, parsed))
}

/// Loads a simulation from any [`FileSource`], checking its modules against `registry`
/// (the module types this process knows: the standard library and loaded plugins).
pub fn load_simulation_with(
    src: &dyn FileSource,
    path: &Path,
    registry: &dyn ModuleTypes,
) -> ConfigResult<Simulation> {
    let path = normalize(path);
    let text = read_top(src, &path)?;
    let sim = parse_simulation_file(&path.display().to_string(), &text)?;

    let (robot_path, robot_file) = include(
        src,
        &path,
        &sim.robot.path,
        sim.robot.pos,
        "robot",
        parse_robot_file,
    )?;
    let robot = robot::resolve_robot(src, &robot_path, &robot_file)
        .map_err(|e| e.included_from(&path, sim.robot.pos))?;

    let (act_path, act_file) = include(
        src,
        &path,
        &sim.actuation.path,
        sim.actuation.pos,
        "actuation",
        parse_actuation_file,
    )?;
    let actuation = actuation::resolve_actuation(src, &act_path, &act_file, &robot, registry)
        .map_err(|e| e.included_from(&path, sim.actuation.pos))?;

    let (env_file, environment) = load_environment(src, &path, &sim)?;
    let (opt_file, optimizer) = load_optimizer(
        src,
        &path,
        &sim,
        (&robot, &actuation, &environment),
        registry,
    )?;

    let mut warnings = actuation.warnings.clone();
    if let (Some(opt), false) = (&opt_file, sim.properties.mode.is_optimization()) {
        warnings.push(format!(
            "{} settings are given but mode is \"{}\"",
            opt.label(),
            sim.properties.mode
        ));
    }
    for l in robot
        .links
        .iter()
        .filter(|l| l.mass_from_geometry && !l.fixed)
    {
        warnings.push(format!(
            "link {} gives no mass; {:.3} kg from its geometry at 1000 kg/m³",
            l.name, l.mass
        ));
    }
    Ok(Simulation {
        file: path,
        files: SimulationFiles {
            simulation: sim,
            robot: robot_file,
            actuation: act_file,
            environment: env_file,
            optimizer: opt_file,
        },
        robot,
        actuation,
        environment,
        optimizer,
        warnings,
    })
}

/// The simulation's environment file and its model (an empty world without one).
fn load_environment(
    src: &dyn FileSource,
    path: &Path,
    sim: &SimulationFile,
) -> ConfigResult<(Option<EnvironmentFile>, EnvironmentModel)> {
    let Some(e) = &sim.environment else {
        return Ok((None, EnvironmentModel::empty()));
    };
    let (env_path, env_file) = include(
        src,
        path,
        &e.path,
        e.pos,
        "environment",
        parse_environment_file,
    )?;
    let model = environment::resolve_environment(src, &env_path, &env_file)
        .map_err(|err| err.included_from(path, e.pos))?;
    Ok((Some(env_file), model))
}

/// The simulation's optimizer file and its model, checked against the mode, the robot,
/// the actuation and the module types.
fn load_optimizer(
    src: &dyn FileSource,
    path: &Path,
    sim: &SimulationFile,
    (robot, actuation, environment): (&RobotModel, &ActuationModel, &EnvironmentModel),
    registry: &dyn ModuleTypes,
) -> ConfigResult<(Option<OptimizerFile>, Option<OptimizerModel>)> {
    let Some(o) = &sim.optimizer else {
        return Ok((None, None));
    };
    let (opt_path, opt_file) =
        include(src, path, &o.path, o.pos, "optimizer", parse_optimizer_file)?;
    let expected = match sim.properties.mode {
        Mode::GeneticAlgorithm => Some("genetic algorithm"),
        Mode::GreatDeluge => Some("modified great deluge"),
        Mode::CmaEs => Some("CMA-ES"),
        Mode::MapElites => Some("MAP-Elites"),
        Mode::EvolutionStrategy => Some("OpenAI-ES"),
        _ => None,
    };
    if let Some(expected) = expected
        && expected != opt_file.label()
    {
        return Err(ConfigError::new(
            path,
            o.pos,
            ErrorKind::InvalidValue,
            format!(
                "mode \"{}\" needs {expected} settings, but {} holds {} settings",
                sim.properties.mode,
                opt_path.display(),
                opt_file.label()
            ),
        ));
    }
    let mut model = optimizer::resolve_optimizer(&opt_path, &opt_file, robot, actuation, registry)
        .map_err(|e| e.included_from(path, o.pos))?;
    if let Some(c) = &opt_file.courses {
        let courses = train_courses(src, &opt_path, c, &opt_file, environment)
            .map_err(|e| e.included_from(path, o.pos))?;
        model.courses = Some(courses);
    }
    Ok((Some(opt_file), Some(model)))
}

/// The courses `<courses>` of optimizer file `file` (at `opt_path`) trains on, generated
/// with `environment`'s physics and start pose.
fn train_courses(
    src: &dyn FileSource,
    opt_path: &Path,
    spec: &CoursesSpec,
    file: &OptimizerFile,
    environment: &EnvironmentModel,
) -> ConfigResult<TrainCourses> {
    let (suite_path, suite) = include(
        src,
        opt_path,
        &spec.suite,
        spec.pos,
        "suite",
        parse_suite_file,
    )?;
    let tasks = courses::train_tasks(opt_path, spec, &suite, &suite_path)?;
    let episodes = match (&file.robustness, spec.episodes) {
        (Some(r), _) => r.episodes as usize,
        (None, Some(k)) => k as usize,
        (None, None) => tasks.len(),
    };
    let list = (0..episodes)
        .map(|k| {
            let Some((task, seed)) = courses::pick(&tasks, k) else {
                return Err(ConfigError::new(
                    opt_path,
                    spec.pos,
                    ErrorKind::InvalidValue,
                    "no train course to pick",
                ));
            };
            Ok(TrainCourse {
                task: task.name.clone(),
                seed,
                environment: course_environment(task, environment, seed, &suite_path)?,
            })
        })
        .collect::<ConfigResult<Vec<_>>>()?;
    Ok(TrainCourses {
        suite: suite_path,
        courses: std::sync::Arc::new(list),
    })
}

//! The composing layer's errors: what the wizard, the expert dialog and the builders
//! refuse, typed, turned into text where a window or the command line shows it. The
//! environment editor's own errors are [`crate::compose::env_edit::EditError`].

use std::path::PathBuf;

/// Why a composition cannot be built, checked or written.
#[derive(Debug, thiserror::Error)]
pub enum ComposeError {
    /// A file the composition reads or writes does not load or check.
    #[error("{0}")]
    Config(#[from] crate::config::ConfigError),
    /// A file or folder operation failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A file that cannot be written with its folder.
    #[error("{0}")]
    Bundle(#[from] crate::config::bundle::BundleError),
    /// A simulation file's include that is not found.
    #[error("{}:{line}: cannot find {include}", file.display())]
    Include {
        /// The simulation file.
        file: PathBuf,
        /// The include's line.
        line: u32,
        /// The path it names.
        include: String,
    },
    /// A robot the builder cannot build (name, topology, joint count).
    #[error("{0}")]
    Build(#[from] crate::config::robot_builder::BuildError),
    /// A robot file that is not there.
    #[error("no robot file {}", .0.display())]
    NoRobotFile(PathBuf),
    /// A name that is none of the accepted ones (part set, mode, fitness).
    #[error("{0}")]
    Name(#[from] crate::config::error::UnknownName),
    /// A module type the registry does not offer.
    #[error("unknown module \"{name}\"; known: {known}")]
    UnknownModule {
        /// The name given.
        name: String,
        /// The registry's module types.
        known: String,
    },
    /// A parameter the module does not have.
    #[error("module {module} has no parameter \"{parameter}\"; its parameters: {known}")]
    UnknownParameter {
        /// The module type.
        module: String,
        /// The parameter given.
        parameter: String,
        /// Its parameters.
        known: String,
    },
    /// A joint mask that is not one 0 or 1 per joint.
    #[error("joint mask \"{mask}\": {why}")]
    Mask {
        /// The mask.
        mask: String,
        /// What is wrong.
        why: String,
    },
    /// A behaviour without groups.
    #[error("assign at least one module to a group of joints")]
    NoGroups,
    /// A group that cannot drive the robot.
    #[error("group {group}: {problem}")]
    Group {
        /// The group (from 1).
        group: usize,
        /// What is wrong.
        problem: GroupProblem,
    },
    /// An optimization without registered parameters.
    #[error("register at least one parameter to optimize")]
    NothingRegistered,
    /// A registered parameter that cannot be optimized.
    #[error("parameter {index} ({module} {parameter}): {problem}")]
    Registration {
        /// The registration (from 1).
        index: usize,
        /// Its module type.
        module: String,
        /// Its parameter.
        parameter: String,
        /// What is wrong.
        problem: &'static str,
    },
    /// A genetic algorithm with fewer than 2 candidates per generation.
    #[error("population size must be at least 2")]
    Popsize,
    /// A module-count range no chain fits.
    #[error("morphology: {} to {} modules: a chain has 2 to {most} modules, min <= max", range[0], range[1])]
    ModuleRange {
        /// The range given.
        range: [u32; 2],
        /// Most modules a chain may have.
        most: u32,
    },
    /// Morphology ranges no body fits.
    #[error("morphology: {0}")]
    Morphology(&'static str),
    /// MAP-Elites descriptors that cannot map the candidates.
    #[error("MAP-Elites: {0}")]
    Descriptors(&'static str),
    /// A step width out of range.
    #[error("step width {0} s is outside 0.000001..{max} s", max = crate::config::simulation::MAX_STEP_WIDTH)]
    StepWidth(f64),
    /// A sampling period of 0 steps.
    #[error("accuracy is a sampling period in steps: at least 1")]
    Accuracy,
    /// A duration that is not positive.
    #[error("duration {0} s must be positive")]
    Duration(f64),
    /// The real-robot mode, which the robot file configures.
    #[error(
        "real robot control is configured on the robot; choose a simulation or optimization mode"
    )]
    RealRobotMode,
    /// A page the user may not skip.
    #[error("the {0} page cannot be skipped")]
    NotSkippable(&'static str),
    /// A page of the wizard that does not validate (named for the summary).
    #[error("{page} page: {source}")]
    Page {
        /// The page's title.
        page: &'static str,
        /// Why.
        source: Box<ComposeError>,
    },
}

/// What of a behaviour group cannot drive the robot.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GroupProblem {
    /// A mask of another length than the robot's joints.
    #[error("{selected} joints selected of a robot with {joints}")]
    Joints {
        /// The mask's length.
        selected: usize,
        /// The robot's joints.
        joints: usize,
    },
    /// No joint selected.
    #[error("select at least one joint")]
    NoJoint,
    /// No module assigned.
    #[error("assign at least one module")]
    NoModule,
    /// A module type the registry does not offer.
    #[error("unknown module \"{name}\"; known: {known}")]
    UnknownModule {
        /// The name.
        name: String,
        /// The registry's module types.
        known: String,
    },
    /// A parameter the module does not have.
    #[error("{module}: no parameter \"{parameter}\"; its parameters: {known}")]
    UnknownParameter {
        /// The module type.
        module: String,
        /// The parameter.
        parameter: String,
        /// Its parameters.
        known: String,
    },
    /// Per-joint values of another count than the driven joints.
    #[error("{module}: {parameter} has {values} values for {driven} joints")]
    ValueCount {
        /// The module type.
        module: String,
        /// The parameter.
        parameter: String,
        /// Values given.
        values: usize,
        /// Joints driven.
        driven: usize,
    },
    /// A value outside the parameter's range.
    #[error("{module}: {parameter} = {value} {unit} is outside {min}..{max}")]
    OutOfRange {
        /// The module type.
        module: String,
        /// The parameter.
        parameter: String,
        /// The value.
        value: f64,
        /// Its unit.
        unit: String,
        /// The minimum.
        min: f64,
        /// The maximum.
        max: f64,
    },
    /// No group of this number.
    #[error("there is no such group")]
    Missing,
    /// The group has no module of this type.
    #[error("no module {0} in this group")]
    NoSuchModule(String),
}

impl ComposeError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| ComposeError::Io { path, source }
    }
}

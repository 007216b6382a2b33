//! The beginner wizard (thesis 4.4.1): pages in order — robot, behaviour, environment,
//! simulation properties, optimization (only for the GA and great-deluge modes), summary —
//! each validated before the next; optional pages may be skipped. It writes ordinary
//! configuration files with time-stamped names into the user folder, with copies of the
//! parts (and a chosen robot) they use so the folder can be moved or shared, and checks
//! them the way `proleg check` does before anything reaches the disk.
//!
//! Fields with rules have typed setters ([`Wizard::set_topology`], [`Wizard::add_group`],
//! [`Wizard::register`], ...); the GUI's pages, its script and the tests call them.

use std::path::{Path, PathBuf};

use crate::compose::behaviour::{BehaviourSpec, Group, ModuleChoice};
use crate::compose::env_edit::EnvEditor;
use crate::compose::error::{ComposeError, GroupProblem};
use crate::compose::optimization::{Method, OptimizationSpec, Registration, ValueSet};
use crate::compose::paths::{MirrorSource, OverlaySource, relative_path};
use crate::compose::robot_builder::{PartSet, RobotSpec, check_name, parse_topology};
use crate::config::actuation::{ParamValue, write_actuation_file};
use crate::config::bundle::write_file;
use crate::config::environment::write_environment_file;
use crate::config::error::Pos;
use crate::config::optimizer::write_optimizer_file;
use crate::config::resolve::load_simulation_with;
use crate::config::resolve::robot::resolve_robot;
use crate::config::robot::{parse_robot_file, write_robot_file};
use crate::config::simulation::{
    FileRef, Mode, SimulationFile, SimulationProperties, write_simulation_file,
};
use crate::config::source::{FsSource, RecordingSource, normalize};
use crate::control::registry::ModuleRegistry;

/// A wizard page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Page {
    /// Build or choose the robot.
    Robot,
    /// Modules on groups of joints.
    Behaviour,
    /// The terrain (the environment editor).
    Environment,
    /// Step width, duration, mode.
    Simulation,
    /// Registered parameters and optimizer settings.
    Optimization,
    /// What will be written.
    Summary,
}

impl Page {
    /// The page's title.
    pub fn title(self) -> &'static str {
        match self {
            Page::Robot => "Robot",
            Page::Behaviour => "Behaviour",
            Page::Environment => "Environment",
            Page::Simulation => "Simulation properties",
            Page::Optimization => "Optimization",
            Page::Summary => "Summary and save",
        }
    }

    /// Whether "Skip" may leave the page at its defaults.
    pub fn optional(self) -> bool {
        matches!(self, Page::Environment | Page::Simulation)
    }
}

/// The robot: built from a topology, or an existing robot file.
#[derive(Debug, Clone, PartialEq)]
pub enum RobotChoice {
    /// A robot built from a specification.
    Build(RobotSpec),
    /// An existing robot file.
    Existing(PathBuf),
}

/// The files the wizard writes.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputFiles {
    /// The robot file written (None: an existing one is used).
    pub robot: Option<PathBuf>,
    /// The actuation file.
    pub actuation: PathBuf,
    /// The environment file.
    pub environment: PathBuf,
    /// The optimizer file, in an optimization mode.
    pub optimizer: Option<PathBuf>,
    /// The simulation file.
    pub simulation: PathBuf,
}

/// The wizard's state.
#[derive(Debug, Clone)]
pub struct Wizard {
    /// The page shown.
    pub page: Page,
    /// The configuration folder (parts, robots, ... live below it).
    pub configs_dir: PathBuf,
    /// Where new files go.
    pub out_dir: PathBuf,
    /// Time stamp in the file names.
    pub stamp: String,
    /// The robot: built or existing.
    pub robot: RobotChoice,
    /// The built robot's spec kept while an existing robot is chosen.
    pub spec: RobotSpec,
    /// The groups of joints and their modules.
    pub behaviour: BehaviourSpec,
    /// The scene (the environment page).
    pub env: EnvEditor,
    /// The simulation properties.
    pub props: SimulationProperties,
    /// The simulation's description.
    pub description: String,
    /// The optimization settings.
    pub optimization: OptimizationSpec,
    /// The module types offered (standard library and loaded plugins).
    pub registry: ModuleRegistry,
    /// The simulation file written by [`Wizard::save`].
    pub saved: Option<PathBuf>,
}

/// A joint mask (`10101`) of a robot of `joints` joints.
fn parse_mask(s: &str, joints: usize) -> Result<Vec<bool>, ComposeError> {
    let bad = |why: String| ComposeError::Mask {
        mask: s.to_string(),
        why,
    };
    let m: Vec<bool> = s
        .trim()
        .chars()
        .map(|c| match c {
            '1' => Ok(true),
            '0' => Ok(false),
            other => Err(bad(format!("'{other}' is not 0 or 1"))),
        })
        .collect::<Result<_, _>>()?;
    if m.len() != joints {
        return Err(bad(format!(
            "{} characters; the robot has {joints} joints",
            m.len()
        )));
    }
    Ok(m)
}

/// A parameter registered for optimization as the Optimization page enters it.
#[derive(Debug, Clone, PartialEq)]
pub struct RegisterSpec {
    /// The module type.
    pub module: String,
    /// The parameter.
    pub parameter: String,
    /// The joints as a mask (`10101`), or `None` for all of the module's joints.
    pub joints: Option<String>,
    /// One value for every joint (true) or one per joint.
    pub uniform: bool,
    /// The values searched.
    pub values: ValueSet,
}

impl Wizard {
    /// A wizard writing into `out_dir`; `stamp` goes into the file names.
    pub fn new(configs_dir: &Path, out_dir: &Path, stamp: &str) -> Self {
        let registry = ModuleRegistry::default();
        let spec = RobotSpec::default();
        let sine =
            ModuleChoice::with_defaults(&registry, "PatternGenerator_sinusoidal").or_else(|| {
                registry
                    .names()
                    .first()
                    .and_then(|n| ModuleChoice::with_defaults(&registry, n))
            });
        let behaviour = match sine {
            Some(m) => BehaviourSpec::simple(spec.joints.len(), m),
            None => BehaviourSpec { groups: Vec::new() },
        };
        let mut w = Wizard {
            page: Page::Robot,
            configs_dir: configs_dir.to_path_buf(),
            out_dir: out_dir.to_path_buf(),
            stamp: stamp.to_string(),
            robot: RobotChoice::Build(spec.clone()),
            spec,
            behaviour,
            env: EnvEditor::new(out_dir.join("new.env.xml")),
            props: SimulationProperties {
                storing_data: false,
                ..SimulationProperties::default()
            },
            description: String::new(),
            optimization: OptimizationSpec::new(Method::Genetic),
            registry,
            saved: None,
        };
        w.env.file = w.files().environment;
        w
    }

    /// The pages in order (optimization only for an optimizing mode).
    pub fn pages(&self) -> Vec<Page> {
        let mut p = vec![
            Page::Robot,
            Page::Behaviour,
            Page::Environment,
            Page::Simulation,
        ];
        if self.props.mode.is_optimization() {
            p.push(Page::Optimization);
        }
        p.push(Page::Summary);
        p
    }

    /// The page's number (from 1) and the page count.
    pub fn progress(&self) -> (usize, usize) {
        let pages = self.pages();
        let i = pages.iter().position(|p| *p == self.page).unwrap_or(0);
        (i + 1, pages.len())
    }

    /// The robot's name (its file's name for an existing robot).
    pub fn robot_name(&self) -> String {
        match &self.robot {
            RobotChoice::Build(s) => s.name.clone(),
            RobotChoice::Existing(p) => p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
                .trim_end_matches(".robot.xml")
                .to_string(),
        }
    }

    /// Number of joints of the chosen robot.
    pub fn joint_count(&self) -> Result<usize, ComposeError> {
        match &self.robot {
            RobotChoice::Build(s) => Ok(s.joints.len()),
            RobotChoice::Existing(p) => {
                let text = std::fs::read_to_string(p).map_err(ComposeError::io(p))?;
                let file = parse_robot_file(&p.display().to_string(), &text)?;
                let model = resolve_robot(&FsSource, p, &file)?;
                Ok(model.joints.len())
            }
        }
    }

    /// The joint orientations as letters (`ppyp`) when known.
    pub fn topology(&self) -> String {
        match &self.robot {
            RobotChoice::Build(s) => crate::compose::robot_builder::topology_string(&s.joints),
            RobotChoice::Existing(_) => String::new(),
        }
    }

    /// Robot files offered in the "existing robot" list.
    pub fn existing_robots(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = [self.configs_dir.join("robots"), self.out_dir.clone()]
            .iter()
            .flat_map(|d| std::fs::read_dir(d).into_iter().flatten().flatten())
            .map(|e| e.path())
            .filter(|p| p.to_string_lossy().ends_with(".robot.xml"))
            .collect();
        v.sort();
        v.dedup();
        v
    }

    /// The names of the files [`Wizard::save`] writes.
    pub fn files(&self) -> OutputFiles {
        let base = format!("{}_{}", self.robot_name(), self.stamp);
        let f = |ext: &str| self.out_dir.join(format!("{base}.{ext}"));
        OutputFiles {
            robot: matches!(self.robot, RobotChoice::Build(_)).then(|| f("robot.xml")),
            actuation: f("actuation.xml"),
            environment: f("env.xml"),
            optimizer: self.props.mode.is_optimization().then(|| {
                f(match self.optimization.method {
                    Method::Genetic => "ga.xml",
                    Method::GreatDeluge => "gd.xml",
                    Method::CmaEs => "cmaes.xml",
                    Method::MapElites => "mapelites.xml",
                })
            }),
            simulation: f("simulation.xml"),
        }
    }

    /// Why the page cannot be left with "Next", if it cannot.
    pub fn validate(&self, page: Page) -> Result<(), ComposeError> {
        match page {
            Page::Robot => match &self.robot {
                RobotChoice::Build(s) => Ok(s.validate()?),
                RobotChoice::Existing(_) => self.joint_count().map(|_| ()),
            },
            Page::Behaviour => self.behaviour.validate(&self.registry, self.joint_count()?),
            Page::Environment => Ok(()),
            Page::Simulation => {
                let p = &self.props;
                if !(1e-6..=crate::config::simulation::MAX_STEP_WIDTH).contains(&p.step_width) {
                    return Err(ComposeError::StepWidth(p.step_width));
                }
                if p.accuracy == 0 {
                    return Err(ComposeError::Accuracy);
                }
                if !(p.duration > 0.0 && p.duration.is_finite()) {
                    return Err(ComposeError::Duration(p.duration));
                }
                if p.mode == Mode::RealRobot {
                    return Err(ComposeError::RealRobotMode);
                }
                Ok(())
            }
            Page::Optimization => self.optimization.validate(),
            Page::Summary => self.compose().map(|_| ()),
        }
    }

    /// Goes to the next page after validating this one ("Next").
    pub fn next_page(&mut self) -> Result<(), ComposeError> {
        self.validate(self.page)?;
        self.advance();
        Ok(())
    }

    /// Leaves an optional page at its defaults.
    pub fn skip(&mut self) -> Result<(), ComposeError> {
        if !self.page.optional() {
            return Err(ComposeError::NotSkippable(self.page.title()));
        }
        self.advance();
        Ok(())
    }

    fn advance(&mut self) {
        if self.page == Page::Robot
            && let Ok(n) = self.joint_count()
        {
            self.behaviour.resize(n);
        }
        let pages = self.pages();
        if let Some(i) = pages.iter().position(|p| *p == self.page) {
            self.page = pages.get(i + 1).copied().unwrap_or(self.page);
        }
        self.env.file = self.files().environment;
    }

    /// Goes to the previous page.
    pub fn back(&mut self) {
        let pages = self.pages();
        if let Some(i) = pages.iter().position(|p| *p == self.page)
            && i > 0
        {
            self.page = pages[i - 1];
        }
    }

    /// Every file's text, checked as one simulation (nothing written).
    pub fn compose(&self) -> Result<Vec<(PathBuf, String)>, ComposeError> {
        for p in self.pages().into_iter().filter(|p| *p != Page::Summary) {
            self.validate(p).map_err(|e| ComposeError::Page {
                page: p.title(),
                source: Box::new(e),
            })?;
        }
        let files = self.files();
        let mut out = Vec::new();
        let robot_path = match &self.robot {
            RobotChoice::Build(spec) => {
                let path = files.robot.clone().unwrap_or_default();
                // The parts are copied beside it (see `copies`).
                out.push((path.clone(), write_robot_file(&spec.to_robot_file("parts"))));
                path
            }
            RobotChoice::Existing(p) => self.in_out_dir(p),
        };
        let robot_ref = relative_path(&self.out_dir, &robot_path);
        out.push((
            files.actuation.clone(),
            write_actuation_file(&self.behaviour.to_actuation_file(&robot_ref)),
        ));
        out.push((
            files.environment.clone(),
            write_environment_file(&self.env.to_file()),
        ));
        if let Some(opt) = &files.optimizer {
            let joints = self.joint_count()?;
            let text = write_optimizer_file(
                &self
                    .optimization
                    .to_optimizer_file(&|m| self.behaviour.joints_of(m, joints)),
            );
            out.push((opt.clone(), text));
        }
        let name = |p: &Path| relative_path(&self.out_dir, p);
        let fref = |p: &Path| FileRef {
            path: name(p),
            pos: Pos::new(0, 0),
        };
        let description = if self.description.trim().is_empty() {
            format!(
                "Made with the proleg wizard: {} on {} joints.",
                self.robot_name(),
                self.joint_count().unwrap_or(0)
            )
        } else {
            self.description.trim().to_string()
        };
        let sim = SimulationFile {
            description: Some(description),
            robot: fref(&robot_path),
            actuation: fref(&files.actuation),
            environment: Some(fref(&files.environment)),
            optimizer: files.optimizer.as_deref().map(fref),
            properties: self.props.clone(),
        };
        out.push((files.simulation.clone(), write_simulation_file(&sim)));
        let copies = self.check(&out, &files.simulation)?;
        out.extend(copies);
        Ok(out)
    }

    /// Where a robot file of the configuration folder is copied (in the same layout under
    /// the output folder, so its parts come along); one already in the output folder (a
    /// robot the wizard built before), or outside the configuration folder, stays.
    fn in_out_dir(&self, robot: &Path) -> PathBuf {
        let (robot, configs) = (normalize(robot), normalize(&self.configs_dir));
        if robot.starts_with(normalize(&self.out_dir)) {
            return robot;
        }
        match robot.strip_prefix(&configs) {
            Ok(rest) => self.out_dir.join(rest),
            Err(_) => robot,
        }
    }

    /// Loads the composed files as a simulation, the way `proleg check` does, with the
    /// configuration folder's files seen in the output folder; returns the ones it used
    /// there that are not composed (parts, their sensors, a chosen robot) as copies to
    /// write (with the parts of every body a co-design run may build), so the folder
    /// stands alone.
    fn check(
        &self,
        files: &[(PathBuf, String)],
        sim: &Path,
    ) -> Result<Vec<(PathBuf, String)>, ComposeError> {
        let mut overlay = OverlaySource::default();
        for (p, t) in files {
            overlay.unsaved.insert(p, t.clone());
        }
        let mirror = MirrorSource {
            base: &overlay,
            at: self.out_dir.clone(),
            from: self.configs_dir.clone(),
        };
        let src = RecordingSource::new(&mirror);
        let sim = load_simulation_with(&src, sim, &self.registry)?;
        // A co-design run's bodies may use parts its first robot does not.
        crate::optimize::design::body_files(&sim, &src)?;
        let out_dir = normalize(&self.out_dir);
        let composed: Vec<PathBuf> = files.iter().map(|(p, _)| normalize(p)).collect();
        Ok(src
            .files()
            .into_iter()
            .map(|(p, t)| (PathBuf::from(p), t))
            .filter(|(p, _)| p.starts_with(&out_dir) && !composed.contains(p))
            .collect())
    }

    /// Writes every file; returns the simulation file.
    pub fn save(&mut self) -> Result<PathBuf, ComposeError> {
        let files = self.compose()?;
        std::fs::create_dir_all(&self.out_dir).map_err(ComposeError::io(&self.out_dir))?;
        for (p, t) in &files {
            write_file(p, t)?;
        }
        let sim = self.files().simulation;
        self.saved = Some(sim.clone());
        Ok(sim)
    }

    /// Names the robot to build (letters, digits, `_` and `-`).
    pub fn set_robot_name(&mut self, name: &str) -> Result<(), ComposeError> {
        check_name(name.trim(), "robot name")?;
        self.spec.name = name.trim().to_string();
        self.build_robot();
        Ok(())
    }

    /// The joints of the robot to build, as letters (`pypyp`: p pitch, y yaw).
    pub fn set_topology(&mut self, letters: &str) -> Result<(), ComposeError> {
        self.spec.joints = parse_topology(letters)?;
        self.build_robot();
        Ok(())
    }

    /// The module parts of the robot to build.
    pub fn set_parts(&mut self, parts: PartSet) {
        self.spec.parts = parts;
        self.build_robot();
    }

    /// Builds the robot of [`Wizard::spec`] (instead of an existing robot file).
    pub fn build_robot(&mut self) {
        self.robot = RobotChoice::Build(self.spec.clone());
    }

    /// Uses an existing robot file (relative to the configuration folder).
    pub fn use_existing_robot(&mut self, file: &Path) -> Result<(), ComposeError> {
        let p = self.configs_dir.join(file);
        if !p.is_file() {
            return Err(ComposeError::NoRobotFile(p));
        }
        self.robot = RobotChoice::Existing(p);
        self.joint_count()?;
        Ok(())
    }

    /// One group of every joint, driven by `module` with its defaults.
    pub fn set_simple_behaviour(&mut self, module: &str) -> Result<(), ComposeError> {
        let n = self.joint_count()?;
        self.behaviour = BehaviourSpec::simple(n, module_choice(&self.registry, module)?);
        Ok(())
    }

    /// Adds a group: the joints of `mask` (`10101`) driven by `modules`.
    pub fn add_group(&mut self, mask: &str, modules: &[String]) -> Result<(), ComposeError> {
        let joints = parse_mask(mask, self.joint_count()?)?;
        let modules = modules
            .iter()
            .map(|m| module_choice(&self.registry, m))
            .collect::<Result<Vec<_>, _>>()?;
        self.behaviour.groups.push(Group { joints, modules });
        Ok(())
    }

    /// Sets a parameter of a module of group `group` (from 1): one value for all its
    /// joints, or one per joint.
    pub fn set_group_param(
        &mut self,
        group: usize,
        module: &str,
        parameter: &str,
        values: &[f64],
    ) -> Result<(), ComposeError> {
        let fail = |problem| ComposeError::Group { group, problem };
        let g = self
            .behaviour
            .groups
            .get_mut(group.wrapping_sub(1))
            .ok_or(fail(GroupProblem::Missing))?;
        let m = g
            .modules
            .iter_mut()
            .find(|m| crate::config::xml::read::same_name(&m.name, module))
            .ok_or_else(|| fail(GroupProblem::NoSuchModule(module.to_string())))?;
        let value = match values {
            [v] => ParamValue::Uniform(*v),
            v => ParamValue::PerJoint(v.to_vec()),
        };
        m.set_value(parameter, value);
        Ok(())
    }

    /// The simulation's mode; an optimization mode also chooses the optimizer's method.
    pub fn set_mode(&mut self, mode: Mode) {
        match mode {
            Mode::GeneticAlgorithm => self.optimization.method = Method::Genetic,
            Mode::GreatDeluge => self.optimization.method = Method::GreatDeluge,
            Mode::CmaEs => self.optimization.method = Method::CmaEs,
            Mode::MapElites => self.optimization.method = Method::MapElites,
            _ => {}
        }
        self.props.mode = mode;
    }

    /// Registers a module parameter for optimization.
    pub fn register(&mut self, spec: RegisterSpec) -> Result<(), ComposeError> {
        let d = self
            .registry
            .get(&spec.module)
            .ok_or_else(|| ComposeError::UnknownModule {
                name: spec.module.clone(),
                known: self.registry.names().join(", "),
            })?;
        let p = d
            .parameter(&spec.parameter)
            .ok_or_else(|| ComposeError::UnknownParameter {
                module: d.type_name.to_string(),
                parameter: spec.parameter.clone(),
                known: d.parameter_names().join(", "),
            })?;
        let (all_joints, joints) = match &spec.joints {
            None => (true, Vec::new()),
            Some(mask) => (false, parse_mask(mask, self.joint_count()?)?),
        };
        self.optimization.params.push(Registration {
            module: d.type_name.to_string(),
            parameter: p.name.to_string(),
            all_joints,
            joints,
            uniform: spec.uniform,
            values: spec.values,
        });
        Ok(())
    }
}

/// A module of type `name` with its default parameters; the error lists the types.
fn module_choice(registry: &ModuleRegistry, name: &str) -> Result<ModuleChoice, ComposeError> {
    ModuleChoice::with_defaults(registry, name).ok_or_else(|| ComposeError::UnknownModule {
        name: name.to_string(),
        known: registry.names().join(", "),
    })
}

#[cfg(test)]
mod tests {

    use super::*;
    use crate::config::robot_builder::BuildError;

    #[test]
    fn a_shipped_robot_is_copied_into_the_output_folder_and_a_built_one_stays() {
        let w = Wizard::new(Path::new("configs"), Path::new("configs/user"), "t");
        assert_eq!(
            w.in_out_dir(Path::new("configs/robots/snake5p.robot.xml")),
            PathBuf::from("configs/user/robots/snake5p.robot.xml")
        );
        assert_eq!(
            w.in_out_dir(Path::new("configs/user/mine.robot.xml")),
            PathBuf::from("configs/user/mine.robot.xml")
        );
    }

    fn wizard(tag: &str) -> (Wizard, PathBuf) {
        let out = std::env::temp_dir().join(format!("proleg_wizard_{tag}_{}", std::process::id()));
        let configs = std::env::current_dir().unwrap().join("configs");
        (Wizard::new(&configs, &out, "20261122_120000"), out)
    }

    #[test]
    fn pages_validate_before_next_and_optimization_shows_only_when_optimizing() {
        let (mut w, _) = wizard("pages");
        assert_eq!(w.pages().len(), 5);
        w.set_topology("").unwrap();
        assert!(matches!(
            w.next_page(),
            Err(ComposeError::Build(BuildError::JointCount(0)))
        ));
        w.set_topology("pyp").unwrap();
        w.next_page().unwrap();
        assert_eq!(w.page, Page::Behaviour);
        // The simple actuation followed the robot to 3 joints.
        assert_eq!(w.behaviour.groups[0].joints.len(), 3);
        assert!(matches!(w.skip(), Err(ComposeError::NotSkippable(_))));
        w.next_page().unwrap();
        w.skip().unwrap();
        assert_eq!(w.page, Page::Simulation);
        w.set_mode(Mode::GreatDeluge);
        assert_eq!(w.pages().len(), 6);
        w.next_page().unwrap();
        assert_eq!(w.page, Page::Optimization);
        assert!(matches!(
            w.next_page(),
            Err(ComposeError::NothingRegistered)
        ));
        w.back();
        assert_eq!(w.page, Page::Simulation);
        assert!(matches!(
            w.add_group("10", &["PatternGenerator_sinusoidal".into()]),
            Err(ComposeError::Mask { .. })
        ));
        assert!(matches!(
            w.add_group("101", &["Sine".into()]),
            Err(ComposeError::UnknownModule { .. })
        ));
        let unknown = RegisterSpec {
            module: "PatternGenerator_sinusoidal".into(),
            parameter: "x".into(),
            joints: None,
            uniform: true,
            values: ValueSet::List(vec![1.0]),
        };
        assert!(matches!(
            w.register(unknown),
            Err(ComposeError::UnknownParameter { .. })
        ));
    }

    #[test]
    fn grouped_robot_with_optimization_is_written_and_loads() {
        let (mut w, out) = wizard("files");
        w.set_robot_name("wiz").unwrap();
        w.set_topology("pypyp").unwrap();
        w.set_parts(PartSet::Plain);
        w.next_page().unwrap();
        w.behaviour.groups.clear();
        w.add_group("10101", &["PatternGenerator_sinusoidal".into()])
            .unwrap();
        w.add_group("01010", &["DirectJointAccess".into()]).unwrap();
        w.set_group_param(1, "PatternGenerator_sinusoidal", "Amplitude", &[30.0])
            .unwrap();
        w.next_page().unwrap();
        w.next_page().unwrap();
        w.set_mode(Mode::GeneticAlgorithm);
        w.props.duration = 5.0;
        w.next_page().unwrap();
        w.register(RegisterSpec {
            module: "PatternGenerator_sinusoidal".into(),
            parameter: "Amplitude".into(),
            joints: None,
            uniform: false,
            values: ValueSet::Range {
                lower: 0.0,
                upper: 40.0,
                increment: 0.25,
            },
        })
        .unwrap();
        w.next_page().unwrap();
        assert_eq!(w.page, Page::Summary);
        let sim = w.save().unwrap();
        assert!(sim.ends_with("wiz_20261122_120000.simulation.xml"));
        let loaded = crate::control::load_simulation(&sim).unwrap();
        assert_eq!(loaded.robot.joints.len(), 5);
        assert_eq!(loaded.actuation.modules.len(), 2);
        let opt = loaded.optimizer.expect("an optimizer");
        assert_eq!(opt.parameters[0].genes, 3, "one gene per pitch joint");
        std::fs::remove_dir_all(out).ok();
    }
}

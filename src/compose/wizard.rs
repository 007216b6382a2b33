//! The beginner wizard (thesis 4.4.1): pages in order — robot, behaviour, environment,
//! simulation properties, optimization (only for the GA and great-deluge modes), summary —
//! each validated before the next; optional pages may be skipped. It writes ordinary
//! configuration files with time-stamped names into the user folder, and checks them the
//! way `proleg check` does before anything reaches the disk.
//!
//! [`Wizard::set`] changes any field from a `KEY VALUE` line; the GUI's script and the
//! tests drive the wizard through it.

use std::path::{Path, PathBuf};

use crate::compose::behaviour::{BehaviourSpec, Group, ModuleChoice};
use crate::compose::env_edit::EnvEditor;
use crate::compose::optimization::{Method, OptimizationSpec, Registration, ValueSet};
use crate::compose::paths::{OverlaySource, relative_path};
use crate::compose::robot_builder::{PartSet, RobotSpec, check_name, parse_topology};
use crate::config::actuation::{ParamValue, write_actuation_file};
use crate::config::environment::write_environment_file;
use crate::config::error::Pos;
use crate::config::optimizer::write_optimizer_file;
use crate::config::resolve::robot::resolve_robot;
use crate::config::resolve::{Simulation, load_simulation_with};
use crate::config::robot::{parse_robot_file, write_robot_file};
use crate::config::simulation::{
    FileRef, Mode, SimulationFile, SimulationProperties, write_simulation_file,
};
use crate::config::source::FsSource;
use crate::control::registry::ModuleRegistry;
use crate::optimize::fitness::Fitness;

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

fn parse_num(s: &str, what: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("{what}: \"{s}\" is not a number"))
}

fn parse_mask(s: &str, joints: usize) -> Result<Vec<bool>, String> {
    let m: Vec<bool> = s
        .trim()
        .chars()
        .map(|c| match c {
            '1' => Ok(true),
            '0' => Ok(false),
            other => Err(format!("joint mask \"{s}\": '{other}' is not 0 or 1")),
        })
        .collect::<Result<_, _>>()?;
    if m.len() != joints {
        return Err(format!(
            "joint mask \"{s}\" has {} characters; the robot has {joints} joints",
            m.len()
        ));
    }
    Ok(m)
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
    pub fn joint_count(&self) -> Result<usize, String> {
        match &self.robot {
            RobotChoice::Build(s) => Ok(s.joints.len()),
            RobotChoice::Existing(p) => {
                let text =
                    std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
                let file =
                    parse_robot_file(&p.display().to_string(), &text).map_err(|e| e.to_string())?;
                let model = resolve_robot(&FsSource, p, &file).map_err(|e| e.to_string())?;
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
                })
            }),
            simulation: f("simulation.xml"),
        }
    }

    /// Why the page cannot be left with "Next", if it cannot.
    pub fn validate(&self, page: Page) -> Result<(), String> {
        match page {
            Page::Robot => match &self.robot {
                RobotChoice::Build(s) => s.validate(),
                RobotChoice::Existing(_) => self.joint_count().map(|_| ()),
            },
            Page::Behaviour => self.behaviour.validate(&self.registry, self.joint_count()?),
            Page::Environment => Ok(()),
            Page::Simulation => {
                let p = &self.props;
                if !(1e-6..=crate::config::simulation::MAX_STEP_WIDTH).contains(&p.step_width) {
                    return Err(format!(
                        "step width {} s is outside 0.000001..{} s",
                        p.step_width,
                        crate::config::simulation::MAX_STEP_WIDTH
                    ));
                }
                if p.accuracy == 0 {
                    return Err("accuracy is a sampling period in steps: at least 1".into());
                }
                if !(p.duration > 0.0 && p.duration.is_finite()) {
                    return Err(format!("duration {} s must be positive", p.duration));
                }
                if p.mode == Mode::RealRobot {
                    return Err("real robot control is configured on the robot; choose a simulation or optimization mode".into());
                }
                Ok(())
            }
            Page::Optimization => self.optimization.validate(),
            Page::Summary => self.compose().map(|_| ()),
        }
    }

    /// Goes to the next page after validating this one ("Next").
    pub fn next_page(&mut self) -> Result<(), String> {
        self.validate(self.page)?;
        self.advance();
        Ok(())
    }

    /// Leaves an optional page at its defaults.
    pub fn skip(&mut self) -> Result<(), String> {
        if !self.page.optional() {
            return Err(format!("the {} page cannot be skipped", self.page.title()));
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
    pub fn compose(&self) -> Result<Vec<(PathBuf, String)>, String> {
        for p in self.pages().into_iter().filter(|p| *p != Page::Summary) {
            self.validate(p)
                .map_err(|e| format!("{} page: {e}", p.title()))?;
        }
        let files = self.files();
        let mut out = Vec::new();
        let robot_path = match &self.robot {
            RobotChoice::Build(spec) => {
                let path = files.robot.clone().unwrap_or_default();
                let parts = relative_path(&self.out_dir, &self.configs_dir.join("parts"));
                out.push((path.clone(), write_robot_file(&spec.to_robot_file(&parts))));
                path
            }
            RobotChoice::Existing(p) => p.clone(),
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
        self.check(&out, &files.simulation)?;
        Ok(out)
    }

    /// Loads the composed files as a simulation, the way `proleg check` does.
    fn check(&self, files: &[(PathBuf, String)], sim: &Path) -> Result<Simulation, String> {
        let mut src = OverlaySource::default();
        for (p, t) in files {
            src.unsaved.insert(p, t.clone());
        }
        load_simulation_with(&src, sim, &self.registry).map_err(|e| e.to_string())
    }

    /// Writes every file; returns the simulation file.
    pub fn save(&mut self) -> Result<PathBuf, String> {
        let files = self.compose()?;
        std::fs::create_dir_all(&self.out_dir)
            .map_err(|e| format!("{}: {e}", self.out_dir.display()))?;
        for (p, t) in &files {
            std::fs::write(p, t).map_err(|e| format!("{}: {e}", p.display()))?;
        }
        let sim = self.files().simulation;
        self.saved = Some(sim.clone());
        Ok(sim)
    }

    /// Changes a field from a `KEY VALUE` line (the script and tests use it):
    ///
    /// ```text
    /// robot.name NAME | robot.topology pypy | robot.parts plain|touch|cube
    /// robot.existing robots/snake5p.robot.xml | robot.build
    /// behaviour.simple MODULE
    /// behaviour.group MASK MODULE[,MODULE...]
    /// behaviour.param GROUP MODULE PARAM VALUE|v1,v2,...   (GROUP from 1)
    /// sim.mode single|ga|gd | sim.step S | sim.accuracy N | sim.duration S
    /// sim.seed N | sim.storing 0|1 | sim.viewer 0|1 | sim.description TEXT
    /// opt.register MODULE PARAM all|MASK uniform|individual LO HI INC
    /// opt.register MODULE PARAM all|MASK uniform|individual list v1,v2,...
    /// opt.popsize N | opt.max-evals N | opt.fitness NAME | opt.clear
    /// ```
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        let words: Vec<&str> = value.split_whitespace().collect();
        match key.split('.').next() {
            Some("robot") => self.set_robot(key, value),
            Some("behaviour") => self.set_behaviour(key, &words),
            Some("sim") => self.set_sim(key, value),
            Some("opt") => self.set_optimization(key, value, &words),
            _ => Err(format!("unknown wizard field \"{key}\"")),
        }
    }

    /// The `robot.*` fields of [`Wizard::set`].
    fn set_robot(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "robot.name" => {
                check_name(value.trim(), "robot name")?;
                self.spec.name = value.trim().to_string();
                self.robot = RobotChoice::Build(self.spec.clone());
            }
            "robot.topology" => {
                self.spec.joints = parse_topology(value)?;
                self.robot = RobotChoice::Build(self.spec.clone());
            }
            "robot.parts" => {
                self.spec.parts = PartSet::parse(value).ok_or_else(|| {
                    format!("part set \"{value}\": expected plain, touch or cube")
                })?;
                self.robot = RobotChoice::Build(self.spec.clone());
            }
            "robot.build" => self.robot = RobotChoice::Build(self.spec.clone()),
            "robot.existing" => {
                let p = self.configs_dir.join(value.trim());
                if !p.is_file() {
                    return Err(format!("no robot file {}", p.display()));
                }
                self.robot = RobotChoice::Existing(p);
                self.joint_count()?;
            }
            other => return Err(format!("unknown wizard field \"{other}\"")),
        }
        Ok(())
    }

    /// The `behaviour.*` fields of [`Wizard::set`].
    fn set_behaviour(&mut self, key: &str, words: &[&str]) -> Result<(), String> {
        let want = |n: usize, usage: &str| want(key, words, n, usage);
        let registry = &self.registry;
        let module = |name: &str| module_choice(registry, name);
        match key {
            "behaviour.simple" => {
                want(1, "MODULE")?;
                let n = self.joint_count()?;
                self.behaviour = BehaviourSpec::simple(n, module(words[0])?);
            }
            "behaviour.clear" => self.behaviour.groups.clear(),
            "behaviour.group" => {
                want(2, "MASK MODULE[,MODULE...]")?;
                let joints = parse_mask(words[0], self.joint_count()?)?;
                let modules = words[1]
                    .split(',')
                    .map(module)
                    .collect::<Result<Vec<_>, _>>()?;
                self.behaviour.groups.push(Group { joints, modules });
            }
            "behaviour.param" => {
                want(4, "GROUP MODULE PARAM VALUE")?;
                let gi = parse_num(words[0], "group")? as usize;
                let g = self
                    .behaviour
                    .groups
                    .get_mut(gi.wrapping_sub(1))
                    .ok_or_else(|| format!("no group {gi}"))?;
                let m = g
                    .modules
                    .iter_mut()
                    .find(|m| crate::config::xml::read::same_name(&m.name, words[1]))
                    .ok_or_else(|| format!("group {gi} has no module {}", words[1]))?;
                let v: Vec<f64> = words[3]
                    .split(',')
                    .map(|w| parse_num(w, words[2]))
                    .collect::<Result<_, _>>()?;
                let value = if v.len() == 1 {
                    ParamValue::Uniform(v[0])
                } else {
                    ParamValue::PerJoint(v)
                };
                m.set_value(words[2], value);
            }
            other => return Err(format!("unknown wizard field \"{other}\"")),
        }
        Ok(())
    }

    /// The `sim.*` fields of [`Wizard::set`].
    fn set_sim(&mut self, key: &str, value: &str) -> Result<(), String> {
        match key {
            "sim.mode" => {
                self.props.mode = match value.trim().to_ascii_lowercase().as_str() {
                    "single" => Mode::SingleRun,
                    "ga" => {
                        self.optimization.method = Method::Genetic;
                        Mode::GeneticAlgorithm
                    }
                    "gd" => {
                        self.optimization.method = Method::GreatDeluge;
                        Mode::GreatDeluge
                    }
                    "cmaes" => {
                        self.optimization.method = Method::CmaEs;
                        Mode::CmaEs
                    }
                    other => Mode::parse(other).ok_or_else(|| {
                        format!("mode \"{other}\": expected single, ga, gd or cmaes")
                    })?,
                }
            }
            "sim.step" => self.props.step_width = parse_num(value, key)?,
            "sim.accuracy" => self.props.accuracy = parse_num(value, key)?.max(0.0) as u32,
            "sim.duration" => self.props.duration = parse_num(value, key)?,
            "sim.seed" => self.props.seed = parse_num(value, key)?.max(0.0) as u64,
            "sim.storing" => self.props.storing_data = value.trim() == "1",
            "sim.viewer" => self.props.show_viewer = value.trim() == "1",
            "sim.description" => self.description = value.to_string(),
            other => return Err(format!("unknown wizard field \"{other}\"")),
        }
        Ok(())
    }

    /// The `opt.*` fields of [`Wizard::set`].
    fn set_optimization(&mut self, key: &str, value: &str, words: &[&str]) -> Result<(), String> {
        match key {
            "opt.register" => self.register(words)?,
            "opt.clear" => self.optimization.params.clear(),
            "opt.popsize" => self.optimization.ga.popsize = parse_num(value, key)?.max(0.0) as u32,
            "opt.max-evals" => {
                self.optimization.max_evaluations = Some(parse_num(value, key)?.max(1.0) as u64)
            }
            "opt.fitness" => self.optimization.fitness = Fitness::parse(value)?,
            other => return Err(format!("unknown wizard field \"{other}\"")),
        }
        Ok(())
    }

    /// `opt.register MODULE PARAM all|MASK uniform|individual (LO HI INC | list v1,...)`.
    fn register(&mut self, words: &[&str]) -> Result<(), String> {
        let want = |n: usize, usage: &str| want("opt.register", words, n, usage);
        want(5, "MODULE PARAM all|MASK uniform|individual LO HI INC")?;
        let d = self
            .registry
            .get(words[0])
            .ok_or_else(|| format!("unknown module \"{}\"", words[0]))?;
        let p = d.parameter(words[1]).ok_or_else(|| {
            format!(
                "module {} has no parameter \"{}\"; its parameters: {}",
                d.type_name,
                words[1],
                d.parameter_names().join(", ")
            )
        })?;
        let (all_joints, joints) = if words[2] == "all" {
            (true, Vec::new())
        } else {
            (false, parse_mask(words[2], self.joint_count()?)?)
        };
        let uniform = match words[3] {
            "uniform" => true,
            "individual" => false,
            other => return Err(format!("\"{other}\": expected uniform or individual")),
        };
        let values = if words[4] == "list" {
            want(6, "... list v1,v2,...")?;
            ValueSet::List(
                words[5]
                    .split(',')
                    .map(|w| parse_num(w, "value"))
                    .collect::<Result<_, _>>()?,
            )
        } else {
            want(7, "... LO HI INC")?;
            ValueSet::Range {
                lower: parse_num(words[4], "lower bound")?,
                upper: parse_num(words[5], "upper bound")?,
                increment: parse_num(words[6], "increment")?,
            }
        };
        self.optimization.params.push(Registration {
            module: d.type_name.to_string(),
            parameter: p.name.to_string(),
            all_joints,
            joints,
            uniform,
            values,
        });
        Ok(())
    }
}

/// A module of type `name` with its default parameters; the error lists the types.
fn module_choice(registry: &ModuleRegistry, name: &str) -> Result<ModuleChoice, String> {
    ModuleChoice::with_defaults(registry, name).ok_or_else(|| {
        format!(
            "unknown module \"{name}\"; known: {}",
            registry.names().join(", ")
        )
    })
}

/// Fails unless `words` holds at least `n` words (`usage` says what `key` expects).
fn want(key: &str, words: &[&str], n: usize, usage: &str) -> Result<(), String> {
    if words.len() < n {
        Err(format!("{key}: expected {usage}"))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wizard(tag: &str) -> (Wizard, PathBuf) {
        let out = std::env::temp_dir().join(format!("proleg_wizard_{tag}_{}", std::process::id()));
        let configs = std::env::current_dir().unwrap().join("configs");
        (Wizard::new(&configs, &out, "20261122_120000"), out)
    }

    #[test]
    fn pages_validate_before_next_and_optimization_shows_only_when_optimizing() {
        let (mut w, _) = wizard("pages");
        assert_eq!(w.pages().len(), 5);
        w.set("robot.topology", "").unwrap();
        assert!(w.next_page().unwrap_err().contains("1 to"));
        w.set("robot.topology", "pyp").unwrap();
        w.next_page().unwrap();
        assert_eq!(w.page, Page::Behaviour);
        // The simple actuation followed the robot to 3 joints.
        assert_eq!(w.behaviour.groups[0].joints.len(), 3);
        assert!(w.skip().unwrap_err().contains("cannot be skipped"));
        w.next_page().unwrap();
        w.skip().unwrap();
        assert_eq!(w.page, Page::Simulation);
        w.set("sim.mode", "gd").unwrap();
        assert_eq!(w.pages().len(), 6);
        w.next_page().unwrap();
        assert_eq!(w.page, Page::Optimization);
        assert!(w.next_page().unwrap_err().contains("register"));
        w.back();
        assert_eq!(w.page, Page::Simulation);
        assert!(w.set("robot.parts", "gold").is_err());
        assert!(w.set("behaviour.group", "10 Sine").is_err());
        assert!(
            w.set("opt.register PatternGenerator_sinusoidal", "x")
                .is_err()
        );
    }

    #[test]
    fn grouped_robot_with_optimization_is_written_and_loads() {
        let (mut w, out) = wizard("files");
        w.set("robot.name", "wiz").unwrap();
        w.set("robot.topology", "pypyp").unwrap();
        w.set("robot.parts", "plain").unwrap();
        w.next_page().unwrap();
        w.set("behaviour.clear", "").unwrap();
        w.set("behaviour.group", "10101 PatternGenerator_sinusoidal")
            .unwrap();
        w.set("behaviour.group", "01010 DirectJointAccess").unwrap();
        w.set(
            "behaviour.param",
            "1 PatternGenerator_sinusoidal Amplitude 30",
        )
        .unwrap();
        w.next_page().unwrap();
        w.next_page().unwrap();
        w.set("sim.mode", "ga").unwrap();
        w.set("sim.duration", "5").unwrap();
        w.next_page().unwrap();
        w.set(
            "opt.register",
            "PatternGenerator_sinusoidal Amplitude all individual 0 40 0.25",
        )
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

//! Top-level simulation files (`*.simulation.xml`, thesis listing B.1): the paths of the
//! robot, actuation, environment and (optionally) optimizer files, and the global
//! simulation properties.
//!
//! Units: `stepWidth` is in seconds (the listing's 0.001 = 1 ms; the thesis's GUI shows
//! it in µs). `accuracy` is the sampling period of live plots, recording and sensor
//! updates in steps. Our extensions inside `simulationProperties`: `duration` (s),
//! `seed`, `delay` (ms of wall time added per step, slow motion) and `realtimeFactor`
//! (1 = real time, 0 = as fast as possible). The optimizer file is named by
//! `<optimizer>` (also accepted: `<geneticAlgorithm>`, `<greatDeluge>`).

use std::fmt;

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::xml::dom::Element;
use crate::config::xml::read::{Reader, read_document, same_name};
use crate::config::xml::write::XmlWriter;

/// Largest step width accepted (s): beyond it no contact simulation is meaningful.
pub const MAX_STEP_WIDTH: f64 = 0.1;

/// What a simulation run does (thesis 4.3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// One simulation run.
    SingleRun,
    /// Drive a real robot.
    RealRobot,
    /// Optimize with the genetic algorithm.
    GeneticAlgorithm,
    /// Optimize with the great deluge.
    GreatDeluge,
    /// Optimize with CMA-ES.
    CmaEs,
    /// Map designs with MAP-Elites.
    MapElites,
    /// Optimize with OpenAI's evolution strategy (learned policies' weights).
    EvolutionStrategy,
}

impl Mode {
    /// The canonical name written to files.
    pub fn name(self) -> &'static str {
        match self {
            Mode::SingleRun => "Single Run Simulation",
            Mode::RealRobot => "Real Robot Control",
            Mode::GeneticAlgorithm => "GA optimization",
            Mode::GreatDeluge => "Great Deluge optimization",
            Mode::CmaEs => "CMA-ES optimization",
            Mode::MapElites => "MAP-Elites optimization",
            Mode::EvolutionStrategy => "Evolution strategy optimization",
        }
    }

    /// Accepted spellings (compared ignoring case, spaces, `_` and `-`).
    const ALIASES: [(Mode, &'static [&'static str]); 7] = [
        (
            Mode::SingleRun,
            &["Single Run Simulation", "Single Run", "single"],
        ),
        (
            Mode::RealRobot,
            &["Real Robot Control", "Real Robot", "real"],
        ),
        (
            Mode::GeneticAlgorithm,
            &[
                "GA optimization",
                "GA optimisation",
                "Genetic Algorithm",
                "Genetic Algorithm optimization",
                "GA",
            ],
        ),
        (
            Mode::GreatDeluge,
            &[
                "Great Deluge optimization",
                "Great Deluge optimisation",
                "Great Deluge",
                "modified great deluge",
                "GD",
            ],
        ),
        (Mode::CmaEs, &["CMA-ES optimization", "CMA-ES", "CMAES"]),
        (
            Mode::MapElites,
            &["MAP-Elites optimization", "MAP-Elites", "MAPElites"],
        ),
        (
            Mode::EvolutionStrategy,
            &[
                "Evolution strategy optimization",
                "Evolution strategy",
                "OpenAI-ES",
                "ES",
            ],
        ),
    ];

    /// Reads a mode as files write it (other spellings accepted).
    pub fn parse(s: &str) -> Option<Mode> {
        Mode::ALIASES
            .iter()
            .find(|(_, names)| names.iter().any(|n| same_name(n, s)))
            .map(|(m, _)| *m)
    }

    /// Whether the mode optimizes.
    pub fn is_optimization(self) -> bool {
        matches!(
            self,
            Mode::GeneticAlgorithm
                | Mode::GreatDeluge
                | Mode::CmaEs
                | Mode::MapElites
                | Mode::EvolutionStrategy
        )
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Global simulation properties.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationProperties {
    /// Whether the thesis's viewer was shown (as written).
    pub show_viewer: bool,
    /// As written (proleg always evaluates in parallel).
    pub parallel_computing: bool,
    /// Whether data is recorded.
    pub storing_data: bool,
    /// What the simulation does.
    pub mode: Mode,
    /// Sampling period of plots, recording and sensor updates, in steps.
    pub accuracy: u32,
    /// Physics step width δ in seconds.
    pub step_width: f64,
    /// Simulated time of one run (an optimizer evaluation) in seconds.
    pub duration: f64,
    /// Seed of the run.
    pub seed: u64,
    /// Extra wall-clock delay per step in ms (slow motion).
    pub delay_ms: f64,
    /// 1 = real time, 0 = as fast as possible.
    pub realtime_factor: f64,
    /// The physics engine that steps the world (`<physicsEngine>`; rapier when absent).
    pub engine: EngineKind,
}

/// The physics engines a simulation can name (`<physicsEngine>rapier|mujoco</physicsEngine>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum EngineKind {
    /// rapier3d: pure Rust, always built, the engine the product was specified with.
    #[default]
    Rapier,
    /// MuJoCo 4.0, loaded at run time from its shared library.
    Mujoco,
}

impl EngineKind {
    /// Every engine, in the order help texts list them.
    pub const ALL: [EngineKind; 2] = [EngineKind::Rapier, EngineKind::Mujoco];

    /// The name files and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            EngineKind::Rapier => "rapier",
            EngineKind::Mujoco => "mujoco",
        }
    }

    /// The engine named `s` (case-insensitive), if any.
    pub fn parse(s: &str) -> Option<EngineKind> {
        let s = s.trim();
        EngineKind::ALL
            .into_iter()
            .find(|e| e.name().eq_ignore_ascii_case(s))
    }
}

impl fmt::Display for EngineKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is no physics engine's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown physics engine `{0}` (known: rapier, mujoco)")]
pub struct UnknownEngine(pub String);

impl std::str::FromStr for EngineKind {
    type Err = UnknownEngine;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        EngineKind::parse(s).ok_or_else(|| UnknownEngine(s.to_string()))
    }
}

impl Default for SimulationProperties {
    fn default() -> Self {
        SimulationProperties {
            show_viewer: true,
            parallel_computing: false,
            storing_data: false,
            mode: Mode::SingleRun,
            accuracy: 30,
            step_width: 0.001,
            duration: 30.0,
            seed: 1,
            delay_ms: 0.0,
            realtime_factor: 1.0,
            engine: EngineKind::Rapier,
        }
    }
}

/// A path written in a file, with where it was written.
#[derive(Debug, Clone, PartialEq)]
pub struct FileRef {
    /// The path as written.
    pub path: String,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// A simulation file as written.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationFile {
    /// A description, if any.
    pub description: Option<String>,
    /// The robot file.
    pub robot: FileRef,
    /// The actuation file.
    pub actuation: FileRef,
    /// The environment file, if any.
    pub environment: Option<FileRef>,
    /// The optimizer file, if any.
    pub optimizer: Option<FileRef>,
    /// The simulation properties.
    pub properties: SimulationProperties,
}

fn file_ref(r: &Reader, el: &Element) -> ConfigResult<FileRef> {
    Ok(FileRef {
        path: r.text(el)?.to_string(),
        pos: el.text_pos,
    })
}

fn read_properties(r: &Reader, el: &Element) -> ConfigResult<SimulationProperties> {
    r.only_children(
        el,
        // As files spell them (names match regardless of case).
        &[
            "showViewer",
            "parallelComputing",
            "storingData",
            "mode",
            "accuracy",
            "stepWidth",
            "duration",
            "seed",
            "delay",
            "realtimeFactor",
            "physicsEngine",
        ],
    )?;
    let mut p = SimulationProperties::default();
    let flag = |name: &str, v: &mut bool| -> ConfigResult<()> {
        if let Some(c) = r.at_most_one(el, name)? {
            *v = r.flag(c)?;
        }
        Ok(())
    };
    flag("showviewer", &mut p.show_viewer)?;
    flag("parallelcomputing", &mut p.parallel_computing)?;
    flag("storingdata", &mut p.storing_data)?;
    read_timing(r, el, &mut p)?;
    if let Some(c) = r.at_most_one(el, "duration")? {
        p.duration = r.f64_in(c, 0.0, 1e7)?;
    }
    if let Some(c) = r.at_most_one(el, "seed")? {
        let t = r.text(c)?;
        p.seed = t.trim().parse().map_err(|_| {
            r.err(
                c.text_pos,
                ErrorKind::InvalidValue,
                format!("<seed>: expected a whole number >= 0, found \"{t}\""),
            )
        })?;
    }
    if let Some(c) = r.at_most_one(el, "delay")? {
        p.delay_ms = r.f64_in(c, 0.0, 60_000.0)?;
    }
    if let Some(c) = r.at_most_one(el, "realtimefactor")? {
        p.realtime_factor = r.f64_in(c, 0.0, 1000.0)?;
    }
    if let Some(c) = r.at_most_one(el, "physicsengine")? {
        let t = r.text(c)?;
        p.engine = EngineKind::parse(t).ok_or_else(|| {
            r.err(
                c.text_pos,
                ErrorKind::InvalidValue,
                format!("unknown physics engine \"{t}\"; expected one of: rapier, mujoco"),
            )
        })?;
    }
    Ok(p)
}

/// The mode, the sampling period and the step width of `<simulationProperties>`.
fn read_timing(r: &Reader, el: &Element, p: &mut SimulationProperties) -> ConfigResult<()> {
    if let Some(c) = r.at_most_one(el, "mode")? {
        let t = r.text(c)?;
        p.mode = Mode::parse(t).ok_or_else(|| {
            let known: Vec<&str> = Mode::ALIASES.iter().map(|(m, _)| m.name()).collect();
            r.err(
                c.text_pos,
                ErrorKind::InvalidValue,
                format!(
                    "unknown mode \"{t}\"; expected one of: {}",
                    known.join(", ")
                ),
            )
        })?;
    }
    if let Some(c) = r.at_most_one(el, "accuracy")? {
        p.accuracy = r.u32(c)?;
        if p.accuracy == 0 {
            return Err(r.err(
                c.text_pos,
                ErrorKind::OutOfRange,
                "<accuracy> is a sampling period in steps; it must be at least 1",
            ));
        }
    }
    if let Some(c) = r.at_most_one(el, "stepwidth")? {
        let v = r.f64(c)?;
        if v >= 1.0 {
            return Err(r.err(
                c.text_pos,
                ErrorKind::OutOfRange,
                format!("<stepWidth> is {v} s; it is given in seconds (0.001 = 1 ms), at most {MAX_STEP_WIDTH}; did you write µs?"),
            ));
        }
        r.check_range(v, 1e-6, MAX_STEP_WIDTH, c.text_pos, "<stepWidth> (s)")?;
        p.step_width = v;
    }
    Ok(())
}

/// Reads a simulation file's text.
pub fn parse_simulation_file(file: &str, text: &str) -> ConfigResult<SimulationFile> {
    let (doc, r) = read_document(file, text, "simulation", "a simulation file")?;
    let root = &doc.root;
    r.only_children(
        root,
        &[
            "description",
            "robot",
            "actuation",
            "environment",
            "optimizer",
            "geneticAlgorithm",
            "greatDeluge",
            "simulationProperties",
        ],
    )?;
    r.only_attrs(root, &[])?;
    let mut optimizer = None;
    for name in ["optimizer", "geneticalgorithm", "greatdeluge"] {
        if let Some(c) = r.at_most_one(root, name)? {
            if optimizer.is_some() {
                return Err(r.err(
                    c.pos,
                    ErrorKind::InvalidValue,
                    "only one optimizer file per simulation",
                ));
            }
            optimizer = Some(file_ref(&r, c)?);
        }
    }
    let properties = match r.at_most_one(root, "simulationproperties")? {
        Some(p) => read_properties(&r, p)?,
        None => SimulationProperties::default(),
    };
    if properties.mode.is_optimization() && optimizer.is_none() {
        return Err(r.err(
            root.pos,
            ErrorKind::Missing,
            format!("mode \"{}\" needs an <optimizer> file", properties.mode),
        ));
    }
    Ok(SimulationFile {
        description: r.at_most_one(root, "description")?.map(|d| d.text.clone()),
        robot: file_ref(&r, r.required(root, "robot")?)?,
        actuation: file_ref(&r, r.required(root, "actuation")?)?,
        environment: r
            .at_most_one(root, "environment")?
            .map(|e| file_ref(&r, e))
            .transpose()?,
        optimizer,
        properties,
    })
}

/// Writes a simulation file.
pub fn write_simulation_file(s: &SimulationFile) -> String {
    let mut w = XmlWriter::new();
    w.open("simulation", &[]);
    if let Some(d) = &s.description {
        w.leaf("description", d);
    }
    w.leaf("robot", &s.robot.path);
    w.leaf("actuation", &s.actuation.path);
    if let Some(e) = &s.environment {
        w.leaf("environment", &e.path);
    }
    if let Some(o) = &s.optimizer {
        w.leaf("optimizer", &o.path);
    }
    let p = &s.properties;
    w.open("simulationProperties", &[]);
    w.flag("showViewer", p.show_viewer);
    w.flag("parallelComputing", p.parallel_computing);
    w.flag("storingData", p.storing_data);
    w.leaf("mode", p.mode.name());
    w.leaf("accuracy", &p.accuracy.to_string());
    w.num("stepWidth", p.step_width);
    w.num("duration", p.duration);
    w.leaf("seed", &p.seed.to_string());
    w.num("delay", p.delay_ms);
    w.num("realtimeFactor", p.realtime_factor);
    if p.engine != EngineKind::default() {
        w.leaf("physicsEngine", p.engine.name());
    }
    w.close();
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_engine(engine: &str) -> String {
        format!(
            "<simulation><robot>r.robot.xml</robot><actuation>a.actuation.xml</actuation>\
             <simulationProperties><physicsEngine>{engine}</physicsEngine></simulationProperties></simulation>"
        )
    }

    #[test]
    fn the_engine_is_read_written_and_read_again() {
        let f = parse_simulation_file("s.simulation.xml", &with_engine("MuJoCo")).unwrap();
        assert_eq!(f.properties.engine, EngineKind::Mujoco);
        let text = write_simulation_file(&f);
        assert!(
            text.contains("<physicsEngine>mujoco</physicsEngine>"),
            "{text}"
        );
        assert_eq!(parse_simulation_file("s.simulation.xml", &text).unwrap(), f);
        // rapier, the default, is not written.
        let rapier = parse_simulation_file("s.simulation.xml", &with_engine("rapier")).unwrap();
        assert!(!write_simulation_file(&rapier).contains("physicsEngine"));
    }

    #[test]
    fn an_unknown_element_names_the_known_ones_as_files_spell_them() {
        let text = "<simulation><robot>r.robot.xml</robot><actuation>a.actuation.xml</actuation>\
             <simulationProperties><stepwidht>0.001</stepwidht></simulationProperties></simulation>";
        let e = parse_simulation_file("s.simulation.xml", text)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("<stepwidht>") && e.contains("showViewer, ") && e.contains("stepWidth, "),
            "{e}"
        );
        let text = "<simulation><robt/></simulation>";
        let e = parse_simulation_file("s.simulation.xml", text)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("geneticAlgorithm, greatDeluge, simulationProperties"),
            "{e}"
        );
    }

    #[test]
    fn an_unknown_engine_is_a_located_error_naming_the_known_ones() {
        let e = parse_simulation_file("s.simulation.xml", &with_engine("bullet")).unwrap_err();
        let text = e.to_string();
        assert!(
            text.starts_with("s.simulation.xml:1:")
                && text.contains("\"bullet\"")
                && text.contains("rapier, mujoco"),
            "{text}"
        );
    }
}

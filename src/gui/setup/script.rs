//! Scripted driving of the configuration window, for GUI tests and the screenshots in
//! docs/: `proleg wizard --script FILE` runs one command per line (blank lines and `#`
//! comments ignored) while the window renders:
//!
//! ```text
//! wait 5                               # frames
//! wait-for file PATH 600               # until PATH exists (a test says its input was sent)
//! slow-frames 400                      # every frame takes 400 ms longer (a slow renderer)
//! tool wizard|expert|editor
//! set robot.topology pypyp             # a wizard field (see WizardField: its typed setter)
//! next | back | skip | save            # wizard navigation; save writes the files
//! add box [X Y]                        # a library item dropped at (X, Y) m (default 1 m ahead)
//! drop stairs 400 300                  # ... dropped at a window position (ray cast)
//! select 2 | select robot | select none
//! move-to X Y Z | move-by DX DY DZ | drag-to X Y
//! rotate 15 | yaw 90 | scale 2 [1 0.5] | friction 0.8 | dynamic on|off | mass 2
//! colour 1 0 0 | delete | undo | redo
//! env-save PATH | env-load PATH        # the standalone editor's file
//! expert robot|actuation|environment|optimizer PATH|none
//! expert-save PATH
//! expert-open PATH                     # the expert dialog's Open (a broken file: its error)
//! expert-edit                          # hand the composition to the wizard
//! preview                              # run the robot in the scene for 5 s
//! open-control PATH                    # "Open in control window" on this simulation file
//! zoom 3                               # height of the top and side views (m)
//! modules open | module-declare ... | module-compile   # see gui::module_editor::script
//! screenshot docs/wizard_robot.png
//! state out/state.txt                  # key = value lines
//! quit
//! ```
//!
//! A bad line stops the script with a message naming the file and line, and the window
//! closes with a failure status.

use std::path::{Path, PathBuf};

use clap::Subcommand;

use crate::gui::scripting::{OnOff, ScriptError, Xyz, finite};

/// One script command: the enum's variants are the script's words (`MoveTo` is
/// `move-to`), their fields its arguments in order.
#[derive(Subcommand, Debug, Clone, PartialEq)]
pub enum Command {
    /// `wait N`: N frames.
    Wait {
        /// Frames.
        frames: u32,
    },
    /// `tool wizard|expert|editor`.
    Tool {
        /// The tool.
        tool: ToolName,
    },
    /// `set FIELD VALUE...`: a wizard field (its typed setter).
    #[command(subcommand)]
    Set(WizardField),
    /// `next`: the next page.
    Next,
    /// `back`.
    Back,
    /// `skip`: leaves an optional page at its defaults.
    Skip,
    /// `save`: writes the wizard's files.
    Save,
    /// `add ITEM [X Y]`: a library item ahead of the robot or at X, Y.
    Add {
        /// The library item.
        item: String,
        /// x (m).
        #[arg(value_parser = finite, allow_negative_numbers = true, requires = "y")]
        x: Option<f64>,
        /// y (m).
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        y: Option<f64>,
    },
    /// `drop ITEM PX PY`: drops an item at a window position.
    Drop {
        /// The library item.
        item: String,
        /// Window x (pixels).
        px: f32,
        /// Window y (pixels).
        py: f32,
    },
    /// `select N|robot|none`.
    Select {
        /// An object number, `robot` or `none`.
        what: String,
    },
    /// `move-to X Y Z`.
    MoveTo(Xyz),
    /// `move-by DX DY DZ`.
    MoveBy(Xyz),
    /// `drag-to X Y`: drags the selection over the ground.
    DragTo {
        /// x (m).
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        x: f64,
        /// y (m).
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        y: f64,
    },
    /// `rotate DEG`.
    Rotate {
        /// Degrees.
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        degrees: f64,
    },
    /// `yaw DEG`: sets the heading.
    Yaw {
        /// Degrees.
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        degrees: f64,
    },
    /// `scale F` or `scale FX FY FZ`.
    Scale {
        /// The factor (along x with three).
        #[arg(value_parser = finite)]
        x: f64,
        /// Along y.
        #[arg(value_parser = finite, requires = "z")]
        y: Option<f64>,
        /// Along z.
        #[arg(value_parser = finite)]
        z: Option<f64>,
    },
    /// `friction MU`.
    Friction {
        /// The Coulomb coefficient.
        #[arg(value_parser = finite)]
        mu: f64,
    },
    /// `dynamic on|off`.
    Dynamic {
        /// On or off.
        state: OnOff,
    },
    /// `mass KG`.
    Mass {
        /// Kilograms.
        #[arg(value_parser = finite)]
        kg: f64,
    },
    /// `colour R G B` (`color` too).
    #[command(alias = "color")]
    Colour {
        /// Red (0..1).
        #[arg(value_parser = finite)]
        r: f64,
        /// Green (0..1).
        #[arg(value_parser = finite)]
        g: f64,
        /// Blue (0..1).
        #[arg(value_parser = finite)]
        b: f64,
    },
    /// `delete`.
    Delete,
    /// `undo`.
    Undo,
    /// `redo`.
    Redo,
    /// `env-save FILE`.
    EnvSave {
        /// The environment file.
        file: PathBuf,
    },
    /// `env-load FILE`.
    EnvLoad {
        /// The environment file.
        file: PathBuf,
    },
    /// `expert PART FILE|none`: a part of the composition.
    Expert {
        /// robot, actuation, environment or optimizer.
        part: String,
        /// The file, or `none`.
        file: String,
    },
    /// `expert-save FILE`.
    ExpertSave {
        /// The simulation file.
        file: PathBuf,
    },
    /// `expert-edit`: hands the composition to the wizard.
    ExpertEdit,
    /// `expert-open FILE`: the expert dialog's Open.
    ExpertOpen {
        /// The simulation file.
        file: PathBuf,
    },
    /// `slow-frames MS`: every frame takes this much longer.
    SlowFrames {
        /// Milliseconds (at most 10 000).
        #[arg(value_parser = clap::value_parser!(u32).range(0..=10_000))]
        ms: u32,
    },
    /// `wait-for file PATH FRAMES`: until the file exists, at most this many frames.
    #[command(subcommand)]
    WaitFor(WaitFor),
    /// `open-control FILE`: opens a simulation in a control window (a child process).
    OpenControl {
        /// The simulation file.
        file: PathBuf,
    },
    /// `preview`: runs the wizard's robot for 5 s.
    Preview,
    /// `zoom H`: height of the top and side views (m).
    Zoom {
        /// Metres.
        #[arg(value_parser = finite)]
        height: f64,
    },
    /// `screenshot FILE.png`.
    Screenshot {
        /// The image file.
        file: PathBuf,
    },
    /// `state FILE`: writes the state a test checks.
    State {
        /// The state file.
        file: PathBuf,
    },
    /// A module library command.
    #[command(flatten)]
    Module(crate::gui::module_editor::script::ModuleCommand),
    /// `quit`.
    Quit,
}

/// What `wait-for` waits for in this window.
#[derive(Subcommand, Debug, Clone, PartialEq)]
pub enum WaitFor {
    /// A file exists (a test says its input was sent).
    File {
        /// The file.
        path: PathBuf,
        /// At most this many frames.
        frames: u32,
    },
}

/// The tools of the configuration window.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ToolName {
    /// The wizard.
    Wizard,
    /// The expert dialog.
    Expert,
    /// The environment editor.
    Editor,
}

/// A wizard field `set` changes, with its value: each one a typed setter of
/// [`crate::compose::wizard::Wizard`] (or a plain field).
#[derive(Subcommand, Debug, Clone, PartialEq)]
pub enum WizardField {
    /// `robot.name NAME`.
    #[command(name = "robot.name")]
    RobotName {
        /// The name.
        name: String,
    },
    /// `robot.topology pypyp` (spaces allowed).
    #[command(name = "robot.topology")]
    Topology {
        /// Letters: p pitch, y yaw.
        #[arg(num_args = 0..)]
        letters: Vec<String>,
    },
    /// `robot.parts plain|touch|cube`.
    #[command(name = "robot.parts")]
    Parts {
        /// The part set.
        #[arg(value_parser = part_set)]
        parts: crate::compose::robot_builder::PartSet,
    },
    /// `robot.build`: the robot is built from the wizard's fields.
    #[command(name = "robot.build")]
    Build,
    /// `robot.existing FILE`: an existing robot file (relative to the configuration
    /// folder).
    #[command(name = "robot.existing")]
    Existing {
        /// The robot file.
        file: PathBuf,
    },
    /// `behaviour.simple MODULE`: one group of all joints.
    #[command(name = "behaviour.simple")]
    Simple {
        /// The module type.
        module: String,
    },
    /// `behaviour.clear`: no groups.
    #[command(name = "behaviour.clear")]
    ClearGroups,
    /// `behaviour.group MASK MODULE[,MODULE...]`.
    #[command(name = "behaviour.group")]
    Group {
        /// The joints (`10101`).
        mask: String,
        /// The module types, comma-separated.
        #[arg(value_delimiter = ',', required = true)]
        modules: Vec<String>,
    },
    /// `behaviour.param GROUP MODULE PARAM VALUE|v1,v2,...` (GROUP from 1).
    #[command(name = "behaviour.param")]
    GroupParam {
        /// The group (from 1).
        group: usize,
        /// The module type.
        module: String,
        /// The parameter.
        param: String,
        /// One value, or one per joint (comma-separated).
        #[arg(value_delimiter = ',', required = true, value_parser = finite, allow_negative_numbers = true)]
        values: Vec<f64>,
    },
    /// `sim.mode single|ga|gd|cmaes|mapelites`.
    #[command(name = "sim.mode")]
    Mode {
        /// The mode.
        mode: ModeName,
    },
    /// `sim.step S`.
    #[command(name = "sim.step")]
    Step {
        /// Seconds.
        #[arg(value_parser = finite)]
        seconds: f64,
    },
    /// `sim.accuracy N`: the sampling period in steps.
    #[command(name = "sim.accuracy")]
    Accuracy {
        /// Steps.
        steps: u32,
    },
    /// `sim.duration S`.
    #[command(name = "sim.duration")]
    Duration {
        /// Seconds.
        #[arg(value_parser = finite)]
        seconds: f64,
    },
    /// `sim.seed N`.
    #[command(name = "sim.seed")]
    Seed {
        /// The seed.
        seed: u64,
    },
    /// `sim.storing 0|1`: data files.
    #[command(name = "sim.storing")]
    Storing {
        /// 1: store data.
        #[arg(value_parser = clap::value_parser!(u8).range(0..=1))]
        on: u8,
    },
    /// `sim.viewer 0|1`.
    #[command(name = "sim.viewer")]
    Viewer {
        /// 1: show the viewer.
        #[arg(value_parser = clap::value_parser!(u8).range(0..=1))]
        on: u8,
    },
    /// `sim.description TEXT...`.
    #[command(name = "sim.description")]
    Description {
        /// The words.
        #[arg(num_args = 0.., allow_hyphen_values = true)]
        words: Vec<String>,
    },
    /// `opt.register MODULE PARAM all|MASK uniform|individual (LO HI INC | list v1,...)`.
    #[command(name = "opt.register")]
    Register {
        /// The module type.
        module: String,
        /// The parameter.
        param: String,
        /// `all` or a joint mask.
        joints: String,
        /// One value for all joints, or one per joint.
        sharing: Sharing,
        /// `LO HI INC`, or `list v1,v2,...`.
        #[arg(num_args = 2..=3, allow_negative_numbers = true)]
        values: Vec<String>,
    },
    /// `opt.clear`: no registered parameters.
    #[command(name = "opt.clear")]
    ClearRegistrations,
    /// `opt.popsize N`.
    #[command(name = "opt.popsize")]
    Popsize {
        /// Candidates per generation.
        size: u32,
    },
    /// `opt.max-evals N`.
    #[command(name = "opt.max-evals")]
    MaxEvals {
        /// Evaluations.
        #[arg(value_parser = clap::value_parser!(u64).range(1..))]
        evaluations: u64,
    },
    /// `opt.morphology MIN MAX pitch,yaw plain,touch [--motif K]`: the body is searched
    /// too, within these ranges.
    #[command(name = "opt.morphology")]
    Morphology {
        /// Fewest modules.
        min: u32,
        /// Most modules.
        max: u32,
        /// The joint orientations allowed, comma-separated (one word: a list after it would
        /// take the part sets too).
        #[arg(required = true, num_args = 1, value_delimiter = ',', value_parser = orientation)]
        orientations: Vec<crate::config::robot_builder::Orientation>,
        /// The part sets allowed, comma-separated.
        #[arg(required = true, num_args = 1, value_delimiter = ',', value_parser = part_set)]
        parts: Vec<crate::compose::robot_builder::PartSet>,
        /// Repeat a motif of K orientations along the chain.
        #[arg(long)]
        motif: Option<u32>,
    },
    /// `opt.fixed-body`: the body is not searched.
    #[command(name = "opt.fixed-body")]
    FixedBody,
    /// `opt.fitness NAME`.
    #[command(name = "opt.fitness")]
    Fitness {
        /// The fitness.
        #[arg(value_parser = crate::config::fitness::Fitness::parse)]
        fitness: crate::config::fitness::Fitness,
    },
}

/// The modes `sim.mode` names.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeName {
    /// One run.
    Single,
    /// The genetic algorithm.
    Ga,
    /// The great deluge.
    Gd,
    /// CMA-ES.
    Cmaes,
    /// MAP-Elites.
    Mapelites,
}

impl ModeName {
    /// The simulation mode.
    pub fn mode(self) -> crate::config::simulation::Mode {
        use crate::config::simulation::Mode;
        match self {
            ModeName::Single => Mode::SingleRun,
            ModeName::Ga => Mode::GeneticAlgorithm,
            ModeName::Gd => Mode::GreatDeluge,
            ModeName::Cmaes => Mode::CmaEs,
            ModeName::Mapelites => Mode::MapElites,
        }
    }
}

/// One value for all joints or one per joint.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sharing {
    /// One value.
    Uniform,
    /// One per joint.
    Individual,
}

/// A part set by name.
fn part_set(
    s: &str,
) -> Result<crate::compose::robot_builder::PartSet, crate::config::error::UnknownName> {
    crate::compose::robot_builder::PartSet::parse(s).ok_or_else(|| {
        crate::config::error::UnknownName::new("part set", s, &["plain", "touch", "cube"])
    })
}

fn orientation(
    s: &str,
) -> Result<crate::config::robot_builder::Orientation, crate::config::error::UnknownName> {
    use crate::config::robot_builder::Orientation;
    match s.trim().to_ascii_lowercase().as_str() {
        "pitch" | "p" => Ok(Orientation::Pitch),
        "yaw" | "y" => Ok(Orientation::Yaw),
        _ => Err(crate::config::error::UnknownName::new(
            "orientation",
            s,
            &["pitch", "yaw"],
        )),
    }
}

/// A parsed script of this window's commands.
pub type Script = crate::gui::scripting::Script<Command>;

/// The script being run by the window, if any.
#[derive(bevy::prelude::Resource, Debug, Clone, Default)]
pub struct SetupScript(pub Option<Script>);

/// Reads a script file.
pub fn load(path: &Path) -> Result<Script, ScriptError> {
    crate::gui::scripting::load_script(path)
}

/// Parses script text (`path` names it in errors).
pub fn parse(path: &Path, text: &str) -> Result<Script, ScriptError> {
    crate::gui::scripting::parse_script(path, text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// clap's own checks of the commands' arguments (which only debug builds run when a
    /// line is parsed: a positional list before another one failed there, not in release).
    #[test]
    fn the_command_definitions_pass_claps_checks() {
        <Command as clap::Subcommand>::augment_subcommands(clap::Command::new("script"))
            .debug_assert();
    }

    #[test]
    fn parses_commands_and_locates_errors() {
        let s = parse(
            Path::new("w.script"),
            "tool editor\nset robot.topology py py\nadd box 1 -2\nscale 2\nscale 1 2 3 # axes\ndrop sphere 10 20\nset behaviour.param 1 M Amplitude 10,-5\nquit\n",
        )
        .unwrap();
        assert_eq!(s.commands.len(), 8);
        assert_eq!(
            s.commands[1].1,
            Command::Set(WizardField::Topology {
                letters: vec!["py".into(), "py".into()]
            })
        );
        assert_eq!(
            s.commands[2].1,
            Command::Add {
                item: "box".into(),
                x: Some(1.0),
                y: Some(-2.0)
            }
        );
        assert_eq!(
            s.commands[3].1,
            Command::Scale {
                x: 2.0,
                y: None,
                z: None
            }
        );
        assert_eq!(
            s.commands[6].1,
            Command::Set(WizardField::GroupParam {
                group: 1,
                module: "M".into(),
                param: "Amplitude".into(),
                values: vec![10.0, -5.0]
            })
        );
        let at = |text: &str| match parse(Path::new("w.script"), text) {
            Err(ScriptError::Parse { line, why, .. }) => (line, why),
            other => panic!("{text:?} parsed: {other:?}"),
        };
        let (line, why) = at("next\nfriction lots\n");
        assert!(line == 2 && why.contains("lots"), "{why}");
        assert_eq!(at("fly\n").0, 1);
        // A wizard field that does not exist, and a part set that does not.
        assert!(at("set robot.colour red\n").1.contains("robot.colour"));
        assert!(at("set robot.parts gold\n").1.contains("gold"));
        // Two scale factors are neither one nor three.
        assert_eq!(at("scale 1 2\n").0, 1);
    }
}

//! Scripted driving of the control window, for GUI tests and the screenshots in docs/:
//! `proleg gui CONFIG --script FILE` runs one command per line (blank lines and `#`
//! comments ignored) while the window renders:
//!
//! ```text
//! wait 5                         # frames
//! start | pause | restart
//! keep-tuned                     # after a restart: the tuned parameter values back
//! continue                       # after a run paused by itself (its duration, a robot
//!                                # that left the world): the message's Continue
//! load CONFIG                    # the toolbar's Load (a broken file: its error, the world kept)
//! run-until 3.0                  # runs (paced) and pauses exactly at this simulated second
//! wait-for running|paused|debug|calibrated 600   # until the state holds (e.g. after a real key press
//!                                # from xdotool), at most this many frames
//! wait-for file PATH 600         # until PATH exists (a test says its input was sent)
//! step-to 10                     # step, paused, to exactly this simulated second
//! speed 0                        # real-time factor (0: as fast as possible)
//! slow-frames 350                # every frame takes 350 ms longer (a slow renderer)
//! set PatternGenerator_sinusoidal Amplitude 20 [JOINT]   # JOINT as in the robot file: 1 = J1
//! plot Robot_Data/y_pos Sinus_Generator/Angle[2]   # a live plot of these series
//! panel params|plots|all|none    # which docked views are open
//! debug on|off                   # the physics debug view
//! per-joint 0 Amplitude on       # properties dialog: a slider per joint for a parameter
//! select-link 0                  # select a robot link, as a click does
//! move-by 0.5 0 0                # move the selection (metres, z up), as a drag does
//! inspect out/demo.data.xml Robot_Data/y_pos   # data file inspection with a graph
//! optimize 8 [STORE]            # run the optimization mode for 8 evaluations (stored in
//!                                # STORE, default CONFIG-STEM.results.sqlite), wait
//! save-best F.actuation.xml      # the view's Save best
//! attach postgres://u@h/db 30     # follow the store's latest unfinished run read-only,
//!                                # wait for 30 evaluations (or the run's end)
//! replay-best                    # show the best candidate in the viewer
//! results STORE                  # the optimization window lists the store's runs
//! replay STORE RUN N|best [EP]   # a stored evaluation (episode EP of a robust run)
//! remote open|close              # the remote control dialog
//! remote-set LeftStickX 1        # a gamepad element's value, as if the pad sent it
//! remote-bind RightStickX rate PatternGenerator_sinusoidal Phase_Difference all 20
//! remote-remove 0                # binding N (from 0)
//! remote-load F.remote.xml | remote-save F.remote.xml
//! modules open | module-declare ... | module-compile   # see gui::module_editor::script
//! assign MODULE 10101            # add a module on these joints (rebuilds the world)
//! weights 1 FILE.safetensors     # actuator 1 (a Policy) runs this network (rebuilds)
//! robot open|close               # the real-robot tab
//! robot-connect PORT             # connect to the servos on PORT (e.g. an emulator's pty)
//! robot-torque on|off | robot-drive on|off | robot-twin on|off | robot-disconnect
//! robot-calibrate out/sweep.data.xml  # calibrate the servos on a recording (background)
//! screenshot docs/control_window.png
//! record on [FILE] | record off   # the Record button: the window's frames (default file:
//!                                # out/recordings/NAME-TIME.mp4)
//! state out/state.txt            # the app state as key = value lines
//! quit
//! ```
//!
//! A bad line stops the script with a message naming the file and line, and the window
//! closes with a failure status.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Subcommand;

use crate::data::export::SeriesSelector;
use crate::gui::scripting::{OnOff, OpenClose, ScriptError, Xyz, finite};

/// One script command: the enum's variants are the script's words (`RunUntil` is
/// `run-until`), their fields its arguments in order.
#[derive(Subcommand, Debug, Clone, PartialEq)]
pub enum Command {
    /// `wait N`: N frames.
    Wait {
        /// Frames.
        frames: u32,
    },
    /// `start`.
    Start,
    /// `pause`.
    Pause,
    /// `restart`.
    Restart,
    /// `continue`: the Continue of a run that paused by itself.
    Continue,
    /// `keep-tuned`: the toolbar's "Keep tuned values" after a restart.
    KeepTuned,
    /// `load FILE`: the toolbar's Load.
    Load {
        /// The simulation file.
        file: PathBuf,
    },
    /// `engine rapier|mujoco`: the toolbar's physics choice.
    Engine {
        /// The engine.
        kind: crate::config::simulation::EngineKind,
    },
    /// `run-until S`: runs until simulated second S.
    RunUntil {
        /// Simulated seconds.
        #[arg(value_parser = finite)]
        seconds: f64,
    },
    /// `wait-for running|paused|debug|calibrated FRAMES` or `wait-for file PATH FRAMES`.
    #[command(subcommand)]
    WaitFor(WaitFor),
    /// `step-to S`: step, paused, to exactly this simulated time (seconds, to the step): a
    /// replay's episode ends where the optimization's did.
    StepTo {
        /// Simulated seconds.
        #[arg(value_parser = finite)]
        seconds: f64,
    },
    /// Real-time factor (0: as fast as possible).
    Speed {
        /// The factor.
        #[arg(value_parser = finite)]
        factor: f64,
    },
    /// `slow-frames MS`: every frame takes this much longer.
    SlowFrames {
        /// Milliseconds (at most 10 000).
        #[arg(value_parser = clap::value_parser!(u32).range(0..=10_000))]
        ms: u32,
    },
    /// `set MODULE PARAM VALUE [JOINT]`: a module parameter (joint from 1).
    Set {
        /// Module type.
        module: String,
        /// Parameter.
        param: String,
        /// New value.
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        value: f64,
        /// Joint (from 1), or all.
        joint: Option<usize>,
    },
    /// Series as `proleg data` selects them: `Handler/series`, `[k]` or `[a..b]` (from 0).
    Plot {
        /// The series.
        #[arg(required = true, value_parser = SeriesSelector::parse)]
        series: Vec<SeriesSelector>,
    },
    /// `record on [FILE]` or `record off`: the Record button.
    #[command(subcommand)]
    Record(Record),
    /// `panel params|plots|all|none`.
    Panel {
        /// Which docked views are open.
        which: Panel,
    },
    /// `per-joint TAB PARAM on|off`: a parameter of module tab TAB per joint or not.
    PerJoint {
        /// Module tab.
        actuator: usize,
        /// Parameter.
        param: String,
        /// Per joint or uniform.
        state: OnOff,
    },
    /// `debug on|off`: the physics debug view.
    Debug {
        /// On or off.
        state: OnOff,
    },
    /// `select-link N`: select robot link N (from 0) as a click would.
    SelectLink {
        /// The link.
        link: usize,
    },
    /// `move-by DX DY DZ`: move the selection by these metres, as a drag would.
    MoveBy(Xyz),
    /// `inspect FILE SERIES...`: the data file inspection on a file with a graph of these
    /// series.
    Inspect {
        /// The data file.
        file: PathBuf,
        /// The series.
        #[arg(required = true, value_parser = SeriesSelector::parse)]
        series: Vec<SeriesSelector>,
    },
    /// `optimize N [STORE]`: the optimization mode for N evaluations; waits for it.
    Optimize {
        /// Evaluations.
        #[arg(value_parser = clap::value_parser!(u64).range(1..))]
        evaluations: u64,
        /// The store (default CONFIG-STEM.results.sqlite).
        store: Option<String>,
    },
    /// `save-best FILE`: the optimization view's Save best.
    SaveBest {
        /// The actuation file.
        file: PathBuf,
    },
    /// `results STORE`: open the optimization window and list the store's runs.
    Results {
        /// The store.
        store: String,
    },
    /// `replay STORE RUN N|best [EP]`: a stored evaluation (episode EP of a robust run).
    Replay {
        /// The store (a path or a postgres:// URL).
        store: String,
        /// The run's id.
        run: i64,
        /// Which evaluation.
        #[arg(value_parser = crate::optimize::replay::Which::parse)]
        which: crate::optimize::replay::Which,
        /// The episode of a robust run.
        episode: Option<u32>,
    },
    /// `attach STORE N`: follow the store's latest unfinished run (read-only) until N of its
    /// evaluations are drawn (or the run ends).
    Attach {
        /// The store.
        store: String,
        /// Evaluations to wait for.
        evaluations: u64,
    },
    /// `replay-best`: the best candidate found, in the viewer.
    ReplayBest,
    /// `remote open|close`: the remote control dialog.
    Remote {
        /// Open or close.
        state: OpenClose,
    },
    /// `remote-set ELEMENT VALUE`: a gamepad element's value, as if the pad sent it.
    RemoteSet {
        /// The element.
        element: String,
        /// Its value.
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        value: f64,
    },
    /// `remote-bind ELEMENT MODE MODULE PARAM JOINTS SCALE`: adds a binding.
    RemoteBind {
        /// Remote element.
        element: String,
        /// How it changes the parameter.
        #[arg(value_parser = bind_mode)]
        mode: crate::config::remote::BindMode,
        /// Module type.
        module: String,
        /// Parameter.
        parameter: String,
        /// Which joints.
        #[arg(value_parser = joint_selection)]
        joints: crate::config::remote::JointSelection,
        /// Change per unit.
        #[arg(value_parser = finite, allow_negative_numbers = true)]
        scale: f64,
    },
    /// `remote-remove I`: removes binding I (from 0).
    RemoteRemove {
        /// The binding.
        index: usize,
    },
    /// `remote-load FILE`.
    RemoteLoad {
        /// The remote file.
        file: PathBuf,
    },
    /// `remote-save FILE`.
    RemoteSave {
        /// The remote file.
        file: PathBuf,
    },
    /// A module library command.
    #[command(flatten)]
    Module(crate::gui::module_editor::script::ModuleCommand),
    /// `assign MODULE MASK`: adds a module on the masked joints.
    Assign {
        /// Module type.
        module: String,
        /// Joint mask (`10101`).
        mask: String,
    },
    /// `weights ACTUATOR FILE`: a Policy actuator's weights file.
    Weights {
        /// The actuator (from 0, in the actuation file's order).
        actuator: usize,
        /// The weights file (.safetensors).
        file: PathBuf,
    },
    /// `robot open|close`: the real-robot tab.
    Robot {
        /// Open or close.
        state: OpenClose,
    },
    /// `robot-connect PORT`.
    RobotConnect {
        /// The serial port.
        port: String,
    },
    /// `robot-torque on|off`.
    RobotTorque {
        /// On or off.
        state: OnOff,
    },
    /// `robot-drive on|off`: the kernel drives the servos.
    RobotDrive {
        /// On or off.
        state: OnOff,
    },
    /// `robot-twin on|off`: the viewer's robot follows the servos.
    RobotTwin {
        /// On or off.
        state: OnOff,
    },
    /// `robot-disconnect`.
    RobotDisconnect,
    /// `robot-calibrate FILE`: calibrate the servo model on a recording (in the
    /// background; `wait` for it).
    RobotCalibrate {
        /// The recording.
        file: PathBuf,
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
    /// `quit`.
    Quit,
}

/// What a `wait-for` waits for.
#[derive(Subcommand, Debug, Clone, PartialEq)]
pub enum WaitFor {
    /// The simulation runs.
    Running {
        /// At most this many frames.
        frames: u32,
    },
    /// The simulation is paused.
    Paused {
        /// At most this many frames.
        frames: u32,
    },
    /// The physics debug view is on.
    Debug {
        /// At most this many frames.
        frames: u32,
    },
    /// The real-robot tab's calibration has ended (with a result or an error).
    Calibrated {
        /// At most this many frames.
        frames: u32,
    },
    /// A file exists (a test says its input was sent).
    File {
        /// The file.
        path: PathBuf,
        /// At most this many frames.
        frames: u32,
    },
}

/// `record on [FILE]` or `record off`.
#[derive(Subcommand, Debug, Clone, PartialEq)]
pub enum Record {
    /// Start recording (default file: out/recordings/NAME-TIME.mp4).
    On {
        /// The video file.
        file: Option<PathBuf>,
    },
    /// Stop recording.
    Off,
}

/// Which docked views `panel` opens.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum Panel {
    /// The parameters.
    Params,
    /// The plots.
    Plots,
    /// Both.
    All,
    /// Neither.
    None,
}

/// A binding mode by name.
fn bind_mode(
    s: &str,
) -> Result<crate::config::remote::BindMode, crate::config::error::UnknownName> {
    crate::config::remote::BindMode::parse(s).ok_or_else(|| {
        crate::config::error::UnknownName::new(
            "binding mode",
            s,
            &["rate", "absolute", "increment", "decrement", "toggle"],
        )
    })
}

/// A joint selection by name or mask.
fn joint_selection(
    s: &str,
) -> Result<crate::config::remote::JointSelection, crate::config::error::UnknownName> {
    crate::config::remote::JointSelection::parse(s).ok_or_else(|| {
        crate::config::error::UnknownName::new(
            "joint selection",
            s,
            &["all", "pitch", "yaw", "a 0/1 mask"],
        )
    })
}

/// A parsed script of this window's commands.
pub type Script = crate::gui::scripting::Script<Command>;

/// Reads a script file.
pub fn load(path: &Path) -> Result<Script, ScriptError> {
    crate::gui::scripting::load_script(path)
}

/// Parses script text (`path` names it in errors).
pub fn parse(path: &Path, text: &str) -> Result<Script, ScriptError> {
    crate::gui::scripting::parse_script(path, text)
}

/// Key = value lines of the state a test checks.
pub fn state_report(pairs: &[(&str, String)]) -> String {
    let mut out = String::new();
    for (k, v) in pairs {
        let _ = writeln!(out, "{k} = {v}");
    }
    out
}

/// The script being run by the window, if any.
#[derive(bevy::prelude::Resource, Debug, Clone, Default)]
pub struct ScriptRunner(pub Option<Script>);

impl ScriptRunner {
    /// A runner of `script`.
    pub fn new(script: Script) -> Self {
        ScriptRunner(Some(script))
    }
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
    fn parses_every_command_and_locates_errors() {
        let s = parse(
            Path::new("t.script"),
            "wait 3\nstart # go\n\nrun-until 1.5\nset Sinus_Generator Amplitude 20 2\nplot Robot_Data/y_pos A/Angle[2]\npanel plots\nscreenshot a.png\nstate s.txt\npause\nrestart\nquit\n",
        )
        .unwrap();
        assert_eq!(s.commands.len(), 11);
        assert_eq!(s.commands[0], (1, Command::Wait { frames: 3 }));
        assert_eq!(s.commands[2], (4, Command::RunUntil { seconds: 1.5 }));
        assert_eq!(
            s.commands[3].1,
            Command::Set {
                module: "Sinus_Generator".into(),
                param: "Amplitude".into(),
                value: 20.0,
                joint: Some(2)
            }
        );
        let at = |text: &str| match parse(Path::new("t.script"), text) {
            Err(ScriptError::Parse { line, why, .. }) => (line, why),
            other => panic!("{text:?} parsed: {other:?}"),
        };
        let (line, why) = at("start\nfly 3\n");
        assert!(line == 2 && why.contains("fly"), "{why}");
        let (line, why) = at("run-until soon\n");
        assert!(line == 1 && why.contains("soon"), "{why}");
        assert!(at("set A B NaN\n").1.contains("NaN"));
        // A toggle's word is checked: `debug of` is no `debug off`.
        let (line, why) = at("start\ndebug of\n");
        assert!(line == 2 && why.contains("on, off"), "{why}");
        assert!(at("remote opne\n").1.contains("open, close"));
        // Negative numbers are numbers, not options.
        let s = parse(Path::new("t.script"), "move-by -0.5 0 1e-3\n").unwrap();
        assert_eq!(
            s.commands[0].1,
            Command::MoveBy(Xyz {
                x: -0.5,
                y: 0.0,
                z: 1e-3
            })
        );
    }

    #[test]
    fn plot_series_are_data_selectors() {
        let s = parse(
            Path::new("p.script"),
            "plot Robot_Data/y_pos M/Angle[0..2]\n",
        )
        .unwrap();
        let Command::Plot { series: sel } = &s.commands[0].1 else {
            panic!("not a plot: {:?}", s.commands[0]);
        };
        assert_eq!(sel.len(), 2);
        assert_eq!(sel[1].parts, Some((0, 2)));
        let e = parse(Path::new("p.script"), "wait 1\nplot nohandler\n").unwrap_err();
        assert!(matches!(e, ScriptError::Parse { line: 2, .. }), "{e}");
    }
}

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
//! wait-for running|paused|debug 600   # until the state holds (e.g. after a real key press
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
//! robot open|close               # the real-robot tab
//! robot-connect PORT             # connect to the servos on PORT (e.g. an emulator's pty)
//! robot-torque on|off | robot-drive on|off | robot-twin on|off | robot-disconnect
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

use crate::data::export::SeriesSelector;

/// One script command.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `wait N`: N frames.
    Wait(u32),
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
    Load(PathBuf),
    /// `engine rapier|mujoco`: the toolbar's physics choice.
    Engine(crate::config::simulation::EngineKind),
    /// `run-until S`: runs until simulated second S.
    RunUntil(f64),
    /// `wait-for STATE FRAMES`: until `running`, `paused` or `debug` holds, or
    /// (`file:PATH`) the file exists.
    WaitFor(String, u32),
    /// `step-to S`: step, paused, to exactly this simulated time (seconds, to the step): a replay's
    /// episode ends where the optimization's did.
    StepTo(f64),
    /// Real-time factor (0: as fast as possible).
    Speed(f64),
    /// `slow-frames MS`: every frame takes this much longer.
    SlowFrames(u32),
    /// `set MODULE PARAM VALUE [JOINT]`: a module parameter (joint from 1).
    Set {
        /// Module type.
        module: String,
        /// Parameter.
        param: String,
        /// New value.
        value: f64,
        /// Joint (from 1), or all.
        joint: Option<usize>,
    },
    /// Series as `proleg data` selects them: `Handler/series`, `[k]` or `[a..b]` (from 0).
    Plot(Vec<SeriesSelector>),
    /// `record on [FILE]` (`Some`, with the file if given) or `record off` (`None`).
    Record(Option<Option<PathBuf>>),
    /// `panel params|plots|all`.
    Panel(String),
    /// Show a parameter of module tab N per joint (individual mode) or not.
    PerJoint {
        /// Module tab.
        actuator: usize,
        /// Parameter.
        param: String,
        /// Per joint or uniform.
        on: bool,
    },
    /// Turn the physics debug view on or off.
    Debug(bool),
    /// Select robot link N (from 0) as a click would.
    SelectLink(usize),
    /// Move the selection by (dx, dy, dz) metres, as a drag would.
    MoveBy([f64; 3]),
    /// Open the data file inspection on a file and add a graph of these series.
    Inspect(PathBuf, Vec<SeriesSelector>),
    /// Run the simulation's optimization for this many evaluations and wait for it.
    Optimize(u64, Option<String>),
    /// `save-best FILE`: the optimization view's Save best.
    SaveBest(PathBuf),
    /// `results STORE`: open the optimization window and list the store's runs.
    Results(String),
    /// `replay STORE RUN N|best [EP]`: a stored evaluation: store, run, evaluation (or best), episode of a robust run.
    Replay {
        /// The store (a path or a postgres:// URL).
        store: String,
        /// The run's id.
        run: i64,
        /// Which evaluation.
        which: crate::optimize::replay::Which,
        /// The episode of a robust run.
        episode: Option<u32>,
    },
    /// Attach the optimization view to the store's latest unfinished run (read-only) and
    /// wait until this many of its evaluations are drawn (or the run ends).
    Attach(String, u64),
    /// Replay the best candidate found in the viewer.
    ReplayBest,
    /// Open or close the remote control dialog.
    Remote(bool),
    /// Set a remote element's value (standing in for the gamepad).
    RemoteSet(String, f64),
    /// Add a binding: element, mode, module, parameter, joints, scale.
    RemoteBind {
        /// Remote element.
        element: String,
        /// How it changes the parameter.
        mode: crate::config::remote::BindMode,
        /// Module type.
        module: String,
        /// Parameter.
        parameter: String,
        /// Which joints.
        joints: crate::config::remote::JointSelection,
        /// Change per unit.
        scale: f64,
    },
    /// `remote-remove I`: removes binding I.
    RemoteRemove(usize),
    /// `remote-load FILE`.
    RemoteLoad(PathBuf),
    /// `remote-save FILE`.
    RemoteSave(PathBuf),
    /// A module library command.
    Module(crate::gui::module_editor::script::ModuleCommand),
    /// `assign MODULE MASK`: adds a module on the masked joints.
    Assign(String, String),
    /// The real-robot tab: open/close, connect, torque, drive, twin, disconnect.
    RobotOpen(bool),
    /// `robot-connect PORT`.
    RobotConnect(String),
    /// `robot-torque on|off`.
    RobotTorque(bool),
    /// `robot-drive on|off`: the kernel drives the servos.
    RobotDrive(bool),
    /// `robot-twin on|off`: the viewer's robot follows the servos.
    RobotTwin(bool),
    /// `robot-disconnect`.
    RobotDisconnect,
    /// `screenshot FILE.png`.
    Screenshot(PathBuf),
    /// `state FILE`: writes the state a test checks.
    State(PathBuf),
    /// `quit`.
    Quit,
}

/// A parsed script of this window's commands.
pub type Script = crate::gui::scripting::Script<Command>;

/// Reads a script file.
pub fn load(path: &Path) -> Result<Script, String> {
    crate::gui::scripting::load_script(path, parse)
}

/// Parses script text (`path` names it in errors).
pub fn parse(path: &Path, text: &str) -> Result<Script, String> {
    crate::gui::scripting::parse_script(path, text, |line, words, at| {
        let num = |w: Option<&&str>, what: &str| -> Result<f64, String> {
            let w = w.ok_or_else(|| at(format!("{line:?}: missing {what}")))?;
            w.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| at(format!("{w:?} is not a number ({what})")))
        };
        if let Some(m) = crate::gui::module_editor::script::parse(words) {
            return Ok(Command::Module(m));
        }
        match run_command(words, &num, at)? {
            Some(c) => Ok(c),
            None => view_command(words, &num, at),
        }
    })
}

/// Whether `w` is `yes` (true) or `no` (false); any other word is an error naming it
/// (`debug of` is not `debug off`).
fn switch(w: &str, (yes, no): (&str, &str), at: &dyn Fn(String) -> String) -> Result<bool, String> {
    match w {
        _ if w == yes => Ok(true),
        _ if w == no => Ok(false),
        other => Err(at(format!("{other:?}: expected {yes} or {no}"))),
    }
}

/// `on` or `off`.
fn on_off(w: &str, at: &dyn Fn(String) -> String) -> Result<bool, String> {
    switch(w, ("on", "off"), at)
}

/// The commands that run, pace and tune the simulation (none: not one of them).
fn run_command(
    words: &[&str],
    num: &NumberOf<'_>,
    at: &dyn Fn(String) -> String,
) -> Result<Option<Command>, String> {
    Ok(Some(match words[0] {
        "wait" => Command::Wait(num(words.get(1), "frames")?.max(0.0) as u32),
        "start" => Command::Start,
        "pause" => Command::Pause,
        "restart" => Command::Restart,
        "continue" => Command::Continue,
        "keep-tuned" => Command::KeepTuned,
        "load" if words.len() == 2 => Command::Load(PathBuf::from(words[1])),
        "engine" if words.len() == 2 => Command::Engine(
            crate::config::simulation::EngineKind::parse(words[1]).ok_or_else(|| {
                at(format!(
                    "unknown physics engine `{}` (rapier, mujoco)",
                    words[1]
                ))
            })?,
        ),
        "run-until" => Command::RunUntil(num(words.get(1), "seconds")?),
        "wait-for" if words.len() == 4 && words[1] == "file" => Command::WaitFor(
            format!("file:{}", words[2]),
            num(words.get(3), "frames")?.max(1.0) as u32,
        ),
        "wait-for" if words.len() == 3 && ["running", "paused", "debug"].contains(&words[1]) => {
            Command::WaitFor(
                words[1].to_string(),
                num(words.get(2), "frames")?.max(1.0) as u32,
            )
        }
        "step-to" => Command::StepTo(num(words.get(1), "seconds")?),
        "speed" => Command::Speed(num(words.get(1), "real-time factor")?.max(0.0)),
        "slow-frames" => {
            Command::SlowFrames(num(words.get(1), "milliseconds")?.clamp(0.0, 10_000.0) as u32)
        }
        "set" => {
            if words.len() < 4 {
                return Err(at("set MODULE PARAM VALUE [JOINT]".into()));
            }
            Command::Set {
                module: words[1].to_string(),
                param: words[2].to_string(),
                value: num(words.get(3), "value")?,
                joint: match words.get(4) {
                    Some(_) => Some(num(words.get(4), "joint")? as usize),
                    None => None,
                },
            }
        }
        _ => return Ok(None),
    }))
}

/// The commands of the views, the optimization view, the devices and quitting.
fn view_command(
    words: &[&str],
    num: &NumberOf<'_>,
    at: &dyn Fn(String) -> String,
) -> Result<Command, String> {
    Ok(match words[0] {
        "plot" if words.len() > 1 => Command::Plot(
            words[1..]
                .iter()
                .map(|w| SeriesSelector::parse(w).map_err(&at))
                .collect::<Result<_, _>>()?,
        ),
        "panel" if words.len() == 2 => Command::Panel(words[1].to_string()),
        "debug" if words.len() == 2 => Command::Debug(on_off(words[1], at)?),
        "per-joint" if words.len() == 4 => Command::PerJoint {
            actuator: num(words.get(1), "module tab")?.max(0.0) as usize,
            param: words[2].to_string(),
            on: on_off(words[3], at)?,
        },
        "select-link" => Command::SelectLink(num(words.get(1), "link")?.max(0.0) as usize),
        "move-by" => Command::MoveBy([
            num(words.get(1), "dx")?,
            num(words.get(2), "dy")?,
            num(words.get(3), "dz")?,
        ]),
        "inspect" if words.len() > 2 => Command::Inspect(
            PathBuf::from(words[1]),
            words[2..]
                .iter()
                .map(|w| SeriesSelector::parse(w).map_err(&at))
                .collect::<Result<_, _>>()?,
        ),
        "screenshot" if words.len() == 2 => Command::Screenshot(PathBuf::from(words[1])),
        "record" if words.get(1) == Some(&"on") && words.len() <= 3 => {
            Command::Record(Some(words.get(2).map(PathBuf::from)))
        }
        "record" if words.len() == 2 && words[1] == "off" => Command::Record(None),
        "state" if words.len() == 2 => Command::State(PathBuf::from(words[1])),
        "optimize" if words.len() <= 3 => Command::Optimize(
            num(words.get(1), "evaluations")?.max(1.0) as u64,
            words.get(2).map(|s| s.to_string()),
        ),
        "save-best" if words.len() == 2 => Command::SaveBest(PathBuf::from(words[1])),
        "attach" if words.len() == 3 => Command::Attach(
            words[1].to_string(),
            num(words.get(2), "evaluations")?.max(0.0) as u64,
        ),
        "replay-best" => Command::ReplayBest,
        "results" if words.len() == 2 => Command::Results(words[1].to_string()),
        "replay" if (4..=5).contains(&words.len()) => Command::Replay {
            store: words[1].to_string(),
            run: num(words.get(2), "run")? as i64,
            which: crate::optimize::replay::Which::parse(words[3])
                .map_err(|e| at(e.to_string()))?,
            episode: match words.get(4) {
                Some(_) => Some(num(words.get(4), "episode")?.max(0.0) as u32),
                None => None,
            },
        },
        w if w.starts_with("remote") || w.starts_with("robot") => device_command(words, &num, at)?,
        "assign" if words.len() == 3 => Command::Assign(words[1].to_string(), words[2].to_string()),
        "quit" => Command::Quit,
        other => return Err(at(format!("unknown or incomplete command {other:?}"))),
    })
}

/// Reads word `w` as a finite number (`what` names it in the error).
type NumberOf<'a> = dyn Fn(Option<&&str>, &str) -> Result<f64, String> + 'a;

/// The remote dialog's and the real-robot tab's commands (`remote*`, `robot*`).
fn device_command(
    words: &[&str],
    num: &NumberOf<'_>,
    at: &dyn Fn(String) -> String,
) -> Result<Command, String> {
    Ok(match words[0] {
        "remote" if words.len() == 2 => Command::Remote(switch(words[1], ("open", "close"), at)?),
        "remote-set" if words.len() == 3 => {
            Command::RemoteSet(words[1].to_string(), num(words.get(2), "value")?)
        }
        "remote-bind" if words.len() == 7 => Command::RemoteBind {
            element: words[1].to_string(),
            mode: crate::config::remote::BindMode::parse(words[2]).ok_or_else(|| {
                at(format!(
                    "mode {:?}: rate, absolute, increment, decrement or toggle",
                    words[2]
                ))
            })?,
            module: words[3].to_string(),
            parameter: words[4].to_string(),
            joints: crate::config::remote::JointSelection::parse(words[5]).ok_or_else(|| {
                at(format!(
                    "joints {:?}: all, pitch, yaw or a 0/1 mask",
                    words[5]
                ))
            })?,
            scale: num(words.get(6), "scale")?,
        },
        "remote-remove" => Command::RemoteRemove(num(words.get(1), "binding")?.max(0.0) as usize),
        "remote-load" if words.len() == 2 => Command::RemoteLoad(PathBuf::from(words[1])),
        "remote-save" if words.len() == 2 => Command::RemoteSave(PathBuf::from(words[1])),
        "robot" if words.len() == 2 => Command::RobotOpen(switch(words[1], ("open", "close"), at)?),
        "robot-connect" if words.len() == 2 => Command::RobotConnect(words[1].to_string()),
        "robot-torque" if words.len() == 2 => Command::RobotTorque(on_off(words[1], at)?),
        "robot-drive" if words.len() == 2 => Command::RobotDrive(on_off(words[1], at)?),
        "robot-twin" if words.len() == 2 => Command::RobotTwin(on_off(words[1], at)?),
        "robot-disconnect" => Command::RobotDisconnect,
        other => return Err(at(format!("unknown or incomplete command {other:?}"))),
    })
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

    #[test]
    fn parses_every_command_and_locates_errors() {
        let s = parse(
            Path::new("t.script"),
            "wait 3\nstart # go\n\nrun-until 1.5\nset Sinus_Generator Amplitude 20 2\nplot Robot_Data/y_pos A/Angle[2]\npanel plots\nscreenshot a.png\nstate s.txt\npause\nrestart\nquit\n",
        )
        .unwrap();
        assert_eq!(s.commands.len(), 11);
        assert_eq!(s.commands[0], (1, Command::Wait(3)));
        assert_eq!(s.commands[2], (4, Command::RunUntil(1.5)));
        assert_eq!(
            s.commands[3].1,
            Command::Set {
                module: "Sinus_Generator".into(),
                param: "Amplitude".into(),
                value: 20.0,
                joint: Some(2)
            }
        );
        let e = parse(Path::new("t.script"), "start\nfly 3\n").unwrap_err();
        assert!(e.starts_with("t.script:2:"), "{e}");
        let e = parse(Path::new("t.script"), "run-until soon\n").unwrap_err();
        assert!(e.contains("t.script:1:") && e.contains("soon"), "{e}");
        let e = parse(Path::new("t.script"), "set A B NaN\n").unwrap_err();
        assert!(e.contains("NaN"), "{e}");
        // A toggle's word is checked: `debug of` is no `debug off`.
        let e = parse(Path::new("t.script"), "start\ndebug of\n").unwrap_err();
        assert!(
            e.contains("t.script:2:") && e.contains("expected on or off"),
            "{e}"
        );
        let e = parse(Path::new("t.script"), "remote opne\n").unwrap_err();
        assert!(e.contains("expected open or close"), "{e}");
    }

    #[test]
    fn plot_series_are_data_selectors() {
        let s = parse(
            Path::new("p.script"),
            "plot Robot_Data/y_pos M/Angle[0..2]\n",
        )
        .unwrap();
        let Command::Plot(sel) = &s.commands[0].1 else {
            panic!("not a plot: {:?}", s.commands[0]);
        };
        assert_eq!(sel.len(), 2);
        assert_eq!(sel[1].parts, Some((0, 2)));
        let e = parse(Path::new("p.script"), "wait 1\nplot nohandler\n").unwrap_err();
        assert!(e.starts_with("p.script:2:"), "{e}");
    }
}

//! Scripted driving of the configuration window, for GUI tests and the screenshots in
//! docs/: `proleg wizard --script FILE` runs one command per line (blank lines and `#`
//! comments ignored) while the window renders:
//!
//! ```text
//! wait 5                               # frames
//! wait-for file PATH 600               # until PATH exists (a test says its input was sent)
//! slow-frames 400                      # every frame takes 400 ms longer (a slow renderer)
//! tool wizard|expert|editor
//! set robot.topology pypyp             # any wizard field (see compose::wizard::Wizard::set)
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

/// One script command.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `wait N`: N frames.
    Wait(u32),
    /// `tool wizard|expert|editor`.
    Tool(String),
    /// `set KEY VALUE`: a wizard field (`Wizard::set`).
    Set(String, String),
    /// `next`: the next page.
    Next,
    /// `back`.
    Back,
    /// `skip`: leaves an optional page at its defaults.
    Skip,
    /// `save`: writes the wizard's files.
    Save,
    /// `add ITEM [X Y]`: a library item ahead of the robot or at X, Y.
    Add(String, Option<[f64; 2]>),
    /// `drop ITEM PX PY`: drops an item at a window position.
    Drop(String, [f32; 2]),
    /// `select N|robot|none`.
    Select(String),
    /// `move-to X Y Z`.
    MoveTo([f64; 3]),
    /// `move-by DX DY DZ`.
    MoveBy([f64; 3]),
    /// `drag-to X Y`: drags the selection over the ground.
    DragTo([f64; 2]),
    /// `rotate DEG`.
    Rotate(f64),
    /// `yaw DEG`: sets the heading.
    Yaw(f64),
    /// `scale FX FY FZ`.
    Scale([f64; 3]),
    /// `friction MU`.
    Friction(f64),
    /// `dynamic on|off`.
    Dynamic(bool),
    /// `mass KG`.
    Mass(f64),
    /// `colour R G B`.
    Colour([f64; 3]),
    /// `delete`.
    Delete,
    /// `undo`.
    Undo,
    /// `redo`.
    Redo,
    /// `env-save FILE`.
    EnvSave(PathBuf),
    /// `env-load FILE`.
    EnvLoad(PathBuf),
    /// `expert PART FILE|none`: a part of the composition.
    Expert(String, String),
    /// `expert-save FILE`.
    ExpertSave(PathBuf),
    /// `expert-edit`: hands the composition to the wizard.
    ExpertEdit,
    /// `expert-open FILE`: the expert dialog's Open.
    ExpertOpen(PathBuf),
    /// `slow-frames MS`: every frame takes this much longer.
    SlowFrames(u32),
    /// `wait-for file PATH FRAMES`: until the file exists, at most this many frames.
    WaitForFile(PathBuf, u32),
    /// `open-control FILE`: opens a simulation in a control window (a child process).
    OpenControl(PathBuf),
    /// `preview`: runs the wizard's robot for 5 s.
    Preview,
    /// `zoom H`: height of the top and side views (m).
    Zoom(f32),
    /// `screenshot FILE.png`.
    Screenshot(PathBuf),
    /// `state FILE`: writes the state a test checks.
    State(PathBuf),
    /// A module library command.
    Module(crate::gui::module_editor::script::ModuleCommand),
    /// `quit`.
    Quit,
}

/// A parsed script of this window's commands.
pub type Script = crate::gui::scripting::Script<Command>;

/// The script being run by the window, if any.
#[derive(bevy::prelude::Resource, Debug, Clone, Default)]
pub struct SetupScript(pub Option<Script>);

/// Reads a script file.
pub fn load(path: &Path) -> Result<Script, String> {
    crate::gui::scripting::load_script(path, parse)
}

/// Parses script text (`path` names it in errors).
pub fn parse(path: &Path, text: &str) -> Result<Script, String> {
    crate::gui::scripting::parse_script(path, text, |line, words, at| {
        let num = |k: usize, what: &str| -> Result<f64, String> {
            let w = words
                .get(k)
                .ok_or_else(|| at(format!("{line:?}: missing {what}")))?;
            w.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| at(format!("{w:?} is not a number ({what})")))
        };
        let arg = |k: usize, what: &str| -> Result<String, String> {
            words
                .get(k)
                .map(|w| w.to_string())
                .ok_or_else(|| at(format!("{line:?}: missing {what}")))
        };
        let rest = |k: usize| words.get(k..).map(|w| w.join(" ")).unwrap_or_default();
        if let Some(m) = crate::gui::module_editor::script::parse(words) {
            return Ok(Command::Module(m));
        }
        let c = match words[0] {
            "wait" => Command::Wait(num(1, "frames")?.max(0.0) as u32),
            "slow-frames" => {
                Command::SlowFrames(num(1, "milliseconds")?.clamp(0.0, 10_000.0) as u32)
            }
            "wait-for" if words.len() == 4 && words[1] == "file" => {
                Command::WaitForFile(PathBuf::from(words[2]), num(3, "frames")?.max(1.0) as u32)
            }
            "tool" => Command::Tool(arg(1, "wizard, expert or editor")?),
            "set" => Command::Set(arg(1, "field")?, rest(2)),
            "next" => Command::Next,
            "back" => Command::Back,
            "skip" => Command::Skip,
            "save" => Command::Save,
            "add" => Command::Add(
                arg(1, "library item")?,
                if words.len() > 2 {
                    Some([num(2, "x")?, num(3, "y")?])
                } else {
                    None
                },
            ),
            "drop" => Command::Drop(
                arg(1, "library item")?,
                [num(2, "window x")? as f32, num(3, "window y")? as f32],
            ),
            "select" => Command::Select(arg(1, "object number, robot or none")?),
            "move-to" => Command::MoveTo([num(1, "x")?, num(2, "y")?, num(3, "z")?]),
            "move-by" => Command::MoveBy([num(1, "dx")?, num(2, "dy")?, num(3, "dz")?]),
            "drag-to" => Command::DragTo([num(1, "x")?, num(2, "y")?]),
            "rotate" => Command::Rotate(num(1, "degrees")?),
            "yaw" => Command::Yaw(num(1, "degrees")?),
            "scale" => {
                let x = num(1, "factor")?;
                if words.len() > 2 {
                    Command::Scale([x, num(2, "y factor")?, num(3, "z factor")?])
                } else {
                    Command::Scale([x; 3])
                }
            }
            "friction" => Command::Friction(num(1, "coefficient")?),
            "dynamic" => Command::Dynamic(arg(1, "on or off")? == "on"),
            "mass" => Command::Mass(num(1, "kg")?),
            "colour" | "color" => {
                Command::Colour([num(1, "red")?, num(2, "green")?, num(3, "blue")?])
            }
            "delete" => Command::Delete,
            "undo" => Command::Undo,
            "redo" => Command::Redo,
            "env-save" => Command::EnvSave(PathBuf::from(arg(1, "path")?)),
            "env-load" => Command::EnvLoad(PathBuf::from(arg(1, "path")?)),
            "expert" => Command::Expert(arg(1, "part")?, arg(2, "path or none")?),
            "expert-save" => Command::ExpertSave(PathBuf::from(arg(1, "path")?)),
            "expert-edit" => Command::ExpertEdit,
            "expert-open" => Command::ExpertOpen(PathBuf::from(arg(1, "path")?)),
            "preview" => Command::Preview,
            "open-control" => Command::OpenControl(PathBuf::from(arg(1, "path")?)),
            "zoom" => Command::Zoom(num(1, "view height (m)")? as f32),
            "screenshot" => Command::Screenshot(PathBuf::from(arg(1, "path")?)),
            "state" => Command::State(PathBuf::from(arg(1, "path")?)),
            "quit" => Command::Quit,
            other => return Err(at(format!("unknown command {other:?}"))),
        };
        Ok(c)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_commands_and_locates_errors() {
        let s = parse(
            Path::new("w.script"),
            "tool editor\nset robot.topology py py\nadd box 1 2\nscale 2\nscale 1 2 3 # axes\ndrop sphere 10 20\nquit\n",
        )
        .unwrap();
        assert_eq!(s.commands.len(), 7);
        assert_eq!(
            s.commands[1].1,
            Command::Set("robot.topology".into(), "py py".into())
        );
        assert_eq!(s.commands[3].1, Command::Scale([2.0; 3]));
        assert_eq!(s.commands[4].1, Command::Scale([1.0, 2.0, 3.0]));
        let e = parse(Path::new("w.script"), "next\nfriction lots\n").unwrap_err();
        assert!(e.starts_with("w.script:2:") && e.contains("lots"), "{e}");
        let e = parse(Path::new("w.script"), "fly\n").unwrap_err();
        assert!(e.starts_with("w.script:1:"), "{e}");
    }
}

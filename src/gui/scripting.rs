//! What the scripts of both windows share: the parsed script (commands with their
//! lines, located parse errors), frames left of a `wait`, and screenshots asked of Bevy
//! that the script waits for until the file is written. Each window defines its own
//! commands (`control::script`, `setup::script`).

use std::path::PathBuf;

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};

/// Frames to wait for a screenshot file before giving up.
pub const SHOT_FRAMES: u32 = 600;

/// A script's pauses.
#[derive(Debug, Clone, Default)]
pub struct ScriptPauses {
    /// Frames left of a `wait`.
    pub waiting: u32,
    /// A screenshot being written: path and frames waited for it.
    pub pending_shot: Option<(PathBuf, u32)>,
    /// Frames a `wait-for` has polled its condition.
    pub polls: u32,
    /// Wall time added to every frame while the script runs (`slow-frames MS`: a test's
    /// stand-in for a slow renderer).
    pub frame_delay: std::time::Duration,
}

impl ScriptPauses {
    /// Whether the script waits this frame; an error when a screenshot never appeared.
    pub fn hold(&mut self) -> Result<bool, String> {
        if self.waiting > 0 {
            self.waiting -= 1;
            return Ok(true);
        }
        if let Some((path, waited)) = self.pending_shot.as_mut() {
            if !path.exists() && *waited < SHOT_FRAMES {
                *waited += 1;
                return Ok(true);
            }
            let missing = !path.exists();
            let shot = path.display().to_string();
            self.pending_shot = None;
            if missing {
                return Err(format!("screenshot {shot} was not written"));
            }
        }
        Ok(false)
    }

    /// One frame of a `wait-for`: go on once `holds`, else poll again next frame, for at
    /// most `frames` frames (then an error naming `what`).
    pub fn poll(&mut self, holds: bool, frames: u32, what: &str) -> Result<Flow, String> {
        self.polls += 1;
        if holds {
            self.polls = 0;
            Ok(Flow::Next)
        } else if self.polls > frames {
            Err(format!("waited {frames} frames for {what}"))
        } else {
            Ok(Flow::Again)
        }
    }

    /// Asks for a screenshot of the window into `path`; the script waits for the file.
    pub fn screenshot(&mut self, commands: &mut Commands, path: PathBuf) {
        crate::gui::control::widgets::ensure_parent(&path);
        let _ = std::fs::remove_file(&path);
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path.clone()));
        self.pending_shot = Some((path, 0));
    }
}

/// A parsed script: its commands with their line numbers, the next one to run, its
/// pauses, and the file (named in errors).
#[derive(Debug, Clone)]
pub struct Script<C> {
    /// The commands with their line numbers.
    pub commands: Vec<(usize, C)>,
    /// The next command to carry out.
    pub next: usize,
    /// Waits and screenshots in progress.
    pub pacing: ScriptPauses,
    /// The script file, named in errors.
    pub file: PathBuf,
}

impl<C> Default for Script<C> {
    fn default() -> Self {
        Script {
            commands: Vec::new(),
            next: 0,
            pacing: ScriptPauses::default(),
            file: PathBuf::new(),
        }
    }
}

/// Parses script text: one command per line, `#` comments and blank lines skipped.
/// `command` turns a line (and its words) into a command; the function it is given
/// prefixes a message with `FILE:LINE:`.
pub fn parse_script<C>(
    path: &std::path::Path,
    text: &str,
    command: impl Fn(&str, &[&str], &dyn Fn(String) -> String) -> Result<C, String>,
) -> Result<Script<C>, String> {
    let mut commands = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let at = |msg: String| format!("{}:{}: {msg}", path.display(), i + 1);
        let words: Vec<&str> = line.split_whitespace().collect();
        commands.push((i + 1, command(line, &words, &at)?));
    }
    Ok(Script {
        commands,
        file: path.to_path_buf(),
        ..Script::default()
    })
}

/// Reads a script file and parses it with `parse`.
pub fn load_script<C>(
    path: &std::path::Path,
    parse: fn(&std::path::Path, &str) -> Result<Script<C>, String>,
) -> Result<Script<C>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(path, &text)
}

/// What a command leaves the script to do.
pub enum Flow {
    /// Go on with the next command this frame.
    Next,
    /// Come back to this command next frame.
    Again,
    /// The command is done; wait for the next frame before going on.
    Yield,
    /// Close the window with success.
    Quit,
}

/// Carries out the commands of the script in `slot` this frame, until one waits: a
/// failing command prints `error: FILE:LINE: cause` and closes the window with a failure;
/// `quit` closes it with success. Either ends the script (`slot` becomes `None`).
pub fn run_commands<C: Clone>(
    slot: &mut Option<Script<C>>,
    exit: &mut MessageWriter<AppExit>,
    mut carry_out: impl FnMut(C, &mut Script<C>) -> Result<Flow, String>,
) {
    let Some(script) = slot.as_mut() else {
        return;
    };
    if !script.pacing.frame_delay.is_zero() {
        std::thread::sleep(script.pacing.frame_delay);
    }
    let outcome = match script.pacing.hold() {
        Ok(true) => return,
        Ok(false) => step_commands(script, &mut carry_out),
        Err(e) => Err(format!("{}: {e}", script.file.display())),
    };
    match outcome {
        Ok(false) => {}
        Ok(true) => {
            exit.write(AppExit::Success);
            *slot = None;
        }
        Err(e) => {
            eprintln!("error: {e}");
            exit.write(AppExit::error());
            *slot = None;
        }
    }
}

/// Runs commands until one waits (`Ok(false)`) or quits (`Ok(true)`); an error names the
/// file and line.
fn step_commands<C: Clone>(
    script: &mut Script<C>,
    carry_out: &mut impl FnMut(C, &mut Script<C>) -> Result<Flow, String>,
) -> Result<bool, String> {
    while let Some((line, c)) = script.commands.get(script.next).cloned() {
        let flow =
            carry_out(c, script).map_err(|e| format!("{}:{line}: {e}", script.file.display()))?;
        match flow {
            Flow::Next => script.next += 1,
            Flow::Again => return Ok(false),
            Flow::Yield => {
                script.next += 1;
                return Ok(false);
            }
            Flow::Quit => return Ok(true),
        }
    }
    Ok(false)
}

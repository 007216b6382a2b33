//! What the scripts of both windows share: the parsed script (commands with their
//! lines, located parse errors), frames left of a `wait`, and screenshots asked of Bevy
//! that the script waits for until the file is written. Each window defines its own
//! commands as a clap-derived enum (`control::script`, `setup::script`): a line's words
//! are parsed as a command line is, so an unknown word or a bad value is an error naming
//! the file and line.

use std::path::PathBuf;

use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};

pub use crate::gui::error::{CommandError, NotFinite, ScriptError};

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
    pub fn hold(&mut self) -> Result<bool, CommandError> {
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
            let shot = path.clone();
            self.pending_shot = None;
            if missing {
                return Err(CommandError::NoScreenshot(shot));
            }
        }
        Ok(false)
    }

    /// One frame of a `wait-for`: go on once `holds`, else poll again next frame, for at
    /// most `frames` frames (then an error naming `what`).
    pub fn poll(&mut self, holds: bool, frames: u32, what: &str) -> Result<Flow, CommandError> {
        self.polls += 1;
        if holds {
            self.polls = 0;
            Ok(Flow::Next)
        } else if self.polls > frames {
            Err(CommandError::Timeout {
                frames,
                what: what.to_string(),
            })
        } else {
            Ok(Flow::Again)
        }
    }

    /// Asks for a screenshot of the window into `path`; the script waits for the file.
    pub fn screenshot(
        &mut self,
        commands: &mut Commands,
        path: PathBuf,
    ) -> Result<(), CommandError> {
        crate::gui::control::widgets::ensure_parent(&path);
        // An old file would pass for the new one: it goes first.
        match std::fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(source) => return Err(CommandError::Write { path, source }),
        }
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path.clone()));
        self.pending_shot = Some((path, 0));
        Ok(())
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

/// A script line's words as a command of `C`: clap parses them as it parses a command
/// line (`C`'s variants are the script's words, their fields its arguments).
#[derive(clap::Parser, Debug)]
#[command(
    no_binary_name = true,
    disable_help_flag = true,
    disable_help_subcommand = true,
    disable_version_flag = true
)]
struct Line<C: clap::Subcommand> {
    #[command(subcommand)]
    command: C,
}

/// Parses script text: one command per line, `#` comments and blank lines skipped; an
/// error names the file and line.
pub fn parse_script<C: clap::Subcommand>(
    path: &std::path::Path,
    text: &str,
) -> Result<Script<C>, ScriptError> {
    use clap::Parser as _;
    let mut commands = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let parsed =
            Line::<C>::try_parse_from(line.split_whitespace()).map_err(|e| ScriptError::Parse {
                file: path.to_path_buf(),
                line: i + 1,
                why: clap_message(&e),
            })?;
        commands.push((i + 1, parsed.command));
    }
    Ok(Script {
        commands,
        file: path.to_path_buf(),
        ..Script::default()
    })
}

/// Clap's message on one line, without its usage and help hints.
fn clap_message(e: &clap::Error) -> String {
    e.render()
        .to_string()
        .lines()
        .map(str::trim)
        .filter(|l| {
            !l.is_empty() && !l.starts_with("Usage:") && !l.starts_with("For more information")
        })
        .collect::<Vec<_>>()
        .join(" ")
        .trim_start_matches("error: ")
        .to_string()
}

/// Reads a script file and parses it.
pub fn load_script<C: clap::Subcommand>(path: &std::path::Path) -> Result<Script<C>, ScriptError> {
    let text = std::fs::read_to_string(path).map_err(|source| ScriptError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_script(path, &text)
}

/// A finite number (scripts refuse NaN and infinities).
pub fn finite(text: &str) -> Result<f64, NotFinite> {
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| NotFinite(text.to_string()))
}

/// Three finite numbers: a position or a displacement (metres, z up).
#[derive(clap::Args, Debug, Clone, Copy, PartialEq)]
pub struct Xyz {
    /// Along x.
    #[arg(value_parser = finite, allow_negative_numbers = true)]
    pub x: f64,
    /// Along y.
    #[arg(value_parser = finite, allow_negative_numbers = true)]
    pub y: f64,
    /// Along z.
    #[arg(value_parser = finite, allow_negative_numbers = true)]
    pub z: f64,
}

impl Xyz {
    /// As an array.
    pub fn array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}

/// `on` or `off`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
}

impl OnOff {
    /// Whether on.
    pub fn on(self) -> bool {
        self == OnOff::On
    }
}

/// `open` or `close`.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenClose {
    /// Open.
    Open,
    /// Close.
    Close,
}

impl OpenClose {
    /// Whether open.
    pub fn open(self) -> bool {
        self == OpenClose::Open
    }
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
    mut carry_out: impl FnMut(C, &mut Script<C>) -> Result<Flow, CommandError>,
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
        Err(source) => Err(ScriptError::Command {
            file: script.file.clone(),
            line: script.commands.get(script.next).map_or(0, |c| c.0),
            source: Box::new(source),
        }),
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
    carry_out: &mut impl FnMut(C, &mut Script<C>) -> Result<Flow, CommandError>,
) -> Result<bool, ScriptError> {
    while let Some((line, c)) = script.commands.get(script.next).cloned() {
        let flow = carry_out(c, script).map_err(|source| ScriptError::Command {
            file: script.file.clone(),
            line,
            source: Box::new(source),
        })?;
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

//! The module library's script commands, shared by both windows' scripts:
//!
//! ```text
//! modules open|close             # the module library window
//! module-workspace DIR           # plugin workspace for new modules (libraries in DIR/lib)
//! module-declare NAME amplitude=30:0..90 data=phase,angle helpers=smooth
//! module-source FILE             # the editor's text from FILE, as if typed
//! module-compile                 # Compile, and wait for the build to finish
//! ```

use std::path::PathBuf;

use crate::gui::module_editor::{ModuleEditor, ParamRow, Status};
use crate::plugin_host::template::ParamDecl;

/// One module-library command.
#[derive(Debug, Clone, PartialEq)]
pub enum ModuleCommand {
    /// `modules open|close`: shows or hides the window.
    Open(bool),
    /// `module-workspace DIR`: the plugin workspace to use.
    Workspace(PathBuf),
    /// Name, `name=value[:min..max]` parameters, data series, helpers (comma-separated).
    Declare {
        /// Module name.
        name: String,
        /// Parameter declarations (`name=initial[:min..max]`).
        params: Vec<String>,
        /// Data series, comma-separated.
        series: String,
        /// Helper functions, comma-separated.
        helpers: String,
    },
    /// `module-source FILE`: replaces the editor's text with the file.
    Source(PathBuf),
    /// `module-compile`: builds and loads; waits for the build.
    Compile,
}

/// The command of a script line's words, or `None` when the line is not one of these.
pub fn parse(words: &[&str]) -> Option<ModuleCommand> {
    Some(match words {
        ["modules", which] => ModuleCommand::Open(*which == "open"),
        ["module-workspace", dir] => ModuleCommand::Workspace(PathBuf::from(dir)),
        ["module-declare", name, rest @ ..] => {
            let mut params = Vec::new();
            let (mut series, mut helpers) = (String::new(), String::new());
            for w in rest {
                if let Some(d) = w.strip_prefix("data=") {
                    series = d.to_string();
                } else if let Some(h) = w.strip_prefix("helpers=") {
                    helpers = h.to_string();
                } else {
                    params.push(w.to_string());
                }
            }
            ModuleCommand::Declare {
                name: name.to_string(),
                params,
                series,
                helpers,
            }
        }
        ["module-source", file] => ModuleCommand::Source(PathBuf::from(file)),
        ["module-compile"] => ModuleCommand::Compile,
        _ => return None,
    })
}

/// Carries out a command; `Ok(false)` asks to be called again next frame (a build).
pub fn run(editor: &mut ModuleEditor, command: ModuleCommand) -> Result<bool, String> {
    match command {
        ModuleCommand::Open(open) => editor.open = open,
        ModuleCommand::Workspace(dir) => editor.use_workspace(&dir),
        ModuleCommand::Declare {
            name,
            params,
            series,
            helpers,
        } => {
            let form = &mut editor.form;
            form.name = name;
            form.params = params
                .iter()
                .map(|p| {
                    ParamDecl::parse(p).map(|d| ParamRow {
                        name: d.name,
                        initial: d.initial,
                        min: d.min,
                        max: d.max,
                    })
                })
                .collect::<Result<_, _>>()?;
            form.series = series;
            form.helpers = helpers;
            editor.declare()?;
        }
        ModuleCommand::Source(path) => {
            editor.source =
                std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            editor.modified = true;
        }
        ModuleCommand::Compile => match editor.awaited_build {
            None => {
                editor.awaited_build = Some(editor.builds);
                editor.compile()?;
                return Ok(false);
            }
            Some(before) => {
                editor.poll();
                if editor.builds <= before {
                    return Ok(false);
                }
                editor.awaited_build = None;
            }
        },
    }
    Ok(true)
}

/// The editor's state as key = value pairs for a script's state file.
pub fn state_pairs(editor: &ModuleEditor) -> Vec<(&'static str, String)> {
    vec![
        ("module_builds", editor.builds.to_string()),
        (
            "module_crate",
            editor.crate_name.clone().unwrap_or_default(),
        ),
        ("module_loaded", editor.last_loaded.join(",")),
        (
            "module_status",
            match &editor.status {
                Status::None => String::new(),
                Status::Info(s) => format!("info: {s}"),
                Status::Error(s) => format!("error: {s}"),
            },
        ),
        (
            "module_log_errors",
            editor
                .log
                .lines()
                .filter(|l| l.starts_with("error"))
                .count()
                .to_string(),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_parse_into_module_commands() {
        assert_eq!(parse(&["modules", "open"]), Some(ModuleCommand::Open(true)));
        assert_eq!(
            parse(&["module-declare", "G", "a=1", "data=p,q", "helpers=h"]),
            Some(ModuleCommand::Declare {
                name: "G".into(),
                params: vec!["a=1".into()],
                series: "p,q".into(),
                helpers: "h".into(),
            })
        );
        assert_eq!(parse(&["module-compile"]), Some(ModuleCommand::Compile));
        assert_eq!(parse(&["module-source"]), None);
        assert_eq!(parse(&["start"]), None);
    }
}

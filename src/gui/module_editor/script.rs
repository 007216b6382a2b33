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
use crate::gui::scripting::OpenClose;
use crate::plugin_host::error::PluginError;
use crate::plugin_host::template::ParamDecl;

/// One module-library command (the words of both windows' scripts that start with
/// `module`).
#[derive(clap::Subcommand, Debug, Clone, PartialEq)]
pub enum ModuleCommand {
    /// `modules open|close`: shows or hides the window.
    Modules {
        /// Open or close.
        state: OpenClose,
    },
    /// `module-workspace DIR`: the plugin workspace to use.
    ModuleWorkspace {
        /// The workspace.
        dir: PathBuf,
    },
    /// `module-declare NAME [name=value[:min..max]]... [data=a,b] [helpers=f,g]`.
    ModuleDeclare {
        /// Module name.
        name: String,
        /// Parameter declarations, `data=` series and `helpers=` functions.
        #[arg(allow_hyphen_values = true)]
        items: Vec<String>,
    },
    /// `module-source FILE`: replaces the editor's text with the file.
    ModuleSource {
        /// The source file.
        file: PathBuf,
    },
    /// `module-compile`: builds and loads; waits for the build.
    ModuleCompile,
}

/// A declaration's items: parameter declarations, the data series and the helpers
/// (comma-separated).
fn declaration_items(items: &[String]) -> (Vec<&str>, String, String) {
    let mut params = Vec::new();
    let (mut series, mut helpers) = (String::new(), String::new());
    for w in items {
        if let Some(d) = w.strip_prefix("data=") {
            series = d.to_string();
        } else if let Some(h) = w.strip_prefix("helpers=") {
            helpers = h.to_string();
        } else {
            params.push(w.as_str());
        }
    }
    (params, series, helpers)
}

/// Carries out a command; `Ok(false)` asks to be called again next frame (a build).
pub fn run(editor: &mut ModuleEditor, command: ModuleCommand) -> Result<bool, PluginError> {
    match command {
        ModuleCommand::Modules { state } => editor.open = state.open(),
        ModuleCommand::ModuleWorkspace { dir } => editor.use_workspace(&dir),
        ModuleCommand::ModuleDeclare { name, items } => {
            let (params, series, helpers) = declaration_items(&items);
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
        ModuleCommand::ModuleSource { file } => {
            editor.source =
                std::fs::read_to_string(&file).map_err(PluginError::io("reading", &file))?;
            editor.modified = true;
        }
        ModuleCommand::ModuleCompile => match editor.awaited_build {
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
    fn a_declaration_splits_parameters_series_and_helpers() {
        let items: Vec<String> = ["a=1", "data=p,q", "b=-2:-5..5", "helpers=h"]
            .map(String::from)
            .to_vec();
        let (params, series, helpers) = declaration_items(&items);
        assert_eq!(params, ["a=1", "b=-2:-5..5"]);
        assert_eq!((series.as_str(), helpers.as_str()), ("p,q", "h"));
    }
}

//! `proleg plugin new | build | list`: the user module library from the command line.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::plugin_host::build::{PluginBuildOptions, build};
use crate::plugin_host::error::PluginError;
use crate::plugin_host::template::{Declaration, ParamDecl};
use crate::plugin_host::{self, PluginHost, ScanReport};
use clap::Subcommand;

/// The `proleg plugin` subcommands.
#[derive(Subcommand)]
pub enum PluginCommand {
    /// Make a new plugin crate in the plugin workspace from a declaration.
    New {
        /// The module's registry name (letters, digits, _), e.g. MyGait.
        name: String,
        /// A parameter: NAME=VALUE or NAME=VALUE:MIN..MAX (repeatable).
        #[arg(long = "param")]
        params: Vec<String>,
        /// A logged data series (repeatable).
        #[arg(long = "data")]
        series: Vec<String>,
        /// A helper function to generate (repeatable).
        #[arg(long = "helper")]
        helpers: Vec<String>,
        /// One line describing the module.
        #[arg(long, default_value = "")]
        summary: String,
        /// The plugin workspace.
        #[arg(long, default_value = "plugins")]
        workspace: PathBuf,
    },
    /// Compile plugin crates (one, or all) and put the libraries in the user library.
    Build {
        /// A plugin crate (package or folder name); all when omitted.
        name: Option<String>,
        /// The plugin workspace.
        #[arg(long, default_value = "plugins")]
        workspace: PathBuf,
        /// The library folder the libraries go to.
        #[arg(long, default_value = plugin_host::DEFAULT_LIBRARY)]
        lib: PathBuf,
        /// Cargo's target folder.
        #[arg(long, default_value = "target/plugins")]
        target_dir: PathBuf,
    },
    /// The library folders, the loaded plugin modules and the skipped libraries.
    List,
}

/// Runs a plugin command; `startup` is the scan made when proleg started.
pub fn run(
    command: PluginCommand,
    host: &mut PluginHost,
    startup: &ScanReport,
) -> Result<String, PluginError> {
    match command {
        PluginCommand::New {
            name,
            params,
            series,
            helpers,
            summary,
            workspace,
        } => {
            let decl = Declaration {
                name,
                summary,
                params: params
                    .iter()
                    .map(|p| ParamDecl::parse(p))
                    .collect::<Result<_, _>>()?,
                helpers,
                series,
            };
            let folder = decl.create(&workspace)?;
            Ok(format!(
                "created {} (module {}); write its step in {}, then: proleg plugin build {}\n",
                folder.display(),
                decl.name,
                folder.join("src/lib.rs").display(),
                decl.crate_name()
            ))
        }
        PluginCommand::Build {
            name,
            workspace,
            lib,
            target_dir,
        } => {
            let outcome = build(&PluginBuildOptions {
                workspace,
                package: name,
                target_dir,
                lib_dir: lib.clone(),
            })?;
            if !outcome.success {
                return Err(PluginError::BuildFailed(outcome.log));
            }
            let mut out = String::new();
            for l in &outcome.libraries {
                match host.load_file(l) {
                    Ok(Some(info)) => {
                        let _ = writeln!(
                            out,
                            "built {} -> module {}",
                            l.display(),
                            info.descriptor.type_name
                        );
                    }
                    Ok(None) => {
                        let _ = writeln!(out, "built {} (unchanged)", l.display());
                    }
                    Err(e) => return Err(PluginError::DoesNotLoad(e)),
                }
            }
            if !plugin_host::library_dirs()
                .iter()
                .any(|d| same_dir(d, &lib))
            {
                let _ = writeln!(
                    out,
                    "note: {} is not a library folder of this proleg; add it to {}",
                    lib.display(),
                    plugin_host::ENV_VAR
                );
            }
            Ok(out)
        }
        PluginCommand::List => Ok(list(host, startup)),
    }
}

fn same_dir(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

fn list(host: &PluginHost, startup: &ScanReport) -> String {
    let mut out = String::new();
    let dirs: Vec<String> = plugin_host::library_dirs()
        .iter()
        .map(|d| d.display().to_string())
        .collect();
    let _ = writeln!(out, "library folders: {}", dirs.join(", "));
    let loaded = host.loaded();
    if loaded.is_empty() {
        let _ = writeln!(
            out,
            "no plugin modules loaded (build some: proleg plugin build)"
        );
    }
    for p in &loaded {
        let d = &p.descriptor;
        let params: Vec<String> = d
            .parameters
            .iter()
            .map(|q| format!("{}={} [{}..{}]", q.name, q.default, q.min, q.max))
            .collect();
        let _ = writeln!(out, "{}  {}", d.type_name, p.file.display());
        if !d.summary.is_empty() {
            let _ = writeln!(out, "    {}", d.summary);
        }
        let _ = writeln!(out, "    parameters: {}", params.join(", "));
        let _ = writeln!(out, "    series: {}", d.series.join(", "));
    }
    for e in &startup.skipped {
        let _ = writeln!(out, "skipped {e}");
    }
    out
}

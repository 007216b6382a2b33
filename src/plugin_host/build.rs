//! Building plugin crates (`proleg plugin build`, the GUI's Compile): runs cargo on the
//! plugin workspace (`plugins/`), captures its output for the user, and copies each built
//! library into the library folder by writing a temporary file and renaming it, so a
//! process that has the old library mapped keeps running.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::plugin_host::error::PluginError;

/// What to build and where to put it.
#[derive(Debug, Clone, PartialEq)]
pub struct PluginBuildOptions {
    /// The plugin workspace (holds `Cargo.toml`, `api/` and the plugin crates).
    pub workspace: PathBuf,
    /// One plugin crate (package or folder name); `None` builds every plugin crate.
    pub package: Option<String>,
    /// Cargo's target folder.
    pub target_dir: PathBuf,
    /// The library folder the built libraries are copied into.
    pub lib_dir: PathBuf,
}

impl Default for PluginBuildOptions {
    fn default() -> Self {
        PluginBuildOptions {
            workspace: PathBuf::from("plugins"),
            package: None,
            target_dir: PathBuf::from("target/plugins"),
            lib_dir: PathBuf::from(super::DEFAULT_LIBRARY),
        }
    }
}

/// The result of a build that ran.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildOutcome {
    /// Whether cargo succeeded.
    pub success: bool,
    /// Cargo's output (compiler messages, errors).
    pub log: String,
    /// The libraries copied into the library folder.
    pub libraries: Vec<PathBuf>,
}

/// A plugin crate of the workspace.
#[derive(Debug, Clone, PartialEq)]
pub struct PluginCrate {
    /// The crate's folder.
    pub folder: PathBuf,
    /// The crate's package name.
    pub package: String,
}

impl PluginCrate {
    /// The file name of its built library (`libNAME.so` on Linux).
    pub fn library_name(&self) -> String {
        format!(
            "{}{}{}",
            std::env::consts::DLL_PREFIX,
            self.package.replace('-', "_"),
            std::env::consts::DLL_SUFFIX
        )
    }
}

/// The package name in a manifest (the first `name = "..."`).
fn package_name(manifest: &str) -> Option<String> {
    manifest.lines().find_map(|l| {
        let rest = l
            .trim()
            .strip_prefix("name")?
            .trim_start()
            .strip_prefix('=')?;
        Some(rest.trim().trim_matches('"').to_string())
    })
}

/// The `cdylib` crates of the workspace, by folder name.
pub fn plugin_crates(workspace: &Path) -> Result<Vec<PluginCrate>, PluginError> {
    let entries =
        std::fs::read_dir(workspace).map_err(PluginError::io("plugin workspace", workspace))?;
    let mut crates = Vec::new();
    for entry in entries.flatten() {
        let folder = entry.path();
        let Ok(manifest) = std::fs::read_to_string(folder.join("Cargo.toml")) else {
            continue;
        };
        if !manifest.contains("cdylib") {
            continue;
        }
        if let Some(package) = package_name(&manifest) {
            crates.push(PluginCrate { folder, package });
        }
    }
    crates.sort_by(|a, b| a.package.cmp(&b.package));
    Ok(crates)
}

/// The cargo to run: the one running us (`CARGO`), else `cargo` from the path.
fn cargo() -> PathBuf {
    std::env::var_os("CARGO")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("cargo"))
}

/// Builds the plugin crate(s) in release mode and installs the libraries; `Err` when the
/// build could not start (no workspace, unknown crate, no cargo).
pub fn build(opts: &PluginBuildOptions) -> Result<BuildOutcome, PluginError> {
    let all = plugin_crates(&opts.workspace)?;
    let chosen: Vec<PluginCrate> = match &opts.package {
        Some(name) => {
            let found = all.iter().find(|c| {
                c.package == *name || c.folder.file_name().is_some_and(|f| f == name.as_str())
            });
            match found {
                Some(c) => vec![c.clone()],
                None => {
                    return Err(PluginError::NoCrate {
                        name: name.clone(),
                        workspace: opts.workspace.clone(),
                        known: all.iter().map(|c| c.package.clone()).collect(),
                    });
                }
            }
        }
        None => all,
    };
    if chosen.is_empty() {
        return Err(PluginError::NoCrates(opts.workspace.clone()));
    }
    let mut cmd = Command::new(cargo());
    cmd.arg("build")
        .arg("--release")
        .arg("--color")
        .arg("never")
        .arg("--manifest-path")
        .arg(opts.workspace.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(&opts.target_dir);
    for c in &chosen {
        cmd.arg("-p").arg(&c.package);
    }
    let output = cmd.output().map_err(|source| PluginError::Cargo {
        cargo: cargo(),
        source,
    })?;
    let mut log = String::from_utf8_lossy(&output.stderr).into_owned();
    log.push_str(&String::from_utf8_lossy(&output.stdout));
    if !output.status.success() {
        return Ok(BuildOutcome {
            success: false,
            log,
            libraries: Vec::new(),
        });
    }
    std::fs::create_dir_all(&opts.lib_dir)
        .map_err(PluginError::io("library folder", &opts.lib_dir))?;
    let mut libraries = Vec::new();
    for c in &chosen {
        let name = c.library_name();
        let built = opts.target_dir.join("release").join(&name);
        let dest = opts.lib_dir.join(&name);
        install(&built, &dest)?;
        log.push_str(&format!("installed {}\n", dest.display()));
        libraries.push(dest);
    }
    Ok(BuildOutcome {
        success: true,
        log,
        libraries,
    })
}

/// Copies `from` to `to` through a temporary file and a rename (a new file, never an
/// overwrite of a library some process has mapped).
fn install(from: &Path, to: &Path) -> Result<(), PluginError> {
    let tmp = to.with_extension("tmp");
    std::fs::copy(from, &tmp).map_err(PluginError::io("copying", from))?;
    std::fs::rename(&tmp, to).map_err(PluginError::io("installing", to))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_example_crates_and_refuses_unknown_ones() {
        let ws = Path::new(env!("CARGO_MANIFEST_DIR")).join("plugins");
        let crates = plugin_crates(&ws).unwrap();
        let names: Vec<&str> = crates.iter().map(|c| c.package.as_str()).collect();
        for example in ["example_rectilinear", "example_sine", "example_square_wave"] {
            assert!(names.contains(&example), "{names:?}");
        }
        assert!(!names.contains(&"proleg-plugin-api"));
        let e = build(&PluginBuildOptions {
            workspace: ws,
            package: Some("nope".into()),
            ..PluginBuildOptions::default()
        })
        .unwrap_err();
        let PluginError::NoCrate { name, known, .. } = e else {
            panic!("not a missing crate: {e}");
        };
        assert_eq!(name, "nope");
        assert!(known.iter().any(|k| k == "example_sine"), "{known:?}");
    }
}

//! The user module library in the GUI (thesis 4.4.4, figs. 4.8-4.9), shared by the
//! control window and the configuration window: declare a new module (name, parameters
//! with initial values and ranges, helper functions, data series), edit its generated
//! Rust in an editor with syntax highlighting, Compile (cargo runs in a background
//! thread; its output is shown), and on success the module is loaded into the registry:
//! it can be assigned to joints at once, without restarting.
//!
//! - [`ModuleEditor`]: the state and the actions (declare, open, save, compile, poll)
//! - [`view`]: the egui window; [`highlight`]: the Rust colouring; [`script`]: the
//!   script commands both windows share

pub mod highlight;
#[cfg(feature = "scripts")]
pub mod script;
pub mod view;

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, TryRecvError, channel};

use bevy::prelude::*;

use crate::plugin_host::build::{BuildOutcome, PluginBuildOptions, build, plugin_crates};
use crate::plugin_host::error::PluginError;
use crate::plugin_host::template::{Declaration, ParamDecl};
use crate::plugin_host::{self, DEFAULT_LIBRARY, PluginHost};

/// One parameter row of the declaration form.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamRow {
    /// Parameter name.
    pub name: String,
    /// Initial value.
    pub initial: f64,
    /// Lowest allowed value.
    pub min: f64,
    /// Highest allowed value.
    pub max: f64,
}

/// The declaration form (fig. 4.8).
#[derive(Debug, Clone, PartialEq)]
pub struct DeclarationForm {
    /// The module's name.
    pub name: String,
    /// What it does.
    pub summary: String,
    /// Its parameters.
    pub params: Vec<ParamRow>,
    /// Comma-separated helper function names.
    pub helpers: String,
    /// Comma-separated data series names.
    pub series: String,
}

impl Default for DeclarationForm {
    fn default() -> Self {
        DeclarationForm {
            name: "MyGait".into(),
            summary: String::new(),
            params: vec![
                ParamRow {
                    name: "Amplitude".into(),
                    initial: 30.0,
                    min: 0.0,
                    max: 90.0,
                },
                ParamRow {
                    name: "Frequency".into(),
                    initial: 1.0,
                    min: 0.0,
                    max: 5.0,
                },
            ],
            helpers: String::new(),
            series: "Phase".into(),
        }
    }
}

fn list(s: &str) -> Vec<String> {
    s.split(',')
        .map(|w| w.trim().to_string())
        .filter(|w| !w.is_empty())
        .collect()
}

impl DeclarationForm {
    /// The form as a template declaration.
    pub fn declaration(&self) -> Declaration {
        Declaration {
            name: self.name.trim().to_string(),
            summary: self.summary.trim().to_string(),
            params: self
                .params
                .iter()
                .map(|p| ParamDecl {
                    name: p.name.trim().to_string(),
                    initial: p.initial,
                    min: p.min,
                    max: p.max,
                })
                .collect(),
            helpers: list(&self.helpers),
            series: list(&self.series),
        }
    }
}

/// What the last action said.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Status {
    /// Nothing to report.
    #[default]
    None,
    /// Information.
    Info(String),
    /// An error.
    Error(String),
}

/// The editor's state.
#[derive(Resource)]
pub struct ModuleEditor {
    /// Whether the window is shown.
    pub open: bool,
    /// The plugin workspace (new crates go here).
    pub workspace: PathBuf,
    /// The library folder built modules are installed in.
    pub lib_dir: PathBuf,
    /// Cargo's target folder.
    pub target_dir: PathBuf,
    /// The declaration form.
    pub form: DeclarationForm,
    /// The crate in the editor (folder name) and its source file.
    pub crate_name: Option<String>,
    /// The module's source in the editor.
    pub source: String,
    /// The source differs from the file.
    pub modified: bool,
    /// The running build's answer (a mutex only to make the resource `Sync`).
    job: Option<Mutex<Receiver<Result<BuildOutcome, PluginError>>>>,
    /// The last build's output.
    pub log: String,
    /// The last outcome (generated, compiled, an error).
    pub status: Status,
    /// Counts module loads: views rebuild their module lists when it changes.
    pub revision: u64,
    /// Modules loaded by the last successful build.
    pub last_loaded: Vec<String>,
    /// Builds finished (successful or not), for scripts.
    pub builds: u64,
    /// A script waits for the build after this many builds.
    pub awaited_build: Option<u64>,
    /// Libraries the last rescan skipped, with the cause.
    pub scan_messages: Vec<String>,
    /// The window's plugin libraries: the program's start-up scan, and what the editor
    /// builds and rescans.
    pub host: PluginHost,
}

impl ModuleEditor {
    /// The editor of a window whose plugins `host` loaded.
    pub fn new(host: PluginHost) -> Self {
        ModuleEditor {
            host,
            ..ModuleEditor::default()
        }
    }
}

impl Default for ModuleEditor {
    fn default() -> Self {
        ModuleEditor {
            open: false,
            workspace: PathBuf::from("plugins"),
            lib_dir: PathBuf::from(DEFAULT_LIBRARY),
            target_dir: PathBuf::from("target/plugins"),
            form: DeclarationForm::default(),
            crate_name: None,
            source: String::new(),
            modified: false,
            job: None,
            log: String::new(),
            status: Status::None,
            revision: 0,
            last_loaded: Vec::new(),
            builds: 0,
            awaited_build: None,
            scan_messages: Vec::new(),
            host: PluginHost::default(),
        }
    }
}

impl ModuleEditor {
    /// Works in the plugin workspace `dir` (libraries into `dir/lib`).
    pub fn use_workspace(&mut self, dir: &Path) {
        self.workspace = dir.to_path_buf();
        self.lib_dir = dir.join("lib");
    }

    fn source_file(&self) -> Option<PathBuf> {
        self.crate_name
            .as_ref()
            .map(|c| self.workspace.join(c).join("src").join("lib.rs"))
    }

    /// The plugin crates of the workspace (folder names).
    pub fn crates(&self) -> Vec<String> {
        plugin_crates(&self.workspace)
            .map(|cs| {
                cs.iter()
                    .filter_map(|c| {
                        c.folder
                            .file_name()
                            .map(|f| f.to_string_lossy().into_owned())
                    })
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Makes the declared module's crate and opens it in the editor.
    pub fn declare(&mut self) -> Result<(), PluginError> {
        let decl = self.form.declaration();
        let folder = decl.create(&self.workspace)?;
        self.status = Status::Info(format!(
            "created {}: write the step in compute(), then Compile",
            folder.display()
        ));
        self.open_crate(&decl.crate_name())
    }

    /// Opens crate `name`'s `src/lib.rs`.
    pub fn open_crate(&mut self, name: &str) -> Result<(), PluginError> {
        let file = self.workspace.join(name).join("src").join("lib.rs");
        self.source = std::fs::read_to_string(&file).map_err(PluginError::io("reading", &file))?;
        self.crate_name = Some(name.to_string());
        self.modified = false;
        Ok(())
    }

    /// Writes the editor's text to the crate's source file.
    pub fn save(&mut self) -> Result<(), PluginError> {
        let file = self
            .source_file()
            .ok_or(PluginError::Editor("no module is open"))?;
        std::fs::write(&file, &self.source).map_err(PluginError::io("writing", &file))?;
        self.modified = false;
        Ok(())
    }

    /// Whether a compile is running.
    pub fn building(&self) -> bool {
        self.job.is_some()
    }

    /// Loads new or changed libraries from the library folders.
    pub fn rescan(&mut self) {
        let report = self.host.scan(&plugin_host::library_dirs());
        self.scan_messages = report.messages();
        if !report.loaded.is_empty() {
            self.revision += 1;
        }
        let names: Vec<&str> = report
            .loaded
            .iter()
            .map(|p| p.descriptor.type_name)
            .collect();
        self.status = Status::Info(format!(
            "rescanned: {} loaded ({}), {} unchanged, {} skipped",
            names.len(),
            names.join(", "),
            report.unchanged,
            report.skipped.len()
        ));
    }

    /// Saves and starts building the open crate in the background.
    pub fn compile(&mut self) -> Result<(), PluginError> {
        if self.building() {
            return Err(PluginError::Editor("a build is running"));
        }
        self.save()?;
        let opts = PluginBuildOptions {
            workspace: self.workspace.clone(),
            package: self.crate_name.clone(),
            target_dir: self.target_dir.clone(),
            lib_dir: self.lib_dir.clone(),
        };
        let (tx, rx) = channel();
        std::thread::Builder::new()
            .name("module build".into())
            .spawn(move || {
                // A closed editor no longer wants the outcome; the libraries are built
                // and installed all the same.
                if tx.send(build(&opts)).is_err() {
                    bevy::log::info!("a module build ended after its editor closed");
                }
            })
            .map_err(PluginError::io("starting the build of", &self.workspace))?;
        self.job = Some(Mutex::new(rx));
        self.log.clear();
        self.status = Status::Info("compiling…".into());
        Ok(())
    }

    /// Collects a finished build: loads its modules into the registry. True when a build
    /// finished this call.
    pub fn poll(&mut self) -> bool {
        let Some(rx) = self.job.as_mut() else {
            return false;
        };
        let rx = rx
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let result = match rx.try_recv() {
            Ok(r) => r,
            Err(TryRecvError::Empty) => return false,
            Err(TryRecvError::Disconnected) => Err(PluginError::Editor("the build thread stopped")),
        };
        self.job = None;
        self.builds += 1;
        match result {
            Err(e) => self.status = Status::Error(e.to_string()),
            Ok(outcome) if !outcome.success => {
                self.log = outcome.log;
                let errors = self.log.lines().filter(|l| l.starts_with("error")).count();
                self.status = Status::Error(format!(
                    "the build failed ({errors} error line(s)); see the output below"
                ));
            }
            Ok(outcome) => {
                self.log = outcome.log;
                self.last_loaded.clear();
                let mut problems = Vec::new();
                for lib in &outcome.libraries {
                    match self.host.load_file(lib) {
                        Ok(Some(info)) => self.last_loaded.push(info.descriptor.type_name.into()),
                        Ok(None) => {}
                        Err(e) => problems.push(e.to_string()),
                    }
                }
                self.revision += 1;
                self.status = if problems.is_empty() {
                    Status::Info(format!(
                        "compiled; module {} loaded: assign it to joints now",
                        self.last_loaded.join(", ")
                    ))
                } else {
                    Status::Error(problems.join("; "))
                };
            }
        }
        true
    }
}

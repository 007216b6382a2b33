//! Runtime-loaded actuation modules (thesis 4.4.4, 5.2.3): the user module library.
//!
//! Plugins are `cdylib`s written against the `proleg-plugin-api` crate (`plugins/api`),
//! which exports a versioned `#[repr(C)]` function table. The host
//! is a value, [`PluginHost`], that owns what it loaded (no process-wide state: two hosts
//! side by side know only their own libraries). It
//! - scans the library folders ([`library_dirs`]: `plugins/lib`, where
//!   `proleg plugin build` puts libraries, and the user folder
//!   `$XDG_DATA_HOME/proleg/plugins`; `PROLEG_PLUGINS` replaces both) at start-up and on
//!   request ([`PluginHost::scan`]), loading every new or changed library
//!   ([`PluginHost::load_file`]);
//! - checks each library's ABI version and symbols ([`library::open`]); a bad one is
//!   skipped with a [`LoadError`] naming the file and the cause;
//! - gives a registry with the standard modules and its plugins ([`PluginHost::registry`]),
//!   which callers pass to the loader and the simulator;
//! - keeps its libraries loaded while it lives (a rebuilt library is loaded from a fresh
//!   copy, replacing the module for new instances; running ones keep the old code).
//!
//! [`build`] compiles plugin crates with cargo, [`template`] writes new ones.
//! [`module`] is a plugin's module as the kernel runs it ([`PluginModule`]); [`error`] the
//! host's errors.

pub mod build;
pub mod error;
pub mod library;
pub mod module;
pub mod template;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

use crate::config::module_types::ModuleDescriptor;
use crate::control::registry::{ModuleFactory, ModuleRegistry};
use crate::plugin_host::error::PluginError;
pub use library::{LoadError, PluginLibrary};
pub use module::PluginModule;

/// Environment variable with the library folders (path list) replacing the defaults.
pub const ENV_VAR: &str = "PROLEG_PLUGINS";
/// Where `proleg plugin build` puts libraries, relative to the working folder.
pub const DEFAULT_LIBRARY: &str = "plugins/lib";

/// The folders scanned for plugin libraries.
pub fn library_dirs() -> Vec<PathBuf> {
    match std::env::var_os(ENV_VAR) {
        Some(list) => std::env::split_paths(&list)
            .filter(|p| !p.as_os_str().is_empty())
            .collect(),
        None => {
            let mut dirs = vec![PathBuf::from(DEFAULT_LIBRARY)];
            dirs.extend(user_dir());
            dirs
        }
    }
}

/// The per-user library folder (`$XDG_DATA_HOME/proleg/plugins`).
pub fn user_dir() -> Option<PathBuf> {
    let data = std::env::var_os("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".local/share")))?;
    Some(data.join("proleg").join("plugins"))
}

/// A loaded plugin module.
#[derive(Debug, Clone, PartialEq)]
pub struct PluginInfo {
    /// The module type the plugin provides.
    pub descriptor: ModuleDescriptor,
    /// The library it was loaded from.
    pub file: PathBuf,
}

/// What a scan did.
#[derive(Debug, Default)]
pub struct ScanReport {
    /// Modules loaded (or reloaded) now.
    pub loaded: Vec<PluginInfo>,
    /// Libraries already loaded and unchanged.
    pub unchanged: usize,
    /// Libraries skipped, with the cause.
    pub skipped: Vec<LoadError>,
}

impl ScanReport {
    /// One line per skipped library, for stderr or the GUI.
    pub fn messages(&self) -> Vec<String> {
        self.skipped.iter().map(|e| e.to_string()).collect()
    }
}

/// A library a [`PluginHost`] loaded.
struct Loaded {
    file: PathBuf,
    stamp: Option<(SystemTime, u64)>,
    info: PluginInfo,
    factory: ModuleFactory,
    _library: Arc<PluginLibrary>,
}

/// The plugin libraries one program (or test) loaded, and the registry they give.
#[derive(Default)]
pub struct PluginHost {
    loaded: Vec<Loaded>,
    /// Fresh copies made for reloads, for their names.
    copies: usize,
    /// The folder they are made in, the host's own.
    copy_dir: Option<PathBuf>,
}

/// A new folder `PREFIX-PID-K` in `parent`, the first `K` not taken.
fn own_dir(parent: &Path, prefix: &str) -> Result<PathBuf, PluginError> {
    std::fs::create_dir_all(parent).map_err(PluginError::io("creating", parent))?;
    for k in 0..10_000 {
        let d = parent.join(format!("{prefix}-{}-{k}", std::process::id()));
        match std::fs::create_dir(&d) {
            Ok(()) => return Ok(d),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(PluginError::io("creating", d)(e)),
        }
    }
    Err(PluginError::NoFreshFolder {
        parent: parent.to_path_buf(),
        prefix: prefix.to_string(),
    })
}

impl std::fmt::Debug for PluginHost {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PluginHost")
            .field("loaded", &self.loaded())
            .finish()
    }
}

/// Whether `path` names a shared library of this platform.
fn is_library(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e == std::env::consts::DLL_EXTENSION)
}

fn stamp(path: &Path) -> Option<(SystemTime, u64)> {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.modified().ok()?, meta.len()))
}

impl PluginHost {
    /// A host that loaded the libraries of the configured [`library_dirs`], and what the
    /// scan did.
    pub fn scan_default() -> (PluginHost, ScanReport) {
        let mut host = PluginHost::default();
        let report = host.scan(&library_dirs());
        (host, report)
    }

    /// Loads every new or changed library in `dirs` (missing folders are passed over).
    pub fn scan(&mut self, dirs: &[PathBuf]) -> ScanReport {
        let mut report = ScanReport::default();
        for dir in dirs {
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            let mut files: Vec<PathBuf> = entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && is_library(p))
                .collect();
            files.sort();
            for file in files {
                match self.load_file(&file) {
                    Ok(Some(info)) => report.loaded.push(info),
                    Ok(None) => report.unchanged += 1,
                    Err(e) => report.skipped.push(e),
                }
            }
        }
        report
    }

    /// Loads one library and registers its module; `None` when it is loaded and unchanged.
    pub fn load_file(&mut self, file: &Path) -> Result<Option<PluginInfo>, LoadError> {
        let err = |cause: String| LoadError {
            file: file.to_path_buf(),
            cause,
        };
        let file = std::fs::canonicalize(file).map_err(|e| err(e.to_string()))?;
        let stamp = stamp(&file);
        let previous = self.loaded.iter().position(|l| l.file == file);
        if let Some(i) = previous
            && self.loaded[i].stamp == stamp
        {
            return Ok(None);
        }
        // The dynamic loader hands out the already loaded library for a path it has seen,
        // so a changed library is loaded from a fresh copy.
        let copy = match previous {
            Some(_) => Some(self.fresh_copy(&file).map_err(|e| err(e.to_string()))?),
            None => None,
        };
        let (library, descriptor) = library::open(&file, copy.as_deref().unwrap_or(&file))?;
        let name = descriptor.type_name;
        if ModuleRegistry::standard().get(name).is_some() {
            return Err(err(format!(
                "module name {name} is taken by a standard module; rename the plugin's module"
            )));
        }
        if let Some(other) = self.loaded.iter().find(|l| {
            l.file != file && crate::config::xml::read::same_name(l.info.descriptor.type_name, name)
        }) {
            return Err(err(format!(
                "module {name} is already loaded from {}",
                other.file.display()
            )));
        }
        let library = Arc::new(library);
        let for_factory = (library.clone(), descriptor.clone());
        let factory: ModuleFactory = Arc::new(move |joints| {
            Box::new(PluginModule::new(
                for_factory.0.clone(),
                for_factory.1.clone(),
                joints,
            ))
        });
        let info = PluginInfo {
            descriptor,
            file: file.clone(),
        };
        let entry = Loaded {
            file,
            stamp,
            info: info.clone(),
            factory,
            _library: library,
        };
        match previous {
            Some(i) => {
                let old = std::mem::replace(&mut self.loaded[i], entry);
                // The old library stays loaded: running modules may still use it.
                std::mem::forget(old._library);
            }
            None => self.loaded.push(entry),
        }
        Ok(Some(info))
    }

    /// A copy of `file` under a name the loader has not seen, in the host's own folder of
    /// the temp folder (made on the first reload: the first free
    /// `proleg-plugins-PID-K`, so hosts of one process never share one).
    fn fresh_copy(&mut self, file: &Path) -> Result<PathBuf, PluginError> {
        let dir = match &self.copy_dir {
            Some(d) => d.clone(),
            None => {
                let d = own_dir(&std::env::temp_dir(), "proleg-plugins")?;
                self.copy_dir = Some(d.clone());
                d
            }
        };
        let n = self.copies;
        self.copies += 1;
        let name = file
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let copy = dir.join(format!("{n}-{name}"));
        std::fs::copy(file, &copy).map_err(PluginError::io("copying to", &copy))?;
        Ok(copy)
    }

    /// A registry with the standard module library and every plugin module this host
    /// loaded (in load order). Callers pass it to the loader and the simulator; it does not
    /// change when more plugins load later (ask again).
    pub fn registry(&self) -> ModuleRegistry {
        let mut r = ModuleRegistry::standard();
        for l in &self.loaded {
            r.register(l.info.descriptor.clone(), Some(l.factory.clone()));
        }
        r
    }

    /// The plugin modules this host loaded, in load order.
    pub fn loaded(&self) -> Vec<PluginInfo> {
        self.loaded.iter().map(|l| l.info.clone()).collect()
    }
}

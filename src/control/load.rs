//! Loading a configuration against the standard module library: the common case of tests,
//! benchmarks and tools that use no plugins. With plugins, load through
//! [`crate::config::load_simulation_with`] and the registry `crate::plugin_host::PluginHost::registry`
//! builds.

use std::path::Path;

use crate::config::{ConfigResult, FsSource, Simulation, load_simulation_with};
use crate::control::ModuleRegistry;

/// Loads a simulation from disk, checking its modules against the standard library.
pub fn load_simulation(path: impl AsRef<Path>) -> ConfigResult<Simulation> {
    load_simulation_with(&FsSource, path.as_ref(), &ModuleRegistry::standard())
}

/// Loads a simulation from disk, checking its modules against `registry`.
pub fn load_simulation_in(
    path: impl AsRef<Path>,
    registry: &ModuleRegistry,
) -> ConfigResult<Simulation> {
    load_simulation_with(&FsSource, path.as_ref(), registry)
}

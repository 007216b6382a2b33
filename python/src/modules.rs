//! The module types every Python entry point loads simulations with: the standard library
//! and the user's plugin modules, found where `proleg` finds them (`plugins/lib`, the user
//! folder, or `PROLEG_PLUGINS`), so a simulation that runs under `proleg run` runs from
//! Python too. The folders are scanned once per process, at the first load; the plugin
//! libraries then stay loaded for the life of the interpreter (their code runs inside the
//! modules built from them). A library that does not load is said once, as a Python
//! `UserWarning` naming the file and the cause, as the command line prints it.

use std::sync::OnceLock;

use proleg::control::ModuleRegistry;
use proleg::plugin_host::PluginHost;
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;

/// The registry, and the scan's messages not yet said.
static MODULES: OnceLock<(ModuleRegistry, Vec<String>)> = OnceLock::new();

/// The module registry of this process (scanning the plugin folders on first use).
pub fn registry(py: Python<'_>) -> PyResult<&'static ModuleRegistry> {
    let mut first = false;
    let (registry, messages) = MODULES.get_or_init(|| {
        first = true;
        let (host, scan) = PluginHost::scan_default();
        let registry = host.registry();
        // The loaded libraries must outlive every module made from them: the process's.
        std::mem::forget(host);
        (registry, scan.messages())
    });
    if first {
        for m in messages {
            let text = std::ffi::CString::new(format!("proleg plugins: {m}"))
                .unwrap_or_else(|_| c"proleg plugins: a library was skipped".to_owned());
            PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 1)?;
        }
    }
    Ok(registry)
}

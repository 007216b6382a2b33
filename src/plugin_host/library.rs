//! Opening one plugin library: load it with libloading, check its ABI version before
//! anything else, read its function table and turn its `#[repr(C)]` descriptor into a
//! [`ModuleDescriptor`]. Every failure is a [`LoadError`] naming the file and the cause.

use std::fmt;
use std::path::{Path, PathBuf};

use proleg_plugin_api::{
    ABI_VERSION, PluginTable, RawDescriptor, RawStr, TABLE_SYMBOL, VERSION_SYMBOL,
};

use crate::config::module_types::{ModuleDescriptor, ParamDescriptor};

/// Why a library was skipped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("plugin {}: {cause}", .file.display())]
pub struct LoadError {
    /// The library file.
    pub file: PathBuf,
    /// Why it was skipped.
    pub cause: String,
}

/// A loaded plugin library: its table, kept loaded for the life of the process.
pub struct PluginLibrary {
    /// The file the user put in the library folder.
    pub file: PathBuf,
    pub(crate) table: PluginTable,
    _library: libloading::Library,
}

// SAFETY: the table holds C function pointers and a pointer to the library's immutable
// descriptor; the module types behind them are `Send + Sync` (the API's trait bound).
unsafe impl Send for PluginLibrary {}
unsafe impl Sync for PluginLibrary {}

impl fmt::Debug for PluginLibrary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PluginLibrary")
            .field("file", &self.file)
            .finish()
    }
}

impl PluginLibrary {
    /// The calling thread's last panic message inside the library.
    pub fn last_error(&self) -> String {
        let mut buf = vec![0u8; 1024];
        // SAFETY: `buf` has `buf.len()` writable bytes.
        let n = unsafe { (self.table.last_error)(buf.as_mut_ptr(), buf.len()) };
        buf.truncate(n.min(1024));
        let text = String::from_utf8_lossy(&buf).into_owned();
        if text.is_empty() {
            "failed without a message".to_string()
        } else {
            text
        }
    }
}

/// Opens `load_from` (a copy of `file` when the file was reloaded) as a plugin.
pub fn open(file: &Path, load_from: &Path) -> Result<(PluginLibrary, ModuleDescriptor), LoadError> {
    let err = |cause: String| LoadError {
        file: file.to_path_buf(),
        cause,
    };
    // SAFETY: loading runs the library's initialisers; plugins are code the user chose to
    // put in a library folder, as with any native plugin system.
    let library = unsafe { libloading::Library::new(load_from) }
        .map_err(|e| err(format!("not a loadable library: {e}")))?;
    // SAFETY: the symbol's type is fixed by the API for every ABI version.
    let version =
        unsafe { library.get::<unsafe extern "C" fn() -> u32>(VERSION_SYMBOL) }.map_err(|_| {
            err(
                "missing symbol proleg_plugin_abi_version: not a proleg plugin (export the \
                 module with proleg_plugin_api::export_module!)"
                    .to_string(),
            )
        })?;
    // SAFETY: as above.
    let version = unsafe { version() };
    if version != ABI_VERSION {
        return Err(err(format!(
            "built for plugin ABI version {version}, this proleg loads version {ABI_VERSION}: \
             rebuild it against this proleg's plugins/api (proleg plugin build)"
        )));
    }
    // SAFETY: the version matched, so the table has this layout.
    let table =
        unsafe { library.get::<unsafe extern "C" fn() -> *const PluginTable>(TABLE_SYMBOL) }
            .map_err(|_| err("missing symbol proleg_plugin_table".to_string()))?;
    // SAFETY: as above; the pointer is checked for null before use.
    let table = unsafe { table() };
    if table.is_null() {
        return Err(err("proleg_plugin_table returned no table".to_string()));
    }
    // SAFETY: non-null and of this ABI's layout; copied out (it lives in the library).
    let table = unsafe { *table };
    if table.abi_version != ABI_VERSION || table.descriptor.is_null() {
        return Err(err(format!(
            "its table says ABI version {}, expected {ABI_VERSION}",
            table.abi_version
        )));
    }
    // SAFETY: the descriptor is static in the library, which stays loaded.
    let raw = unsafe { &*table.descriptor };
    let descriptor = descriptor(raw).map_err(|e| err(e.to_string()))?;
    Ok((
        PluginLibrary {
            file: file.to_path_buf(),
            table,
            _library: library,
        },
        descriptor,
    ))
}

/// Most parameters or series a descriptor may declare (guards against garbage counts).
const MAX_ITEMS: usize = 256;

/// A string of the descriptor, copied out and leaked: module descriptors are `'static`
/// and loaded libraries are never unloaded, so this is a few bytes per library.
fn text(s: &RawStr, what: &'static str) -> Result<&'static str, BadTable> {
    if s.len > 4096 || (s.ptr.is_null() && s.len > 0) {
        return Err(BadTable::String(what, "not a valid string"));
    }
    let bytes = if s.len == 0 {
        &[][..]
    } else {
        // SAFETY: the API builds every `RawStr` from a `&'static str` of the library.
        unsafe { std::slice::from_raw_parts(s.ptr, s.len) }
    };
    let text = std::str::from_utf8(bytes).map_err(|_| BadTable::String(what, "not UTF-8"))?;
    Ok(Box::leak(text.to_owned().into_boxed_str()))
}

/// Whether `name` can be written in actuation files (letters, digits, `_`).
pub fn valid_module_name(name: &str) -> bool {
    name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A plugin's table that does not describe a module.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum BadTable {
    /// A string of the descriptor.
    #[error("{0}: {1}")]
    String(&'static str, &'static str),
    /// A name that actuation files cannot hold.
    #[error("module name {0:?}: use letters, digits and _ (starting with a letter)")]
    Name(String),
    /// Counts beyond [`MAX_ITEMS`].
    #[error("module {0}: too many parameters or series")]
    TooMany(String),
    /// A parameter without a name.
    #[error("module {0}: a parameter without a name")]
    Unnamed(String),
    /// A parameter whose initial value lies outside its range.
    #[error("module {module}, parameter {parameter}: initial value {initial} outside its range {}..{}", range[0], range[1])]
    Initial {
        /// The module.
        module: String,
        /// The parameter.
        parameter: String,
        /// Its initial value.
        initial: f64,
        /// Its range.
        range: [f64; 2],
    },
}

fn descriptor(raw: &RawDescriptor) -> Result<ModuleDescriptor, BadTable> {
    let name = text(&raw.name, "module name")?;
    if !valid_module_name(name) {
        return Err(BadTable::Name(name.to_string()));
    }
    if raw.param_count > MAX_ITEMS || raw.series_count > MAX_ITEMS {
        return Err(BadTable::TooMany(name.to_string()));
    }
    let raw_params = if raw.param_count == 0 {
        &[][..]
    } else {
        // SAFETY: the API points `params` at `param_count` entries in the library.
        unsafe { std::slice::from_raw_parts(raw.params, raw.param_count) }
    };
    let mut parameters = Vec::with_capacity(raw_params.len());
    for p in raw_params {
        let pname = text(&p.name, "parameter name")?;
        if pname.is_empty() {
            return Err(BadTable::Unnamed(name.to_string()));
        }
        let fine = p.min.is_finite() && p.max.is_finite() && p.default.is_finite();
        if !fine || p.min > p.max || p.default < p.min || p.default > p.max {
            return Err(BadTable::Initial {
                module: name.to_string(),
                parameter: pname.to_string(),
                initial: p.default,
                range: [p.min, p.max],
            });
        }
        parameters.push(ParamDescriptor {
            name: pname,
            aliases: &[],
            unit: text(&p.unit, "unit")?,
            default: p.default,
            min: p.min,
            max: p.max,
            help: text(&p.help, "help")?,
        });
    }
    let raw_series = if raw.series_count == 0 {
        &[][..]
    } else {
        // SAFETY: the API points `series` at `series_count` entries in the library.
        unsafe { std::slice::from_raw_parts(raw.series, raw.series_count) }
    };
    let series = raw_series
        .iter()
        .map(|s| text(s, "series name"))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(ModuleDescriptor {
        type_name: name,
        summary: text(&raw.summary, "summary")?,
        parameters: Box::leak(parameters.into_boxed_slice()),
        series: Box::leak(series.into_boxed_slice()),
        sensing: raw.sensing,
        network: false,
    })
}

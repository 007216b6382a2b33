//! Where configuration files come from: the file system, or an in-memory set of files
//! (tests, fuzzing, the configuration GUI's unsaved edits).
//!
//! Includes are resolved relative to the including file's folder; when not found there,
//! relative to each ancestor folder in turn (the thesis's files name parts relative to
//! the program's working directory, e.g. `./configuration/robotXML/base/PY.kinbody.xml`).

use std::collections::BTreeMap;
use std::io;
use std::path::{Component, Path, PathBuf};

/// Reads configuration files.
pub trait FileSource {
    /// The text of `path`.
    fn read(&self, path: &Path) -> io::Result<String>;
    /// Whether `path` exists.
    fn exists(&self, path: &Path) -> bool;
    /// The bytes of a binary file (a policy's weights). In memory a binary file is text:
    /// [`BINARY_PREFIX`] then its bytes in base64 ([`binary_as_text`]).
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        text_as_binary(&self.read(path)?)
    }
}

/// How a binary file's in-memory text starts.
pub const BINARY_PREFIX: &str = "proleg-binary-base64:";

/// A binary file as in-memory text ([`BINARY_PREFIX`] and base64).
pub fn binary_as_text(bytes: &[u8]) -> String {
    use base64::Engine;
    format!(
        "{BINARY_PREFIX}{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

/// The bytes of a file's in-memory text: decoded when [`binary_as_text`] wrote it, else
/// the text's own bytes.
pub fn text_as_binary(text: &str) -> io::Result<Vec<u8>> {
    use base64::Engine;
    match text.strip_prefix(BINARY_PREFIX) {
        Some(encoded) => base64::engine::general_purpose::STANDARD
            .decode(encoded.trim())
            .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e.to_string())),
        None => Ok(text.as_bytes().to_vec()),
    }
}

/// The real file system.
#[derive(Debug, Clone, Copy, Default)]
pub struct FsSource;

impl FileSource for FsSource {
    fn read(&self, path: &Path) -> io::Result<String> {
        let bytes = std::fs::read(path)?;
        String::from_utf8(bytes).map_err(|e| {
            io::Error::new(
                io::ErrorKind::InvalidData,
                format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
            )
        })
    }

    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }

    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        std::fs::read(path)
    }
}

/// Files held in memory, keyed by normalized path.
#[derive(Debug, Clone, Default)]
pub struct MemSource {
    files: BTreeMap<PathBuf, String>,
}

impl MemSource {
    /// An empty source.
    pub fn new() -> Self {
        MemSource::default()
    }

    /// Adds (or replaces) a file.
    pub fn insert(&mut self, path: impl AsRef<Path>, text: impl Into<String>) {
        self.files.insert(normalize(path.as_ref()), text.into());
    }

    /// Adds a file (builder style).
    pub fn with(mut self, path: impl AsRef<Path>, text: impl Into<String>) -> Self {
        self.insert(path, text);
        self
    }
}

impl FileSource for MemSource {
    fn read(&self, path: &Path) -> io::Result<String> {
        self.files
            .get(&normalize(path))
            .cloned()
            .ok_or_else(|| io::Error::new(io::ErrorKind::NotFound, "no such file"))
    }

    fn exists(&self, path: &Path) -> bool {
        self.files.contains_key(&normalize(path))
    }
}

/// Files in memory laid over another source: a path the memory holds is read from it,
/// any other from the source below (a generated robot over the configuration folder).
pub struct Overlay<'a> {
    /// The files laid on top.
    pub top: MemSource,
    /// Where the others are read.
    pub base: &'a dyn FileSource,
}

impl FileSource for Overlay<'_> {
    fn read(&self, path: &Path) -> io::Result<String> {
        if self.top.exists(path) {
            self.top.read(path)
        } else {
            self.base.read(path)
        }
    }

    fn exists(&self, path: &Path) -> bool {
        self.top.exists(path) || self.base.exists(path)
    }

    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        if self.top.exists(path) {
            self.top.read_bytes(path)
        } else {
            self.base.read_bytes(path)
        }
    }
}

/// Another source that keeps a copy of every file read through it: the resolved
/// configuration of a run, stored with it so a worker on another host needs nothing else.
pub struct RecordingSource<'a> {
    inner: &'a dyn FileSource,
    read: std::sync::Mutex<BTreeMap<PathBuf, String>>,
}

impl<'a> RecordingSource<'a> {
    /// Records what is read from `inner`.
    pub fn new(inner: &'a dyn FileSource) -> Self {
        RecordingSource {
            inner,
            read: std::sync::Mutex::new(BTreeMap::new()),
        }
    }

    /// Every file read, as (normalized path, text), by path.
    pub fn files(&self) -> Vec<(String, String)> {
        self.read
            .lock()
            .map(|m| {
                m.iter()
                    .map(|(p, t)| (p.display().to_string(), t.clone()))
                    .collect()
            })
            .unwrap_or_default()
    }
}

impl FileSource for RecordingSource<'_> {
    fn read(&self, path: &Path) -> io::Result<String> {
        let text = self.inner.read(path)?;
        if let Ok(mut m) = self.read.lock() {
            m.insert(normalize(path), text.clone());
        }
        Ok(text)
    }

    fn exists(&self, path: &Path) -> bool {
        self.inner.exists(path)
    }

    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        let bytes = self.inner.read_bytes(path)?;
        if let Ok(mut m) = self.read.lock() {
            m.insert(normalize(path), binary_as_text(&bytes));
        }
        Ok(bytes)
    }
}

/// Removes `.` and resolves `..` lexically (no file-system access).
pub fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}

/// Finds the file `written` names, as included from `from`.
pub fn resolve_include(src: &dyn FileSource, from: &Path, written: &str) -> Option<PathBuf> {
    let written_path = Path::new(written.trim());
    if written_path.is_absolute() {
        return src.exists(written_path).then(|| normalize(written_path));
    }
    let dir = from.parent().unwrap_or(Path::new(""));
    for base in dir.ancestors() {
        let candidate = normalize(&base.join(written_path));
        if src.exists(&candidate) {
            return Some(candidate);
        }
    }
    None
}

/// The path that names `target` from a file in folder `from_dir`, with `/` separators.
/// Both are taken relative to the working directory when not absolute.
pub fn relative_path(from_dir: &Path, target: &Path) -> String {
    let abs = |p: &Path| {
        if p.is_absolute() {
            normalize(p)
        } else {
            normalize(
                &std::env::current_dir()
                    .unwrap_or_else(|_| PathBuf::from("/"))
                    .join(p),
            )
        }
    };
    let (from, to) = (abs(from_dir), abs(target));
    let f: Vec<Component> = from.components().collect();
    let t: Vec<Component> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    if common <= 1 {
        // Only the root in common: an absolute path says it best.
        return to.display().to_string();
    }
    let mut parts: Vec<String> = vec!["..".to_string(); f.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    parts.join("/")
}

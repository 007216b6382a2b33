//! Paths of composed configurations: the relative path one written file uses to name
//! another, time-stamped file names (thesis 4.4.1: the wizard names files itself), and a
//! [`FileSource`] that sees unsaved files over the disk so a composition is checked
//! before anything is written, and one that sees the configuration folder's files where
//! their copies will be ([`MirrorSource`]), so a composition's folder stands alone.

use std::io;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::config::source::{FileSource, FsSource, MemSource, normalize};

pub use crate::config::source::relative_path;

/// A time stamp for file names, `20261122_143005` (UTC).
pub fn timestamp_now() -> String {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    timestamp(secs)
}

/// The UTC time stamp of `secs` after the Unix epoch.
pub fn timestamp(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    // Howard Hinnant's civil-from-days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}{month:02}{day:02}_{:02}{:02}{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Unsaved files first, then the disk.
#[derive(Debug, Clone, Default)]
pub struct OverlaySource {
    /// The unsaved files, by path.
    pub unsaved: MemSource,
}

impl FileSource for OverlaySource {
    fn read(&self, path: &Path) -> io::Result<String> {
        match self.unsaved.read(path) {
            Ok(t) => Ok(t),
            Err(_) => FsSource.read(path),
        }
    }

    fn exists(&self, path: &Path) -> bool {
        self.unsaved.exists(path) || FsSource.exists(path)
    }

    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        if self.unsaved.exists(path) {
            self.unsaved.read_bytes(path)
        } else {
            FsSource.read_bytes(path)
        }
    }
}

/// A source that also shows the files of `from` as if they were in `at`: a composition
/// that copies the configuration folder's files it uses (parts, their sensors, a chosen
/// robot, a library mesh) into its own folder is checked with them there, and learns
/// which they are, before anything is written. A file really at a path is read from there;
/// else `at/REST` is the first of `from/REST`, `from/../REST`, ... that exists (the include
/// search from inside `from`).
pub struct MirrorSource<'a> {
    /// Where the files are read.
    pub base: &'a dyn FileSource,
    /// The folder the copies will be in.
    pub at: PathBuf,
    /// The folder they are copied from.
    pub from: PathBuf,
}

impl MirrorSource<'_> {
    /// `path` itself when it is there or not in `at`, else its original.
    fn found(&self, path: &Path) -> PathBuf {
        let norm = normalize(path);
        let rest = match norm.strip_prefix(normalize(&self.at)) {
            Ok(rest) if !self.base.exists(path) => rest,
            _ => return path.to_path_buf(),
        };
        self.from
            .ancestors()
            .map(|d| d.join(rest))
            .find(|p| self.base.exists(p))
            .unwrap_or_else(|| path.to_path_buf())
    }
}

impl FileSource for MirrorSource<'_> {
    fn read(&self, path: &Path) -> io::Result<String> {
        self.base.read(&self.found(path))
    }

    fn exists(&self, path: &Path) -> bool {
        self.base.exists(&self.found(path))
    }

    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.base.read_bytes(&self.found(path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_climb_and_descend() {
        assert_eq!(
            relative_path(
                Path::new("/a/configs/user"),
                Path::new("/a/configs/parts/PP.xml")
            ),
            "../parts/PP.xml"
        );
        assert_eq!(
            relative_path(Path::new("/a/configs"), Path::new("/a/configs/x.xml")),
            "x.xml"
        );
        assert_eq!(
            relative_path(Path::new("/a/b"), Path::new("/c/d.xml")),
            "/c/d.xml"
        );
    }

    #[test]
    fn timestamps_are_civil_utc() {
        assert_eq!(timestamp(0), "19700101_000000");
        // 2026-11-22 14:30:05 UTC
        assert_eq!(timestamp(1_795_357_805), "20261122_143005");
        assert_eq!(timestamp(951_782_400), "20000229_000000");
    }

    #[test]
    fn overlay_prefers_unsaved_files() {
        let mut o = OverlaySource::default();
        o.unsaved.insert("Cargo.toml", "unsaved");
        assert_eq!(o.read(Path::new("Cargo.toml")).unwrap(), "unsaved");
        assert!(o.read(Path::new("README.md")).is_ok());
        assert!(!o.exists(Path::new("no/such.file")));
    }
}

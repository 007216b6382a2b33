//! A configuration's files written into a folder of their own, so that it stands alone:
//! each file at its place relative to the deepest folder holding them all, so every
//! relative reference between them (a simulation naming its robot, a robot its parts, a
//! part its sensors) still resolves, and nothing in the folder names a file outside it.
//! Exports that travel (`results --export-robot`, `calibrate -o`) write through here.

use std::path::{Component, Path, PathBuf};

use crate::config::source::{normalize, text_as_binary};

/// A bundle that could not be written.
#[derive(Debug, thiserror::Error)]
pub enum BundleError {
    /// A file or folder could not be written.
    #[error("{}: cannot write: {source}", path.display())]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// Where the files of one configuration go in a folder of their own.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The deepest folder holding every file (lexically).
    root: PathBuf,
    /// The folder they go into.
    dir: PathBuf,
}

impl Layout {
    /// The layout of `paths` (as the loader read them) in `dir`.
    pub fn of<'a>(paths: impl IntoIterator<Item = &'a Path>, dir: &Path) -> Layout {
        let paths: Vec<PathBuf> = paths.into_iter().map(normalize).collect();
        Layout {
            root: common_folder(&paths),
            dir: dir.to_path_buf(),
        }
    }

    /// Where `path` (one of the layout's files) goes.
    pub fn place(&self, path: &Path) -> PathBuf {
        let path = normalize(path);
        self.dir
            .join(path.strip_prefix(&self.root).unwrap_or(&path))
    }
}

/// Writes `files` (path as read, text as a [`crate::config::FileSource`] holds it) into
/// `dir` in their own layout and returns it.
pub fn write_bundle(files: &[(String, String)], dir: &Path) -> Result<Layout, BundleError> {
    let layout = Layout::of(files.iter().map(|(p, _)| Path::new(p)), dir);
    for (path, text) in files {
        write_file(&layout.place(Path::new(path)), text)?;
    }
    Ok(layout)
}

/// Writes one file as a [`crate::config::FileSource`] holds it (a binary file, such as a
/// policy's weights, decoded back to its bytes), making its folder.
pub fn write_file(path: &Path, text: &str) -> Result<(), BundleError> {
    let failed = |p: &Path| {
        let path = p.to_path_buf();
        move |source| BundleError::Write { path, source }
    };
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(failed(parent))?;
    }
    let bytes = text_as_binary(text).map_err(failed(path))?;
    std::fs::write(path, bytes).map_err(failed(path))
}

/// The deepest folder holding every one of `paths` (lexically; empty for none).
fn common_folder(paths: &[PathBuf]) -> PathBuf {
    let mut common: Option<Vec<Component<'_>>> = None;
    for p in paths {
        let folder: Vec<Component<'_>> = p
            .parent()
            .map(|d| d.components().collect())
            .unwrap_or_default();
        common = Some(match common {
            None => folder,
            Some(c) => c
                .into_iter()
                .zip(folder)
                .take_while(|(a, b)| a == b)
                .map(|(a, _)| a)
                .collect(),
        });
    }
    common.unwrap_or_default().iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::source::binary_as_text;

    #[test]
    fn the_common_folder_is_the_deepest_that_holds_every_file() {
        let p = |s: &str| PathBuf::from(s);
        assert_eq!(
            common_folder(&[
                p("configs/a.simulation.xml"),
                p("configs/environments/flat.env.xml"),
                p("configs/parts/x.kinbody.xml"),
            ]),
            p("configs")
        );
        assert_eq!(common_folder(&[p("/w/c/a.xml"), p("/w/d/b.xml")]), p("/w"));
        assert_eq!(common_folder(&[p("a.xml")]), p(""));
    }

    #[test]
    fn a_bundle_keeps_the_layout_and_writes_binary_files_as_bytes() {
        let dir = std::env::temp_dir().join(format!("proleg-bundle-{}", std::process::id()));
        let weights = [0u8, 159, 146, 150, 255];
        let files = vec![
            ("w/configs/a.simulation.xml".to_string(), "<a/>".to_string()),
            (
                "w/configs/./parts/../policies/p.bin".to_string(),
                binary_as_text(&weights),
            ),
        ];
        let layout = write_bundle(&files, &dir).expect("written");
        assert_eq!(
            layout.place(Path::new("w/configs/policies/p.bin")),
            dir.join("policies/p.bin")
        );
        assert_eq!(
            std::fs::read(dir.join("policies/p.bin")).expect("read"),
            weights
        );
        assert_eq!(
            std::fs::read_to_string(dir.join("a.simulation.xml")).expect("read"),
            "<a/>"
        );
        std::fs::remove_dir_all(&dir).expect("removed");
    }
}

//! How a URDF is imported: what a robot without collision geometry gets, and where
//! `package://` meshes are looked for (the command line's `--package-path`).

use std::path::PathBuf;

/// How to import a URDF.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ImportOptions {
    /// Import a robot left without any collision geometry (with a warning) rather than
    /// refuse it.
    pub allow_no_collision: bool,
    /// Where `package://` meshes are looked for after the URDF's folder and those above
    /// it: folders holding packages (`ROS_PACKAGE_PATH`) or packages themselves.
    pub package_path: Vec<PathBuf>,
    /// Packages given by name (`--package-path NAME=DIR`): looked up first.
    pub packages: Vec<(String, PathBuf)>,
}

impl ImportOptions {
    /// The defaults with `ROS_PACKAGE_PATH`'s folders as the package path.
    pub fn from_env() -> Self {
        ImportOptions {
            allow_no_collision: false,
            package_path: std::env::var_os("ROS_PACKAGE_PATH")
                .map(|p| std::env::split_paths(&p).collect())
                .unwrap_or_default(),
            packages: Vec::new(),
        }
    }
}

/// A `--package-path` argument that is not `NAME=DIR`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("\"{0}\": give a package as NAME=DIR (the NAME of package://NAME/... and its folder)")]
pub struct PackageArgError(pub String);

/// A package named on the command line: `NAME=DIR`.
pub fn package_arg(arg: &str) -> Result<(String, PathBuf), PackageArgError> {
    match arg.split_once('=') {
        Some((name, dir)) if !name.is_empty() && !dir.is_empty() && !name.contains('/') => {
            Ok((name.to_string(), PathBuf::from(dir)))
        }
        _ => Err(PackageArgError(arg.to_string())),
    }
}

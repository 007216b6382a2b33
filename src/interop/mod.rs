//! Other robotics formats, converted to and from proleg's files: URDF robots in
//! ([`urdf`], `proleg import`), MuJoCo's MJCF out ([`mjcf`], `proleg export mjcf`).
//!
//! The URDF import reads and writes configuration models only ([`crate::config`]); the
//! MJCF export also takes the simulation's contact and servo constants ([`crate::sim`]) so
//! that MuJoCo models the same servos. Everything imported is checked by loading it like
//! any other file.

pub mod mjcf;
pub mod urdf;

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::config::transform::Pose;

/// A rigid transform as a proleg pose.
pub fn to_pose(t: &Isometry3<f64>) -> Pose {
    let q = t.rotation.quaternion();
    Pose {
        translation: [t.translation.x, t.translation.y, t.translation.z],
        rotation: [q.w, q.i, q.j, q.k],
    }
}

/// A proleg pose as a rigid transform.
pub fn to_isometry(p: &Pose) -> Isometry3<f64> {
    let [w, x, y, z] = p.rotation;
    let [tx, ty, tz] = p.translation;
    Isometry3::from_parts(
        Translation3::new(tx, ty, tz),
        UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
    )
}

/// A conversion that could not be done: the file and the cause.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {cause}", .file.display())]
pub struct InteropError {
    /// The file read or written.
    pub file: PathBuf,
    /// What went wrong.
    pub cause: String,
}

impl InteropError {
    /// An error about `file`.
    pub fn new(file: &Path, cause: impl Into<String>) -> Self {
        InteropError {
            file: file.to_path_buf(),
            cause: cause.into(),
        }
    }
}

/// Writes `text` to `path`, creating its folder.
pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), InteropError> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| InteropError::new(dir, format!("cannot create the folder: {e}")))?;
    }
    std::fs::write(path, text).map_err(|e| InteropError::new(path, format!("cannot write: {e}")))
}

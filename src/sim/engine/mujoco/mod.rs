//! The MuJoCo engine: MuJoCo 4.0.0's C library behind [`PhysicsEngine`](super::PhysicsEngine),
//! loaded at run time so that the program builds, and everything but this engine runs,
//! without it. Every MuJoCo type of the crate lives in this module.
//!
//! - [`ffi`]: the bindings bindgen generated from the 4.0.0 headers (`scripts/mujoco-bindgen`)
//! - [`library`]: finding, loading and checking the library; MuJoCo's error hooks
//! - [`mjcf`]: the one mapping of a simulation to MJCF (engine and export)
//! - [`engine`]: [`MujocoEngine`], the world built in memory from that mapping
//! - [`parts`]: our bodies in it (a static environment body is geoms of MuJoCo's world body)
//!
//! Where the library is: `PROLEG_MUJOCO` (the file, or a folder holding
//! `lib/libmujoco.so.4.0.0`), else `~/.local/share/proleg/mujoco/lib/libmujoco.so.4.0.0`,
//! where `scripts/demo` and `scripts/test` install it from the Python registry's
//! `mujoco-core==4.0.0` wheel.

mod engine;
#[allow(unsafe_code)]
pub mod ffi;
pub mod library;
pub mod mjcf;
mod models;
mod parts;

pub use engine::{MujocoEngine, check_mjcf_file};

/// The MuJoCo version the bindings were generated for.
pub const MUJOCO_VERSION: &str = "4.0.0";

/// How MuJoCo integrates one simulation step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MujocoSettings {
    /// MuJoCo steps per simulation step (its timestep is the step width divided by this);
    /// more than 1 only for converged references.
    pub steps_per_step: u32,
    /// Solver iterations (MuJoCo's default 100 when `None`).
    pub iterations: Option<u32>,
}

impl Default for MujocoSettings {
    /// Production: one MuJoCo step per simulation step, MuJoCo's defaults otherwise.
    fn default() -> Self {
        MujocoSettings {
            steps_per_step: 1,
            iterations: None,
        }
    }
}

impl MujocoSettings {
    /// The converged reference of the accuracy gate: a step `factor` times finer, the
    /// elliptic cone, twice the solver iterations.
    pub fn reference(factor: u32) -> Self {
        MujocoSettings {
            steps_per_step: factor.max(1),
            iterations: Some(200),
        }
    }
}

impl std::fmt::Display for MujocoSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "mujoco {MUJOCO_VERSION}: {} step(s) per step, {} solver iterations, implicitfast",
            self.steps_per_step,
            self.iterations.unwrap_or(100)
        )
    }
}

/// What goes wrong with MuJoCo: each says what to do in one line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MujocoError {
    /// No library where we look.
    #[error(
        "MuJoCo {MUJOCO_VERSION} is not installed ({path}): run `bash scripts/install-mujoco` (a checkout or the release tarball), `pip install 'proleg[mujoco]'` (Python), or set PROLEG_MUJOCO to libmujoco.so.{MUJOCO_VERSION}"
    )]
    Missing {
        /// Where we looked.
        path: String,
    },
    /// A file that does not load as MuJoCo's library.
    #[error("{path} is not MuJoCo {MUJOCO_VERSION}'s library: {cause}")]
    NotMujoco {
        /// The file.
        path: String,
        /// What the loader said.
        cause: String,
    },
    /// A library of another version.
    #[error(
        "{path} is MuJoCo {found}, proleg needs {MUJOCO_VERSION}: run `bash scripts/install-mujoco` (or set PROLEG_MUJOCO)"
    )]
    WrongVersion {
        /// The file.
        path: String,
        /// The version it reports.
        found: String,
    },
    /// A setting of the configuration MuJoCo has no counterpart for.
    #[error("MuJoCo cannot simulate this: {0}")]
    Unsupported(String),
    /// A model MuJoCo refuses.
    #[error("MuJoCo rejects the model of {file}: {cause}")]
    Rejected {
        /// The simulation file.
        file: String,
        /// MuJoCo's message.
        cause: String,
    },
    /// A mesh or height field that cannot be mapped.
    #[error("{file}: cannot map the mesh to MuJoCo: {cause}")]
    Mesh {
        /// The mesh file.
        file: String,
        /// What is wrong.
        cause: String,
    },
    /// A robot that is not a tree of links.
    #[error("{file}: MJCF needs a tree of links: {cause}")]
    NotATree {
        /// The robot file.
        file: String,
        /// What is wrong.
        cause: String,
    },
    /// An error MuJoCo raised through its error hook.
    #[error("MuJoCo: {0}")]
    Library(String),
}

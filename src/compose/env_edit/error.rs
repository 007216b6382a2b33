//! Why an edit of the environment editor was refused, or its file not read or written.

use std::path::PathBuf;

use crate::config::ConfigError;

/// An edit refused, with its reason; or a scene file that cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum EditError {
    /// An edit that needs a selection, without one.
    #[error("select an object or the robot first")]
    NoSelection,
    /// An object index beyond the scene's objects.
    #[error("no object {index}; the scene has {count}")]
    NoObject {
        /// The index given.
        index: usize,
        /// Objects in the scene.
        count: usize,
    },
    /// A position or angle that is not a finite number.
    #[error("{what} {value} is not finite")]
    NotFinite {
        /// "position" or "angle".
        what: &'static str,
        /// The value as given.
        value: String,
    },
    /// What the robot placeholder cannot do (it only moves and turns).
    #[error("{0}")]
    Robot(&'static str),
    /// An included kinbody file, whose contents are edited in that file.
    #[error("{file} is an included file: it moves and turns here, edit its contents in that file")]
    Included {
        /// The file as the scene names it.
        file: String,
    },
    /// A generated terrain, whose bodies come from its family, difficulty and seed.
    #[error(
        "{label} is a generated terrain: it moves and turns here; change its difficulty or seed, or write it out with `proleg terrain` to edit its bodies"
    )]
    Generated {
        /// The terrain's short name.
        label: String,
    },
    /// A terrain edit with something else selected.
    #[error("select a generated terrain first")]
    NotTerrain,
    /// A terrain difficulty or size the generator refuses.
    #[error("{0}")]
    Terrain(#[source] crate::config::terrain::TerrainError),
    /// Scale factors outside 0..1000.
    #[error("scale factors {0:?} must lie in 0..1000")]
    Scale([f64; 3]),
    /// A friction outside the editor's range.
    #[error("friction {0} is outside 0..{max} (Coulomb coefficient)", max = super::EDITOR_MAX_FRICTION)]
    Friction(f64),
    /// A mass that is not positive (or beyond 1e6 kg).
    #[error("mass {0} kg must be positive (at most 1e6)")]
    Mass(f64),
    /// A colour part outside 0..1.
    #[error("colour {0:?}: each part lies in 0..1")]
    Colour([f64; 3]),
    /// A name the files cannot hold.
    #[error("{0}")]
    Name(#[source] crate::config::robot_builder::BuildError),
    /// A scene file that cannot be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A scene file that does not parse, or a scene that does not make a valid file (its
    /// meshes or included files not found, values out of range).
    #[error("{0}")]
    Invalid(#[from] ConfigError),
}

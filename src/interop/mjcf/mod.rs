//! MuJoCo export (`proleg export mjcf`): a loaded simulation as one MJCF document, for a
//! cross-engine check of a gait or to carry a robot into MuJoCo-based tools. The mapping is
//! the MuJoCo engine's own ([`crate::sim::engine::mjcf_export`]); an export differs only in
//! its servos, written as `<position>` actuators that approximate proleg's servo without
//! proleg's servo stage.

use std::path::Path;

use crate::config::Simulation;
use crate::interop::{InteropError, write_text};
use crate::sim::engine::{mjcf_check, mjcf_export};

/// What an export wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfExport {
    /// Bodies (environment and robot links) written.
    pub bodies: usize,
    /// Hinges (and position actuators) written.
    pub joints: usize,
    /// Mesh and height-field assets written.
    pub assets: usize,
    /// Where MuJoCo will differ by construction, one line each.
    pub notes: Vec<String>,
    /// MuJoCo loaded the file written (false: its library is not installed, not checked).
    pub loaded_by_mujoco: bool,
}

/// Writes `sim` as MJCF to `out` and, where MuJoCo's library is installed, loads it there:
/// a file MuJoCo refuses is an error with MuJoCo's message.
pub fn export_mjcf(sim: &Simulation, out: &Path) -> Result<MjcfExport, InteropError> {
    let doc = mjcf_export(sim).map_err(|e| InteropError::new(&sim.file, e.to_string()))?;
    write_text(out, &doc.xml)?;
    let loaded_by_mujoco = mjcf_check(out).map_err(|e| InteropError::new(out, e.to_string()))?;
    Ok(MjcfExport {
        bodies: doc.bodies,
        joints: doc.joints,
        assets: doc.assets,
        notes: doc.notes,
        loaded_by_mujoco,
    })
}

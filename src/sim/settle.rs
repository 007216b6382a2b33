//! Whether a robot comes to rest on its floor (`proleg settle`): the physical check of an
//! imported robot. Its servos hold the start pose (each joint at 0 deg, or the nearest
//! limit) for a while; then the lowest point of its moving links' geometry must lie within
//! [`SETTLE_TOLERANCE`] of the floor: neither through it (no collision geometry, a
//! blow-up) nor above it (a link that became an anchor and holds the robot in the air).
//! The same check on both engines: it reads only the links' poses from the engine, and the
//! geometry's exact lowest point ([`lowest_z`]) from the configuration.

use std::fmt;

use crate::config::Simulation;
use crate::config::body::{BodyKind, Geom, Shape, highest_z, lowest_z};
use crate::config::mesh::TriMesh;
use crate::control::ModuleRegistry;
use crate::sim::error::SimError;
use crate::sim::{BuildOptions, Simulator};

/// How long (s) `proleg import` lets what it imported settle.
pub const IMPORT_SETTLE_SECONDS: f64 = 2.0;

/// How far (m) the robot's lowest point may be from the floor once settled.
pub const SETTLE_TOLERANCE: f64 = 0.01;

/// The largest link speed (m/s) of a robot at rest.
pub const REST_SPEED: f64 = 0.05;

/// What a settle run found.
#[derive(Debug, Clone, PartialEq)]
pub struct SettleReport {
    /// Simulated seconds.
    pub seconds: f64,
    /// Height (m) of the floor: the top of the environment's static bodies.
    pub floor: f64,
    /// Height (m) of the lowest point of the moving links' geometry at the end.
    pub lowest: f64,
    /// The link holding the lowest point.
    pub lowest_link: String,
    /// Largest speed (m/s) of a link at the end.
    pub max_speed: f64,
    /// The link moving fastest at the end.
    pub fastest_link: String,
}

impl SettleReport {
    /// The lowest point within [`SETTLE_TOLERANCE`] of the floor.
    pub fn settled(&self) -> bool {
        (self.lowest - self.floor).abs() <= SETTLE_TOLERANCE
    }

    /// Settled, and no link faster than [`REST_SPEED`]: the robot came to rest rather than
    /// touching the floor by chance while it shakes or tumbles.
    pub fn at_rest(&self) -> bool {
        self.settled() && self.max_speed <= REST_SPEED
    }
}

impl fmt::Display for SettleReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let gap = self.lowest - self.floor;
        let verdict = if self.at_rest() {
            "settled"
        } else if self.settled() {
            "settled (still moving)"
        } else if !gap.is_finite() {
            "NOT settled: the simulation diverged"
        } else if gap < 0.0 {
            "NOT settled: it sank through the floor"
        } else {
            "NOT settled: it hangs above the floor"
        };
        write!(
            f,
            "{verdict} after {:.2} s with joints held: lowest point {:+.4} m from the floor (link {}; tolerance {SETTLE_TOLERANCE} m), fastest link {} at {:.3} m/s",
            self.seconds, gap, self.lowest_link, self.fastest_link, self.max_speed
        )
    }
}

/// Runs `sim` for `seconds` with its servos holding the start pose and measures where the
/// robot came to rest.
pub fn settle(
    sim: &Simulation,
    seconds: f64,
    opts: &BuildOptions,
    registry: &ModuleRegistry,
) -> Result<SettleReport, SimError> {
    let mut s = Simulator::with_registry(sim, opts, registry)?;
    let hold = sim
        .robot
        .joints
        .iter()
        .map(|j| 0.0_f64.clamp(j.limits_deg[0], j.limits_deg[1]))
        .collect();
    s.set_joint_override(0, Some(hold))?;
    let floor = floor_height(sim);
    let dt = sim.files.simulation.properties.step_width;
    let steps = (seconds / dt).round().max(1.0) as u64;
    s.run_steps(steps);
    let mut lowest = f64::INFINITY;
    let mut lowest_link = String::new();
    let mut max_speed = 0.0_f64;
    let mut fastest_link = String::new();
    for (b, link) in s.robot_bodies(0)?.into_iter().zip(&sim.robot.links) {
        let Some(state) = s.body_state(b) else {
            continue;
        };
        let v = state.linvel;
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if speed >= max_speed {
            max_speed = speed;
            fastest_link.clone_from(&link.name);
        }
        for g in &link.geoms {
            let z = lowest_z(&state.pose.mul(&g.pose), g, mesh_of(sim, g));
            if z < lowest {
                lowest = z;
                lowest_link.clone_from(&link.name);
            }
        }
    }
    let sound = lowest.is_finite() && !s.diverged();
    Ok(SettleReport {
        seconds: steps as f64 * dt,
        floor,
        lowest: if sound { lowest } else { f64::NAN },
        lowest_link,
        max_speed,
        fastest_link,
    })
}

/// The top (m) of the environment's static bodies (0 without any): the floor an imported
/// robot stands on.
pub fn floor_height(sim: &Simulation) -> f64 {
    let top = sim
        .environment
        .bodies
        .iter()
        .filter(|b| b.kind == BodyKind::Static)
        .flat_map(|b| b.geoms.iter().map(move |g| (b, g)))
        .map(|(b, g)| highest_z(&b.pose.mul(&g.pose), g, mesh_of(sim, g)))
        .fold(f64::NEG_INFINITY, f64::max);
    if top.is_finite() { top } else { 0.0 }
}

/// The loaded mesh of a trimesh geometry of `sim`.
fn mesh_of<'a>(sim: &'a Simulation, g: &Geom) -> Option<&'a TriMesh> {
    match &g.shape {
        Shape::Trimesh { file, .. } => sim.mesh(file).map(|m| &**m),
        _ => None,
    }
}

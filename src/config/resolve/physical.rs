//! A robot's physical validation: every link must be a body some rigid body can be, the
//! same rules for both engines, every fault of a file reported with its place.
//!
//! | Rule | Why |
//! |---|---|
//! | a moving link has geometry or a `<Mass>` | without either it has no mass and no inertia: rapier holds it in place (an anchor), MuJoCo refuses it |
//! | a `<Mass>` without geometry gives `<inertia>` | there is nothing to spread the mass over; without inertia the link cannot turn |
//! | `<inertia>` is positive definite and satisfies A + B >= C ([`inertia_fault`]) | no mass distribution has another tensor |
//! | a static link is the root of the tree | a fixed base; a hinge cannot move a link fixed to the world |
//! | the robot has some geometry | it would fall through every floor |

use crate::config::body::{BodyKind, inertia_fault};
use crate::config::error::{ConfigError, ErrorKind};
use crate::config::resolve::flatten::{PlacedBody, PlacedJoint};
use crate::config::robot::RobotFile;

/// Every physical fault of a robot's bodies (with the joints naming them), located; empty
/// when the robot is physical.
pub fn robot_faults(
    file: &std::path::Path,
    robot: &RobotFile,
    bodies: &[PlacedBody],
    joints: &[PlacedJoint],
) -> Vec<ConfigError> {
    let mut faults = Vec::new();
    for pb in bodies {
        let b = &pb.body;
        let fault =
            |pos, message: String| ConfigError::new(&pb.file, pos, ErrorKind::OutOfRange, message);
        let dynamic = b.kind == BodyKind::Dynamic;
        match &b.mass {
            _ if !dynamic => {}
            None if b.geoms.is_empty() => faults.push(fault(
                b.pos,
                format!(
                    "body {} has no geometry and no <Mass>: nothing gives it mass or inertia (an engine would hold it in place); give it a <Mass> with <inertia>",
                    b.name
                ),
            )),
            Some(m) if b.geoms.is_empty() && m.inertia.is_none() => faults.push(fault(
                m.pos,
                format!(
                    "body {}: its <Mass> has no <inertia> and the body no geometry to spread the mass over, so it could not turn; give its <inertia>",
                    b.name
                ),
            )),
            Some(m) => {
                if let Some(why) = m.inertia.as_ref().and_then(inertia_fault) {
                    faults.push(fault(m.pos, format!("body {}: <inertia>: {why}", b.name)));
                }
            }
            None => {}
        }
        if !dynamic && let Some(pj) = joints.iter().find(|pj| pj.joint.bodies[1] == b.name) {
            faults.push(fault(
                b.pos,
                format!(
                    "body {} is static (fixed to the world), yet joint {} moves it: only the root of a robot can be its fixed base",
                    b.name, pj.joint.name
                ),
            ));
        }
    }
    if bodies.iter().all(|pb| pb.body.geoms.is_empty()) {
        faults.push(ConfigError::new(
            file,
            robot.pos,
            ErrorKind::Missing,
            "the robot has no geometry: nothing of it collides, and it would fall through every floor",
        ));
    }
    faults
}

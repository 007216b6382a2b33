//! Body sensing: each step, before the kernels run, every robot's centre of mass, heading,
//! gravity in its head's frame and joint speeds go into its [`RobotSensors`], so sensing
//! modules can tell progress from being stuck and policies see how the body moves.

use bevy::prelude::*;

use crate::sim::physics::SimPhysics;
use crate::sim::record::{centre_of_mass, gravity_in_head, heading};
use crate::sim::robot::SimRobot;
use crate::sim::servo::JointState;
use crate::sim::tactile::RobotSensors;

/// Updates each robot's sensed body state (part of the `Sense` set, after the joints').
pub fn sense_position(
    physics: Res<SimPhysics>,
    mut robots: Query<(&SimRobot, &mut RobotSensors)>,
    states: Query<&JointState>,
) {
    let engine = physics.engine.as_ref();
    for (robot, mut sensors) in &mut robots {
        let s = &mut sensors.0;
        s.position = centre_of_mass(engine, robot);
        s.heading = heading(engine, robot);
        s.gravity_head = gravity_in_head(engine, robot);
        for (slot, e) in s.joint_speeds.iter_mut().zip(&robot.joints) {
            *slot = states.get(*e).map_or(0.0, |j| j.velocity);
        }
    }
}

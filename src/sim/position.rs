//! Position sensing: each step, before the kernels run, every robot's centre of mass goes
//! into its [`RobotSensors`] so sensing modules can tell progress from being stuck.

use bevy::prelude::*;

use crate::sim::physics::SimPhysics;
use crate::sim::record::centre_of_mass;
use crate::sim::robot::SimRobot;
use crate::sim::tactile::RobotSensors;

/// Updates each robot's sensed position (part of the `Sense` set).
pub fn sense_position(physics: Res<SimPhysics>, mut robots: Query<(&SimRobot, &mut RobotSensors)>) {
    for (robot, mut sensors) in &mut robots {
        sensors.0.position = centre_of_mass(physics.engine.as_ref(), robot);
    }
}

//! What the servos spend: each robot's mechanical power (Σ |torque · joint speed|) and the
//! energy it adds up to, accumulated every step in the `Record` stage. The cost-of-transport
//! fitness and the data logger's `power` / `energy` series read it from here.

use bevy::prelude::*;

use crate::sim::clock::SimClock;
use crate::sim::robot::SimRobot;
use crate::sim::servo::JointState;

/// A robot's mechanical power and energy so far.
#[derive(Component, Debug, Clone, Copy, Default, PartialEq)]
pub struct Energy {
    /// Power the servos put out in the last step (W).
    pub power: f64,
    /// Energy the servos put out since the start (J).
    pub joules: f64,
}

/// Adds each robot's step of power to its energy (first in the `Record` stage).
pub fn accumulate_energy(
    clock: Res<SimClock>,
    mut robots: Query<(&SimRobot, &mut Energy)>,
    states: Query<&JointState>,
) {
    for (robot, mut energy) in &mut robots {
        let mut power = 0.0;
        for e in &robot.joints {
            if let Ok(s) = states.get(*e) {
                power += (s.torque * s.velocity.to_radians()).abs();
            }
        }
        energy.power = power;
        energy.joules += power * clock.dt;
    }
}

//! Planar laser range finders (OpenRAVE BaseLaser2D, thesis listing B.4): every scan time
//! each beam is cast as a ray from the sensor against everything the robot can collide
//! with (not its own link) and the range to the first hit — or the maximum range — is
//! stored. Beams lie in the sensor's x-y plane; angle 0 looks along the sensor's +y axis
//! (forward along the chain in the ready robots), positive angles turn towards -x.

use bevy::prelude::*;

use crate::sim::clock::SimClock;
use crate::sim::engine::LaserId;
use crate::sim::physics::SimPhysics;
use crate::sim::randomize::NoisySensors;
use crate::sim::tactile::RobotSensors;

/// A laser of a robot: its engine laser and scan period.
#[derive(Component, Debug, Clone)]
pub struct Laser2dSensor {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's lasers (the order of `SensorData::laser`).
    pub index: usize,
    /// The engine's laser.
    pub laser: LaserId,
    /// Range (m), for the noise model.
    pub max_range: f64,
    /// Scan period in steps.
    pub period: u64,
}

/// Casts every laser whose scan is due (part of the `Sense` set).
pub fn scan_lasers(
    physics: Res<SimPhysics>,
    clock: Res<SimClock>,
    lasers: Query<&Laser2dSensor>,
    mut robots: Query<(&mut RobotSensors, Option<&mut NoisySensors>)>,
) {
    for laser in &lasers {
        if !clock.step.is_multiple_of(laser.period.max(1)) {
            continue;
        }
        let Ok((mut sensors, noise)) = robots.get_mut(laser.robot) else {
            continue;
        };
        let Some(ranges) = sensors.0.laser.get_mut(laser.index) else {
            continue;
        };
        physics.engine.scan(laser.laser, ranges);
        if let Some(mut n) = noise {
            n.perturb_ranges(ranges, laser.max_range);
        }
    }
}

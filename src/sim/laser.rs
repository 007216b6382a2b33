//! Planar laser range finders (OpenRAVE BaseLaser2D, thesis listing B.4): every scan time
//! each beam is cast as a ray from the sensor against everything the robot can collide
//! with (not its own link) and the range to the first hit — or the maximum range — is
//! stored. Beams lie in the sensor's x-y plane; angle 0 looks along the sensor's +y axis
//! (forward along the chain in the ready robots), positive angles turn towards -x.

use bevy::prelude::*;
use rapier3d::prelude as rp;

use crate::config::sensor::Laser2d;
use crate::sim::clock::SimClock;
use crate::sim::physics::SimPhysics;
use crate::sim::randomize::NoisySensors;
use crate::sim::tactile::RobotSensors;

/// One laser.
#[derive(Component, Debug, Clone)]
pub struct Laser2dSensor {
    /// The robot it belongs to.
    pub robot: Entity,
    /// Index among the robot's lasers.
    pub index: usize,
    /// The link it is mounted on and its pose there.
    pub body: rp::RigidBodyHandle,
    /// Pose of the sensor on its link.
    pub pose: rp::Pose,
    /// Beam angles (radians).
    pub angles: Vec<f64>,
    /// Range reported when a beam hits nothing (m).
    pub max_range: f64,
    /// Steps between scans.
    pub period: u64,
    /// What the rays can hit (the robot's own collision filter).
    pub groups: rp::InteractionGroups,
}

/// Beam angles (degrees) from `min` to `max` every `resolution` degrees.
pub fn beam_angles(l: &Laser2d) -> Vec<f64> {
    let n = ((l.max_angle - l.min_angle) / l.resolution + 1e-9).floor() as usize + 1;
    (0..n)
        .map(|i| l.min_angle + i as f64 * l.resolution)
        .collect()
}

/// Scans every laser whose period has come (part of the `Sense` set).
pub fn scan_lasers(
    physics: Res<SimPhysics>,
    clock: Res<SimClock>,
    lasers: Query<&Laser2dSensor>,
    mut robots: Query<(&mut RobotSensors, Option<&mut NoisySensors>)>,
) {
    let w = &physics.world;
    for laser in &lasers {
        if !clock.step.is_multiple_of(laser.period.max(1)) {
            continue;
        }
        let (Some(body), Ok((mut sensors, noise))) =
            (w.bodies.get(laser.body), robots.get_mut(laser.robot))
        else {
            continue;
        };
        let Some(ranges) = sensors.0.laser.get_mut(laser.index) else {
            continue;
        };
        let at = body.position() * laser.pose;
        let filter = rp::QueryFilter::default()
            .groups(laser.groups)
            .exclude_rigid_body(laser.body);
        for (range, a) in ranges.iter_mut().zip(&laser.angles) {
            let local = rp::Vector::new(-(a.sin() as f32), a.cos() as f32, 0.0);
            let ray = rp::Ray::new(at.translation, at.rotation * local);
            *range = w
                .cast_ray(&ray, laser.max_range as f32, true, filter)
                .map_or(laser.max_range, |(_, toi)| toi as f64);
        }
        if let Some(mut n) = noise {
            n.perturb_ranges(ranges, laser.max_range);
        }
    }
}
